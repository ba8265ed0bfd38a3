"""The hemisphere forming case (validation/cases/hemisphere_forming.py): its observed orders
over three meshes, the cells it compares with the net, its holder, its coarse blank formed to
the end against the net, and its figures sized for a report page."""

import math
from types import SimpleNamespace

import numpy as np
import pytest

from solvers.quasi_static import KINETIC_BOUND
from validation.cases import hemisphere_forming as case


def fake_run(cells: int, value: float) -> dict:
    """A ``run`` record of ``cells`` whose three measured quantities are ``value``."""
    return {
        "cells": cells,
        "result": SimpleNamespace(converged=True),
        **{key: value for key in case.ORDER_QUANTITIES},
    }


def test_the_orders_recover_a_second_order_sequence_over_the_three_meshes():
    """f(h) = 3 + 0.01 h^2 on the blank's meshes h = 200 / n: order 2, extrapolated 3."""
    runs = [fake_run(n, 3.0 + 0.01 * (200.0 / n) ** 2) for n in (12, 20, 32)]
    records = case.orders({"fibrous": runs})
    assert len(records) == len(case.ORDER_QUANTITIES)
    for record in records:
        assert record.cells == (12, 20, 32)
        assert record.sizes == pytest.approx((200 / 12, 10.0, 6.25))
        assert record.order == pytest.approx(2.0, rel=1e-9)
        assert record.extrapolated == pytest.approx(3.0, rel=1e-9)


def test_an_oscillating_sequence_has_no_order_and_fails_its_checks(monkeypatch):
    runs = [fake_run(n, v) for n, v in zip((12, 20, 32), (3.0, 2.0, 2.5))]
    records = case.orders({"fibrous": runs})
    assert all(math.isnan(record.order) for record in records)
    monkeypatch.setattr(case, "ORDER_TOLERANCE", {"fibrous draw_in_mm": 0.05})
    verdicts = case.order_checks(records)
    assert len(verdicts) == 1  # the draw-in's
    assert not any(verdict.passed for verdict in verdicts)


def test_a_quantity_named_for_an_order_check_is_checked_whatever_its_limit(monkeypatch):
    """With the rms named in ORDER_TOLERANCE (0.1): rms = e0 + 0.001 h^2 on the three meshes (h
    = 200 / n mm), the finest mesh within 7 % of the Richardson value e0, passes for a limit
    of 0.5 deg as for 2.5 (a limit is the shell's departure from the net, not bounded); rms =
    0.5 + 0.05 h, the finest 38 % off its limit, fails."""
    monkeypatch.setattr(case, "ORDER_TOLERANCE", {"fibrous rms_deg": 0.1})
    for limit, slope, power, passes in ((0.5, 0.001, 2, True), (2.5, 0.001, 2, True),
                                        (0.5, 0.05, 1, False)):  # fmt: skip
        runs = [fake_run(n, limit + slope * (200.0 / n) ** power) for n in (12, 20, 32)]
        verdicts = case.order_checks(case.orders({"fibrous": runs}))
        rms = [verdict for verdict in verdicts if "rms" in verdict.name]
        assert len(rms) == 1 and rms[0].passed is passes


def test_the_rms_error_is_reported_not_checked_for_an_order_it_does_not_show():
    """The fibrous rms error against the net on 16 / 24 / 36 cells (the case's defaults,
    unscaled; docs/hemisphere_forming.md): 2.207 / 1.517 / 1.920 deg, not monotone, no order;
    on 12 / 20 / 32, 2.730 / 2.140 / 2.136, an order (9.7) past ORDER_RANGE: no order either.
    So no order check names it."""
    for cells, sequence in (((16, 24, 36), (2.2068, 1.5170, 1.9201)),
                            ((12, 20, 32), (2.7300, 2.1400, 2.1360))):  # fmt: skip
        runs = [fake_run(n, value) for n, value in zip(cells, sequence)]
        rms = next(r for r in case.orders({"fibrous": runs}) if "rms" in r.quantity)
        assert math.isnan(rms.order)
    assert "fibrous rms_deg" not in case.ORDER_TOLERANCE


def test_the_integral_draw_ins_and_the_late_punch_force_are_reported_with_their_orders():
    """The fibrous runs at 12 / 20 / 32 and 16 / 24 / 36 cells (the case's defaults,
    unscaled; docs/hemisphere_forming.md): the draw-in averaged along the edges has order 7.4
    on the first triple and 1.1 on the second (13.18 at 20 cells above 13.04 at 24), the
    corners' 4.55 and none, the late punch force 0.6 and 2.8: no clear order, so each gets an
    order record and no check (ORDER_TOLERANCE names none of them), as the edge middle's
    draw-in (22.61 / 28.57 / 24.51 mm, one node in one of two states: no order)."""
    measured = {
        (12, 20, 32): {
            "edge_draw_in_mm": (11.4369, 13.1780, 13.2183),
            "corner_draw_in_mm": (4.5559, 7.3275, 7.5926),
            "late_punch_force_N": (40.7584, 48.5174, 53.8236),
            "draw_in_mm": (22.6074, 28.5702, 24.5051),
        },
        (16, 24, 36): {
            "edge_draw_in_mm": (12.5226, 13.0439, 13.3768),
            "corner_draw_in_mm": (5.9850, 6.5413, 7.8193),
            "late_punch_force_N": (46.0480, 52.0766, 54.0324),
            "draw_in_mm": (25.6195, 24.4869, 24.6485),
        },
    }
    expected = {
        (12, 20, 32): {"edge_draw_in_mm": 7.35, "corner_draw_in_mm": 4.55,
                       "late_punch_force_N": 0.60, "draw_in_mm": math.nan},
        (16, 24, 36): {"edge_draw_in_mm": 1.11, "corner_draw_in_mm": -2.05,
                       "late_punch_force_N": 2.78, "draw_in_mm": math.nan},
    }  # fmt: skip
    for cells, values in measured.items():
        runs = [fake_run(n, 2.0) for n in cells]
        for key, sequence in values.items():
            for run, value in zip(runs, sequence):
                run[key] = value
        records = {r.quantity: r for r in case.orders({"fibrous": runs})}
        for key, order in expected[cells].items():
            record = records[case.ORDER_QUANTITIES[key]]
            if math.isnan(order):
                assert math.isnan(record.order)
            else:
                assert record.order == pytest.approx(order, abs=0.01)
        named = [c.name for c in case.order_checks(list(records.values()))]
        assert not any(case.ORDER_QUANTITIES[key] in name for key in values for name in named)


@pytest.mark.parametrize("cells", [12, 20, 32])
def test_the_compared_cells_are_one_material_region_inside_the_rim_on_every_mesh(cells):
    """The cells compared with the net are chosen by the net alone: those it lays at least
    one coarse cell (RIM_MARGIN of arc) inside the die's rim, 28 % of the blank on every mesh
    (the area of the region, to a row of cells), as much in each quadrant."""
    from femcore import Mesh

    mesh = Mesh.rectangle(200.0, 200.0, nx=cells, ny=cells, origin=(-100.0, -100.0, 0.0))
    compared = case.compared_cells(mesh)
    assert case.RIM_MARGIN == pytest.approx(200.0 / 12)
    assert math.degrees(case.COMPARED_POLAR) == pytest.approx(71.07, abs=0.01)
    assert compared.mean() == pytest.approx(0.28, abs=0.01)
    centres = mesh.points[mesh.triangles].mean(axis=1)[:, :2]
    quadrants = [np.sum(compared & (sx * centres[:, 0] > 0) & (sy * centres[:, 1] > 0))
                 for sx in (-1, 1) for sy in (-1, 1)]  # fmt: skip
    assert max(quadrants) - min(quadrants) <= cells // 4  # a quarter row of cells
    # Where the net lays the region's cells: at most COMPARED_POLAR from the bowl's bottom.
    net = case._net()
    radius = case.DIE - 0.5 * case.THICKNESS
    on = case._at_cells(mesh, net["points"][..., 2])[compared]
    assert np.all(np.arccos(on / radius) <= case.COMPARED_POLAR + 1e-12)


@pytest.mark.parametrize("ring", [False, True])
def test_the_holder_is_on_the_flange_free_along_z_and_pressed_by_its_force(ring):
    """A plane over the whole blank or a ring whose bore is the flange's start."""
    from elements import RigidAnnulus, RigidPlane

    _, held = case.model(4, "fibrous", rim=case.DIE_RIM, ring=ring)
    die, punch, holder = (interaction.tool for interaction in held.interactions)
    assert type(holder) is (RigidAnnulus if ring else RigidPlane)
    assert holder.free_names == ("z",)
    assert np.allclose(holder.force, [0.0, 0.0, -case.HOLDER_FORCE])
    assert np.allclose(holder.point, [0.0, 0.0, case.THICKNESS])
    assert np.allclose(holder.normal, [0.0, 0.0, -1.0])
    if ring:
        assert holder.inner == pytest.approx(case.flange_start(case.DIE_RIM), rel=1e-15)
    assert float(case.holder_closing(case.HOLDER_CLOSING)) == 1.0
    _, unheld = case.model(4, "fibrous", holder_force=0.0)
    assert len(unheld.interactions) == 2


@pytest.mark.parametrize("rim", [0.0, 5.0, 10.0])
def test_the_ring_holder_presses_the_flat_flange_and_leaves_the_die_round_free(rim):
    """A ring holder (``model(ring=True)``) rests on the die's flat flange, from sqrt(R^2 +
    2 R r) out (closed form, the round's end), not over the die's opening. Over the flange a
    blank lying flat touches it (its distance h / 2, the contact offset); a blank lying on the
    round, its mid-surface h / 2 off the die's torus, and the blank standing over the round at
    the flange's level (a node 3 mm inside the flange's start, 0.23 mm up: the 20-cell run
    under the plane) are out of its reach (distance > h / 2): a plane pressed them down."""
    _, held = case.model(4, "fibrous", rim=rim, ring=True)
    holder = held.interactions[-1].tool
    h = case.THICKNESS
    start = math.sqrt(case.DIE**2 + 2.0 * case.DIE * rim)
    d, _ = holder.distance(np.array([[start + 1.0, 0.0, 0.5 * h], [0.0, start + 20.0, 0.5 * h]]))
    assert d == pytest.approx([0.5 * h, 0.5 * h], abs=1e-12)
    turn = np.linspace(0.0, 0.5 * np.pi - math.atan2(rim, start), 50)  # from the flange down
    # the round's points (r, z) on the mid-surface: the torus's tube radius rim + h / 2
    radial = start - (rim + 0.5 * h) * np.sin(turn)
    height = -rim + (rim + 0.5 * h) * np.cos(turn)
    on_round = np.column_stack([radial, np.zeros_like(radial), height])[1:]
    standing = np.array([[start - 3.0, 0.0, 0.23]])
    d, _ = holder.distance(np.vstack([on_round, standing]))
    assert np.all(d > 0.5 * h)


@pytest.mark.slow
def test_the_coarse_blank_forms_to_the_end_under_its_holder_along_the_net_quasi_statically(
    coarse_report,
):
    """12 x 12 cells, fibrous, the holder at HOLDER_FORCE, the die's 10-mm entry radius, the
    stroke time-scaled x2 (TIME_SCALING), 8279 steps (6 s of CPU at load 17), read from the
    coarse report's run of the case (tests/conftest.py: the suite runs the blank once).
    Measured: the rms shear error against the net 2.73 deg (2.74 unscaled); the kinetic
    energy at most 0.033 of the work after the first tenth (0.009 unscaled), 0.0007 at the
    end; the holder does not rise (its flange stays flat); the damping dissipates 0.34 % of
    the work (0.25 % unscaled)."""
    _, report = coarse_report
    run = report["cases"][case.NAME]
    assert run["converged"]
    values = run["parameters"]
    assert values["cells"].startswith("12 x 12")
    assert values["fibrous_rms_shear_error_deg"] < case.RMS_TOLERANCE_DEG["coarse"]
    assert values["fibrous_largest_kinetic_over_work"] < KINETIC_BOUND
    assert values["fibrous_share_above_kinetic_bound"] == 0.0
    assert values["fibrous_reached_s"] == pytest.approx(
        case.DURATION / case.TIME_SCALING["fibrous"]["coarse"]
    )
    assert values["fibrous_final_kinetic_over_work"] < 0.5 * KINETIC_BOUND
    assert values["fibrous_largest_holder_lift_mm"] < 0.5 * case.THICKNESS
    assert 0.0 < values["fibrous_damping_over_work"] < 0.15


def flat_run(cells, kinematics, net=None, time_scaling=1.0):
    """A run's record standing in for ``case.run``: a flat blank whose numbers are
    f = f0 + C h^p, h the cell size (mm), reaching the end of its stroke in DURATION /
    ``time_scaling``; the scaling it was given in its ``scaling``."""
    from femcore import Mesh

    mesh = Mesh.rectangle(200.0, 200.0, nx=cells, ny=cells, origin=(-100.0, -100.0, 0.0))
    h = 200.0 / cells
    result = SimpleNamespace(
        converged=True,
        positions=mesh.points,
        steps=10,
        wall_time=1.0,
    )
    return {
        "cells": cells,
        "mesh": mesh,
        "result": result,
        "shear": np.zeros(len(mesh.triangles)),
        "compared": np.zeros(len(mesh.triangles), dtype=bool),
        "on_bowl": 0,
        "rms_deg": 0.5 + 0.001 * h**2,
        "largest_shear_deg": 0.0,
        "draw_in_mm": 50.0 - 0.01 * h**2,
        "punch_force_N": 75.0 - 0.5 * h,
        "edge_draw_in_mm": 13.0 - 0.001 * h**2,
        "corner_draw_in_mm": 7.5 - 0.001 * h**2,
        "late_punch_force_N": 60.0 - 0.5 * h,
        "holder_lift_mm": 0.0,
        "kinetic_over_work": 0.01,
        "largest_kinetic_over_work": 0.05,
        "kinetic_exceeded_share": 0.0,
        "end_time_s": case.DURATION / time_scaling,
        "damping_over_work": 0.1,
        "contact_damping_over_work": 0.0,
        "cost": {"wall_s": 1.0, "cpu_s": 1.0, "load": (1.0, 1.0)},
        "scaling": {
            "time_scaling": time_scaling,
            "mass_scaling_dt_s": None,
            "added_mass_ratio": 0.0,
        },
    }


def test_the_fine_resolution_reports_and_checks_the_orders_of_its_three_meshes(monkeypatch):
    """compute("fine") runs the two coarser meshes too (here: flat blanks standing in for the
    runs, their numbers f = f0 + C h^p) and reports an order per kinematics and quantity; the
    quantities ORDER_TOLERANCE names are checked."""

    monkeypatch.setattr(case, "run", flat_run)
    outcome = case.compute("fine")
    assert {(o.kinematics, o.cells) for o in outcome.orders} == {
        ("fibrous", (12, 20, 32)),
        ("mindlin", (12, 20, 32)),
    }
    draw_in = next(
        o for o in outcome.orders if o.kinematics == "fibrous" and o.quantity.startswith("draw")
    )
    assert draw_in.order == pytest.approx(2.0, rel=1e-9)
    ordered = [c for c in outcome.checks if "observed order" in c.name]
    assert len(ordered) == len(case.ORDER_TOLERANCE)
    assert all(c.passed for c in ordered)
    kinetic = [c for c in outcome.checks if "kinetic energy above" in c.name]
    # each kinematics' run on the resolution's mesh, share 0 <= KINETIC_SHARE
    assert len(kinetic) == 2 and all(c.passed for c in kinetic)
    assert "fibrous n = 12: runtime" in outcome.parameters


@pytest.mark.parametrize("resolution", ["coarse", "default", "fine"])
def test_every_run_of_a_resolution_takes_its_time_scaling_and_the_report_states_it(
    monkeypatch, resolution
):
    """compute runs each kinematics (and, at "fine", the order's other meshes) with its
    TIME_SCALING at the resolution, and its solver line and parameters say for each whether
    the stroke was time-scaled, by how much, and the largest KE / W its run gave (here: flat
    blanks standing in for the runs, KE / W 0.05)."""
    given = []

    def recorded(cells, kinematics, net=None, time_scaling=1.0):
        given.append((kinematics, time_scaling))
        return flat_run(cells, kinematics, net, time_scaling)

    monkeypatch.setattr(case, "run", recorded)
    outcome = case.compute(resolution)
    speed = {k: case.TIME_SCALING[k][resolution] for k in ("fibrous", "mindlin")}
    assert sorted(given) == sorted(list(speed.items()) * (3 if resolution == "fine" else 1))
    assert outcome.parameters["time_scaling"] == speed
    for kinematics, factor in speed.items():
        stroke = case.DURATION / factor
        assert outcome.parameters["stroke_run_in_s"][kinematics] == pytest.approx(stroke)
        assert outcome.parameters[f"{kinematics}_scaling"]["time_scaling"] == factor
        assert outcome.parameters[f"{kinematics}_reached_s"] == pytest.approx(stroke)
        scaled = "not time-scaled" if factor == 1.0 else f"time-scaled x{factor:g}"
        assert f"{kinematics} {scaled}" in outcome.solver
    assert outcome.solver.count("largest KE / W after the first tenth 0.050") == 2
    # the report's default time-scales the fibrous stroke (benchmarks/hemisphere_scaling.py)
    assert case.TIME_SCALING["fibrous"]["default"] > 1.0


def test_a_fibrous_run_whose_kinetic_energy_nears_the_bound_fails_the_scalings_margin(monkeypatch):
    """A fibrous run with KE / W at most 0.07 after the first tenth (as x3 gave), never above
    the bound 0.1, passes the share rule but fails the margin its time scaling must keep
    (KINETIC_MARGIN of the bound); 0.03 (as x2 gave) passes both."""
    for largest, kept in ((0.07, False), (0.03, True)):

        def ringing(cells, kinematics, net=None, time_scaling=1.0, largest=largest):
            return {
                **flat_run(cells, kinematics, net, time_scaling),
                "largest_kinetic_over_work": largest,
            }

        monkeypatch.setattr(case, "run", ringing)
        checks = case.compute("default").checks
        share = [c for c in checks if "kinetic energy above" in c.name]
        margin = [c for c in checks if "the largest KE / W" in c.name]
        assert len(share) == 2 and all(c.passed for c in share)  # fibrous and Mindlin
        assert len(margin) == 1 and margin[0].passed is kept


def _drawn_run(mesh, largest: float, share: float, damped: float) -> SimpleNamespace:
    """A run's result as the figures read it: the blank at rest, its frames, its largest
    KE / W after the first tenth, the share of the judged stroke above the bound and the
    damper's share of the work."""
    return SimpleNamespace(
        positions=np.vstack([mesh.points, [[0.0, 0.0, 1.0]]]),  # and the holder's node
        frames=[SimpleNamespace(time=t, tool_forces=np.zeros((3, 3))) for t in (0.0, 0.3)],
        write=lambda path: None,
        info={"quasi_static": {"kinetic_over_work_largest": largest, "exceeded_share": share}},
        energies={"damping": np.array([0.0, damped]), "external_work": np.array([0.0, 1.0])},
    )


@pytest.mark.parametrize(
    ("share", "verdict"),
    [
        (0.066, "the mindlin run passes the rule but rises to KE / W 0.17 and its damper took "
         "18% of the work"),
        (0.15, "the mindlin run is not quasi-static by the case's rule"),
    ],
)  # fmt: skip
def test_the_force_figure_says_how_quasi_static_each_run_was(tmp_path, share, verdict):
    # The coarse report's runs: fibrous KE / W at most 0.033, never above 0.1, its damper
    # 0.34 % of the work; Mindlin 0.171, 6.6 % of the judged stroke above 0.1, its damper
    # 18.5 % (its flange rings). The figure invites comparing their punch forces (91.7
    # against 72.6 N at the end), so its caption gives both runs' figures and says which run
    # is outside the rule, or passes it with a peak above the bound and a damper's share
    # above DAMPING_NOTED; a share of 15 % is outside the rule (KINETIC_SHARE, 10 %).
    from femcore import Mesh

    mesh = Mesh.rectangle(200.0, 200.0, nx=2, ny=2, origin=(-100.0, -100.0, 0.0))
    shear = np.zeros(len(mesh.triangles))
    runs = {
        "fibrous": _drawn_run(mesh, 0.033, 0.0, 0.0034),
        "mindlin": _drawn_run(mesh, 0.171, share, 0.185),
    }
    data = case.HemisphereData(
        mesh=mesh, runs=runs, shear={k: shear for k in runs}, net_shear=shear,
        compared=np.ones(len(shear), bool), cells=2,
    )  # fmt: skip
    caption = next(f.caption for f in case.render(data, tmp_path) if f.file.endswith("-force.png"))
    assert (
        "fibrous largest KE / W 0.033, none of the stroke above 0.1, damping 0.3% of the work"
        in caption
    )
    mindlin = f"mindlin largest KE / W 0.171, {share:.1%} of the stroke above 0.1"
    assert f"{mindlin}, damping 18.5% of the work" in caption
    assert verdict[0].upper() + verdict[1:] in caption and "the fibrous run" not in caption.lower()


def test_the_shear_and_fibre_figures_fit_an_800_px_page_at_a_readable_size(tmp_path):
    # At most 1,000 px wide: shown at about 780 px their 10-pt text still reads as 9 pt (the
    # shear figure was one row of three, 1,430 px, its text 7 px there).
    from matplotlib.image import imread

    from femcore import Mesh

    cells = 4
    mesh = Mesh.rectangle(200.0, 200.0, nx=cells, ny=cells, origin=(-100.0, -100.0, 0.0))
    shear = np.linspace(-0.5, 0.5, len(mesh.triangles))
    run = _drawn_run(mesh, 0.03, 0.0, 0.003)
    data = case.HemisphereData(
        mesh=mesh, runs={"fibrous": run, "mindlin": run},
        shear={"fibrous": shear, "mindlin": shear}, net_shear=shear,
        compared=np.ones(len(shear), bool), cells=cells,
    )  # fmt: skip
    drawn = {figure.file: figure for figure in case.render(data, tmp_path)}
    for name in (f"{case.NAME}-shear.png", f"{case.NAME}-fibres.png"):
        height, width = imread(tmp_path / name).shape[:2]
        assert 800 < width <= 1000 and height < 1.2 * width, (name, width, height)
    assert drawn[f"{case.NAME}-shear.png"].caption


def test_the_die_with_an_entry_radius_lies_on_its_bowl_its_round_and_its_flange():
    """validation.specimens.hemisphere_die(rim=r): every point lies on the bowl's sphere, on
    the round (a torus of tube radius r about the circle of radius sqrt(R^2 + 2 R r) at z = -r,
    tangent to both: closed form) or on the flange's plane, to round-off; the round spans the
    polar angles from the sphere's tangent point to the flange; rim 0 is the sharp die."""
    from validation.specimens import hemisphere_die

    radius, rim = case.DIE, 5.0
    die = hemisphere_die(radius, 170.0, rings=48, rim=rim)
    x = die.points
    r = np.hypot(x[:, 0], x[:, 1])
    start = math.sqrt(radius**2 + 2.0 * radius * rim)
    on_bowl = np.abs(np.linalg.norm(x, axis=1) - radius) < 1e-9
    on_round = np.abs(np.hypot(r - start, x[:, 2] + rim) - rim) < 1e-9
    on_flange = np.abs(x[:, 2]) < 1e-12
    assert np.all(on_bowl | on_round | on_flange)
    round_only = on_round & ~on_bowl & ~on_flange
    assert round_only.sum() > 0 and r[round_only].min() > radius * start / (radius + rim) - 1e-9
    assert r[on_flange & (r > 1.0)].min() == pytest.approx(start, rel=1e-12)
    sharp = hemisphere_die(radius, 170.0, rings=48)
    assert np.array_equal(hemisphere_die(radius, 170.0, rings=48, rim=0.0).points, sharp.points)
    with pytest.raises(ValueError, match="rim"):
        hemisphere_die(radius, 170.0, rings=48, rim=-1.0)


@pytest.mark.parametrize("rim", [5.0, 10.0])
def test_the_net_on_the_compared_cells_lies_on_the_bowl_of_a_die_with_an_entry_radius(rim):
    """The net at fibre arc lengths (u, v) is built from its crossings in the rectangle
    [0, u] x [0, v] alone (drape.py: each crossing from its three neighbours towards the
    pole). Its polar angle grows along every fibre away from the generators, so each compared
    cell's net lies within COMPARED_POLAR (71.1 deg) of the pole, on the bowl of a die whose
    round starts at arcsin(sqrt(R^2 + 2 R r) / (R + r)) (closed form: 84.8 deg at r = 5 mm,
    80.5 at 10): the reference is the same on the sharp and the rounded die."""
    net = case._net()
    radius = case.DIE - 0.5 * case.THICKNESS
    polar = np.arccos(np.clip(net["points"][..., 2] / radius, -1.0, 1.0))
    n = (len(net["u"]) - 1) // 2
    for quadrant in (polar[n:, n:], polar[n::-1, n:], polar[n:, n::-1], polar[n::-1, n::-1]):
        reached = np.isfinite(quadrant)
        grows = np.diff(quadrant, axis=0) > 0.0
        assert np.all(grows[reached[1:] & reached[:-1]])
        assert np.all((np.diff(quadrant, axis=1) > 0.0)[reached[:, 1:] & reached[:, :-1]])
    bowl_end = math.asin(math.sqrt(case.DIE**2 + 2.0 * case.DIE * rim) / (case.DIE + rim))
    assert case.COMPARED_POLAR < bowl_end - math.radians(9.0)


def test_the_run_gives_the_solver_its_scaling_options_and_refuses_bad_ones(monkeypatch):
    """``run``'s time and mass scaling reach the solver as stated (the stroke in DURATION / s);
    without them the case's own unscaled solver."""
    given = {}

    class Built(Exception):
        pass

    def solver(**options):
        given.update(options)
        raise Built

    monkeypatch.setattr(case, "CentralDifference", solver)
    with pytest.raises(Built):
        case.run(4, "fibrous", time_scaling=4.0, mass_scaling_dt=2e-5)
    assert given["duration"] == case.DURATION / 4.0 and given["mass_scaling_dt"] == 2e-5
    with pytest.raises(Built):
        case.run(4, "fibrous")
    assert given["duration"] == case.DURATION and given["mass_scaling_dt"] is None
    for bad in (0.0, -2.0, math.nan, math.inf, True, "4"):
        with pytest.raises(ValueError, match="time_scaling"):
            case.run(4, "fibrous", time_scaling=bad)
    for bad in (0.0, -1e-6, math.nan):
        with pytest.raises(ValueError, match="mass_scaling_dt"):
            case.run(4, "fibrous", mass_scaling_dt=bad)


def test_the_frictional_variant_puts_coulomb_friction_on_the_die_and_the_holder_only():
    """``model(friction=, fibre_bending=)``: the die and the holder get the Coulomb
    coefficient, the punch stays frictionless, the tools keep their places as the first
    interactions and the fibres' in-plane bending comes after them; the case has neither."""
    from elements.fibre_bending import FibreBending

    _, varied = case.model(4, "fibrous", rim=case.DIE_RIM, friction=0.25, fibre_bending=0.5)
    die, punch, holder, bending = varied.interactions
    assert (die.friction, punch.friction, holder.friction) == (0.25, 0.0, 0.25)
    assert isinstance(bending, FibreBending) and bending.stiffness == 0.5
    _, own = case.model(4, "fibrous", rim=case.DIE_RIM)
    assert [i.friction for i in own.interactions] == [0.0, 0.0, 0.0]
    _, unheld = case.model(4, "fibrous", holder_force=0.0, friction=0.25, fibre_bending=0.5)
    assert [type(i) for i in unheld.interactions][-1] is FibreBending
    assert len(unheld.interactions) == 3
    with pytest.raises(ValueError, match="friction"):
        case.model(4, "fibrous", friction=-0.1)
    with pytest.raises(ValueError, match="FibreBending"):
        case.model(4, "fibrous", fibre_bending=-0.5)
    # the in-plane bending of fibres the Mindlin shell has not: refused at the call, not at
    # the model's compile
    with pytest.raises(ValueError, match="'mindlin' without fibre_bending"):
        case.model(4, "mindlin", fibre_bending=0.5)
    with pytest.raises(ValueError, match="kinematics"):
        case.model(4, "kirchhoff")


def test_the_run_builds_the_variant_it_is_given(monkeypatch):
    """``run(friction=, fibre_bending=)`` reaches ``model``; without them the case's own."""
    given = {}

    class Built(Exception):
        pass

    def model(*args, **options):
        given.update(options)
        raise Built

    monkeypatch.setattr(case, "model", model)
    with pytest.raises(Built):
        case.run(4, "fibrous", friction=0.3, fibre_bending=0.5)
    assert (given["friction"], given["fibre_bending"]) == (0.3, 0.5)
    with pytest.raises(Built):
        case.run(4, "fibrous")
    assert (given["friction"], given["fibre_bending"]) == (0.0, 0.0)


def test_the_holders_closing_at_a_float_is_numpys_formula_to_the_bit():
    """holder_closing at a step's float tau (an explicit run's, once a step) answers as numpy's
    operations on that scalar do (the smooth step of np.minimum(tau / HOLDER_CLOSING, 1)), at
    random taus over the run, the closing's end and past it, the start."""
    from femcore.loads import smooth_step

    rng = np.random.default_rng(5)
    taus = np.concatenate([rng.uniform(0.0, 1.0, 5000), [0.0, case.HOLDER_CLOSING, 1.0, 0.05]])
    for tau in taus:
        expected = smooth_step(np.minimum(np.asarray(tau) / case.HOLDER_CLOSING, 1.0))
        got = case.holder_closing(float(tau))
        assert np.asarray(got).tobytes() == np.asarray(expected).tobytes(), tau


def test_the_text_s_mindlin_blank_is_as_much_softer_in_shear_as_it_says():
    """The case, its figures and the report's summary say the Mindlin blank is not the fabric:
    ElasticShell.equivalent's shear is linear at the fabric's initial slope, 1.9, 2.9 and 4.0
    x softer than the fabric's shear law at 30, 36 and 40.5 deg (the shear the blank reaches).
    The ratios are those of the two laws evaluated here, to the printed digit (0.05)."""
    from materials import ElasticShell
    from validation.studies.hemisphere_forming_figures import MATERIAL_DIFFERS

    fabric = case.fabric()
    section = ElasticShell.equivalent(fabric)
    slope = float(np.asarray(fabric.shear.value(np.array([1e-6])))[0]) / 1e-6  # N/mm
    assert section.plane_stress[2, 2] * 0.3 == pytest.approx(slope, rel=1e-3)  # G12 h
    for degrees, said in ((30.0, 1.9), (36.0, 2.9), (40.5, 4.0)):
        gamma = math.radians(degrees)
        ratio = float(np.asarray(fabric.shear.value(np.array([gamma])))[0]) / (slope * gamma)
        assert ratio == pytest.approx(said, abs=0.05), degrees
    assert "1.9, 2.9 and 4.0 x softer" in MATERIAL_DIFFERS
    assert "1.9, 2.9 and 4.0 x softer" in " ".join(case.CASE.description.split())
