"""The observed orders of the paper cases (validation.checks.observed_order,
validation.paper.orders, the report's table) on synthetic sequences of known order, and the
gripper that replaced the lifted node of bai-6.2.1 (elements.Grip, a gripped corner specimen).
"""

import math
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from elements import Grip
from femcore import Body, Mesh
from femcore.interaction_checks import check_interaction, check_objectivity
from femcore.state import State
from materials.presets import g1151_laminate
from validation import specimens
from validation.checks import observed_order
from validation.paper import (
    deflection_name,
    observed_orders,
    order_checks,
    order_quantities,
    solve,
    thickness_name,
)
from validation.records import ObservedOrder, SideProfile
from validation.report_html import _orders_table


# ---------------------------------------------------------------------- Richardson
@pytest.mark.parametrize("p", [0.5, 1.0, 2.0, 3.2])
@pytest.mark.parametrize("sizes", [(4.0, 2.0, 1.0), (20.0, 8.0, 5.0), (25.0, 10.0, 5.0 / 3.0)])
def test_the_observed_order_of_a_known_sequence(p, sizes):
    """f(h) = f0 + C h^p on three meshes of any ratios gives back p and f0 (to round-off)."""
    h = np.asarray(sizes)
    values = 7.0 - 0.3 * h**p
    order, extrapolated = observed_order(h, values)
    assert order == pytest.approx(p, abs=1e-9)
    assert extrapolated == pytest.approx(7.0, abs=1e-9)
    # the constant-ratio formula of the issue, log((f1 - f2) / (f2 - f3)) / log(r)
    if np.isclose(h[0] / h[1], h[1] / h[2]):
        f1, f2, f3 = values
        assert order == pytest.approx(math.log((f1 - f2) / (f2 - f3)) / math.log(h[0] / h[1]))


def test_an_oscillating_or_diverging_sequence_has_no_order():
    assert all(math.isnan(v) for v in observed_order([4.0, 2.0, 1.0], [1.0, 2.0, 1.5]))
    order, _ = observed_order([4.0, 2.0, 1.0], [1.0, 1.1, 1.3])  # growing differences
    assert order == pytest.approx(-1.0)
    assert observed_order([4.0, 2.0, 1.0], [1.0, 2.0, 2.0]) == (math.inf, 2.0)


@pytest.mark.parametrize(
    "sizes, values, message",
    [
        ([1.0, 2.0, 3.0], [1.0, 2.0, 3.0], "decreasing"),
        ([4.0, 2.0], [1.0, 2.0], "three"),
        ([4.0, 2.0, 1.0], [1.0, np.nan, 2.0], "finite"),
    ],
)
def test_bad_sequences_are_refused(sizes, values, message):
    with pytest.raises(ValueError, match=message):
        observed_order(sizes, values)


# ---------------------------------------------------------------------- records and checks
def runs(p: float, kinematics: str = "mindlin") -> list:
    """Three runs (cells, h, quantities, converged) of a deflection converging at order p to
    10 mm and, for the fibrous shell, a thickness at order 2 to 1.2 h."""
    out = []
    for cells in (10, 20, 40):
        h = 200.0 / cells
        quantities = {deflection_name("side_1"): 10.0 + 0.5 * (h / 20.0) ** p}
        if kinematics == "fibrous":
            quantities[thickness_name("side_1")] = 1.2 - 0.02 * (h / 20.0) ** 2
        out.append((cells, h, quantities, True))
    return out


def test_the_records_give_the_orders_and_the_checks_decide_on_them():
    orders = observed_orders({"fibrous": runs(0.5, "fibrous"), "mindlin": runs(1.0)})
    found = {(o.kinematics, o.quantity): o for o in orders}
    assert found["mindlin", deflection_name("side_1")].order == pytest.approx(1.0)
    assert found["fibrous", deflection_name("side_1")].order == pytest.approx(0.5)
    assert found["fibrous", thickness_name("side_1")].order == pytest.approx(2.0)
    assert found["fibrous", thickness_name("side_1")].extrapolated == pytest.approx(1.2)
    assert found["mindlin", deflection_name("side_1")].cells == (10, 20, 40)
    # Only the quantities with a tolerance are checked: at order 1 the Richardson value is
    # exact (its gap to the finest mesh, 1.2 %, is the error left there); the fibrous
    # deflection has no tolerance here.
    case = SimpleNamespace(
        source="§x",
        order_tolerance={"default": {"mindlin deflection": 0.02, "fibrous thickness": 0.002}},
    )
    checks = order_checks(case, orders, "default")
    assert len(checks) == 2 and all(c.passed for c in checks)
    assert order_checks(case, orders, "coarse") == []
    # an oscillating sequence fails its check; one converged within the tolerance passes
    wobbly = observed_orders({"mindlin": [(10, 20.0, {"d": 10.0}, True),
                                          (20, 10.0, {"d": 10.5}, True),
                                          (40, 5.0, {"d": 10.2}, True)]})  # fmt: skip
    strict = SimpleNamespace(source="§x", order_tolerance={"default": {"mindlin deflection": 0.01}})
    assert not order_checks(strict, wobbly, "default")[0].passed
    loose = SimpleNamespace(source="§x", order_tolerance={"default": {"mindlin deflection": 0.1}})
    (converged,) = order_checks(loose, wobbly, "default")
    assert converged.passed and "no positive order" in converged.name


def test_the_quantities_are_read_at_the_middle_of_each_side():
    """The deflection and the fibrous shell's thickness along the director (/ h) at half the
    side's length, interpolated between its nodes."""
    s = np.array([0.0, 30.0, 70.0, 100.0])
    side = SideProfile(
        s=s,
        midsurface=np.column_stack([s, 0 * s, 0.01 * s**2]),
        director_angle_deg=np.full(4, 90.0),
        thickness=np.array([2.0, 2.1, 2.4, 2.2]),
        rotation_deg=np.zeros(4),
        side_tilt_deg=np.zeros(4),
        director_tilt_deg=np.zeros(4),
    )
    fibrous = order_quantities({"side_1": side}, "fibrous", 2.0)
    assert fibrous[deflection_name("side_1")] == pytest.approx(9.0 + 20.0 / 40.0 * (49.0 - 9.0))
    assert fibrous[thickness_name("side_1")] == pytest.approx((2.1 + 0.5 * 0.3) / 2.0)
    assert list(order_quantities({"side_1": side}, "mindlin", 2.0)) == [deflection_name("side_1")]


def test_the_report_shows_the_orders_in_a_table():
    record = ObservedOrder("mindlin", "deflection (mm)", (10, 20, 40), (20.0, 10.0, 5.0),
                           (11.0, 10.5, 10.25), 1.0, 10.0, True)  # fmt: skip
    # no order: None, as results.json writes NaN
    none = ObservedOrder("fibrous", "thickness (/ h)", (10, 20, 40), (20.0, 10.0, 5.0),
                         (1.0, 1.2, 1.1), None, None, True)  # fmt: skip
    case = {"observed_orders": [vars(record), vars(none)],
            "elements": {"mindlin": {"label": "Mindlin"}}}  # fmt: skip
    table = _orders_table(case)
    assert "<th>n = 10<br>h = 20 mm</th>" in table and "<td>Mindlin</td>" in table
    assert "<td class='num'>1.00</td>" in table and "2.44 %" in table
    assert "<td class='num'>-</td>" in table  # no order
    assert _orders_table({"checks": []}) == ""


# ---------------------------------------------------------------------- the gripper
def jittered(turn: np.ndarray | None = None):
    """A Grip of 20 N/mm on 5 nodes of a jittered 3 x 3 grid, the nodes moved apart."""
    turn = np.eye(3) if turn is None else turn
    rng = np.random.default_rng(5)
    mesh = Mesh.rectangle(4.0, 4.0, nx=2, ny=2)
    mesh = mesh.with_points((mesh.points + rng.normal(scale=0.3, size=(9, 3))) @ turn.T)
    block = Grip([4, 0, 2, 6, 8], 20.0).bind(Body.bare(mesh))
    moved = mesh.points + rng.normal(scale=0.2, size=(9, 3)) @ turn.T
    zero = np.zeros((9, 3))
    return block, State(moved, zero, zero.copy(), zero.copy()), None


def test_the_grip_conforms_to_the_interaction_protocol():
    block, state, history = jittered()
    check_interaction(block, state, history)
    check_objectivity(jittered, Rotation.from_rotvec([0.3, -0.7, 0.5]).as_matrix())
    np.testing.assert_array_equal(block.connectivity[:, 0], 4)  # tied to the first node
    with pytest.raises(ValueError, match="two or more"):
        Grip([3], 1.0).bind(block and Body.bare(Mesh.rectangle(1.0, 1.0, 1, 1)))
    with pytest.raises(ValueError, match="positive"):
        Grip([0, 1], 0.0)


def test_a_gripped_corner_is_lifted_as_one_patch():
    """bai-6.2.1's set-up at 10 cells with the Mindlin shell: the 20 x 15 mm patch (node set
    "grip") rises 40 mm, slides sideways as one (its nodes part by < 1e-3 mm) and stays flat
    and level (rotations held); gravity first, then the lift."""
    fabric = g1151_laminate()
    specimen = specimens.corner(200.0, 150.0, 10, grip=(20.0, 15.0))
    assert specimen.gripped and len(specimen.loaded) == 4  # one cell at 10 cells
    model = specimens.build(specimen, "mindlin", fabric, (None, None, 40.0))
    result, _, _ = solve(model, 10)
    assert result.converged
    moved = result.positions[specimen.loaded] - specimen.mesh.points[specimen.loaded]
    np.testing.assert_allclose(moved[:, 2], 40.0, atol=1e-9)
    assert np.abs(moved - moved.mean(axis=0)).max() < 1e-3
    assert np.linalg.norm(moved[0, :2]) > 1.0  # it slid towards the clamp
    np.testing.assert_allclose(result.directors[specimen.loaded], [[0.0, 0.0, 1.0]] * 4, atol=1e-9)


@pytest.mark.parametrize("kinematics", [pytest.param("fibrous", marks=pytest.mark.slow), "mindlin"])
@pytest.mark.parametrize("name", ["bai-5.1", "bai-6.1.1", "bai-6.2.1", "bai-6.2.2"])
def test_the_refinement_runs_other_path_reaches_the_same_equilibrium(name, kinematics):
    """The paper cases solve the orders' other meshes on ``order_increments`` arc-length
    increments a phase, other than their own runs' ``increments`` (fewer for the corner
    cases, more for bai-5.1, whose shorter first steps are cut less), as only the last
    equilibrium is read (validation.paper.refinement_orders): on the coarsest mesh of the
    default sequence (10 cells; bai-6.2.2's 6, its limit point passed on either path; bai-5.1's
    15) both paths end converged at the same equilibrium. The nodes within 4e-5 mm: each
    path's last state is converged to Newton's tolerance, measured at most 7.4e-10 (fibrous)
    and 3.4e-11 (Mindlin) of the compared quantities apart (bai-6.2.2: 2.3e-10, 3.6e-16;
    bai-5.1: 3.7e-12, 3.0e-15); a path that left the branch (a missed limit point) would part
    them by millimetres."""
    from validation.cases import bai_5_1, bai_6_1_1, bai_6_2_1, bai_6_2_2

    modules = {"bai-5.1": bai_5_1, "bai-6.1.1": bai_6_1_1, "bai-6.2.1": bai_6_2_1}
    spec = {**modules, "bai-6.2.2": bai_6_2_2}[name].SPEC
    assert spec.order_increments is not None and spec.order_increments != spec.increments
    specimen = spec.make_specimen(spec.order_cells["default"][0])
    ends = []
    for increments in (spec.increments, spec.order_increments):
        model = spec.model(specimen, kinematics)
        result, note, _ = solve(model, increments, spec.arc_iterations, spec.arc_chords)
        assert result.converged, note
        ends.append(result)
    np.testing.assert_allclose(ends[1].positions, ends[0].positions, rtol=0, atol=4e-5)
    if spec.order_increments < spec.increments:
        assert len(ends[1].frames) < len(ends[0].frames)  # the shorter path


@pytest.mark.parametrize("bad", [0, -2, 2.5, True, "5"])
def test_a_paper_case_refuses_order_increments_that_are_not_a_count(bad):
    from dataclasses import replace

    from validation.cases import bai_6_2_1

    with pytest.raises(ValueError, match="order_increments must be a whole number >= 1"):
        replace(bai_6_2_1.SPEC, order_increments=bad)


def test_a_paper_case_takes_a_numpy_integer_as_its_order_increments():
    from dataclasses import replace

    from validation.cases import bai_6_2_1

    assert replace(bai_6_2_1.SPEC, order_increments=np.int64(5)).order_increments == 5


@pytest.mark.parametrize("kinematics", ["fibrous", "mindlin"])
def test_bai_5_1_steps_aimed_at_more_iterations_end_at_the_same_equilibrium(kinematics):
    """bai-5.1 takes its arc-length steps aimed at ``arc_iterations`` (10) Newton iterations
    an increment instead of the default 5 (validation/cases/bai_5_1.py): on its 15-cell order
    mesh both paths end at one equilibrium, within what Newton's tolerance (1e-8 of the
    forces) allows on a 65 mm motion, 1e-6 mm (measured: 2.6e-10 mm fibrous, 2.6e-13 mm
    Mindlin), with fewer Newton iterations (260 -> 145, 236 -> 120)."""
    from solvers.arc_length import DESIRED_ITERATIONS
    from validation.cases import bai_5_1

    spec = bai_5_1.SPEC
    assert spec.arc_iterations > DESIRED_ITERATIONS
    specimen = spec.make_specimen(15)
    ends = []
    for aim in (DESIRED_ITERATIONS, spec.arc_iterations):
        result, note, _ = solve(spec.model(specimen, kinematics), spec.increments, aim)
        assert result.converged, note
        ends.append(result)
    np.testing.assert_allclose(ends[1].positions, ends[0].positions, rtol=0, atol=1e-6)
    assert ends[1].steps < ends[0].steps


@pytest.mark.parametrize("bad", [0, 2.5, True, "5"])
def test_a_paper_case_refuses_arc_iterations_that_are_not_a_count(bad):
    from dataclasses import replace

    from validation.cases import bai_5_1

    with pytest.raises(ValueError, match="arc_iterations must be an integer >= 1"):
        replace(bai_5_1.SPEC, arc_iterations=bad)


def test_a_phase_s_first_arc_length_step_is_cut_harder_at_each_failure(monkeypatch):
    """The first step of a phase is the tangent's guess; its k-th failed attempt is retried at
    1/2^k of the last length (solvers/arc_length.py, docs/theory.md §6.6): bai-5.1's first
    displacement step on its 15-cell Mindlin model (which halving cut five times, to converge
    at 1/32 of the guess) is tried at 1, 1/2, 1/8 and converges at 1/64 of it."""
    import solvers.arc_length as arc_length
    from validation.cases import bai_5_1

    tried = []
    corrector = arc_length.arc_corrector

    def recorded(run, pattern, prediction):
        if run.phase == 1 and run.reached == 1.0:  # the displacement phase's first increment
            tried.append(prediction.load)
        return corrector(run, pattern, prediction)

    monkeypatch.setattr(arc_length, "arc_corrector", recorded)
    spec = bai_5_1.SPEC
    result, note, _ = solve(spec.model(spec.make_specimen(15), "mindlin"), spec.increments)
    assert result.converged, note
    shares = np.array(tried) / tried[0]
    np.testing.assert_allclose(shares, [1, 1 / 2, 1 / 8, 1 / 64], rtol=1e-12)


class _Solved(Exception):
    """Raised by a stand-in for the paper cases' solve, once it has seen its arguments."""


@pytest.mark.parametrize("path", ["runs", "orders"])
def test_the_report_s_bai_5_1_runs_and_order_runs_aim_at_the_case_s_arc_iterations(
    path, monkeypatch
):
    """The report's bai-5.1 (validation/paper/case.py ``compute_paper_case``, its order runs
    ``refinement_orders``) solves every model with the case's ``arc_iterations`` (10), not the
    default aim, and cases/bai-5.1.toml, which runs the case as the report does, says the
    same."""
    import validation.paper.case as paper
    from fibreshell.case import read_case_data
    from validation.cases import bai_5_1

    aims = []

    def seen(model, increments, arc_iterations=None, arc_chords=None):
        aims.append(arc_iterations)
        raise _Solved

    monkeypatch.setattr(paper, "solve", seen)
    spec = bai_5_1.SPEC
    with pytest.raises(_Solved):
        if path == "runs":
            paper.compute_paper_case(spec, "coarse")
        else:  # the default sequence starts on a mesh of its own (15 cells)
            assert spec.order_cells["default"][0] != spec.cells["default"]
            paper.refinement_orders(spec, "default", None, {})
    assert aims == [spec.arc_iterations] and spec.arc_iterations == 10
    case_file = read_case_data(Path(__file__).parents[1] / "cases" / "bai-5.1.toml")
    assert case_file["solver"]["arc_iterations"] == spec.arc_iterations


@pytest.mark.parametrize("name", ["bai_5_1", "bai_6_1_1", "bai_6_1_2", "bai_6_2_1", "bai_6_2_2"])
@pytest.mark.parametrize("path", ["runs", "orders"])
def test_the_report_s_paper_runs_take_the_case_s_chord_steps(name, path, monkeypatch):
    """Every run of a paper case (the three kinematics and the order runs) solves with the
    case's ``arc_chords`` (validation.paper.ARC_CHORDS, bai-5.1 none), and the case file that
    runs the case as the report does says the same."""
    import importlib

    import validation.paper.case as paper
    from fibreshell.case import read_case_data

    spec = importlib.import_module(f"validation.cases.{name}").SPEC
    ratios = []

    def seen(model, increments, arc_iterations=None, arc_chords=None):
        ratios.append(arc_chords)
        raise _Solved

    monkeypatch.setattr(paper, "solve", seen)
    with pytest.raises(_Solved):
        if path == "runs":
            paper.compute_paper_case(spec, "coarse")
        else:  # the default sequence starts on a mesh of its own
            assert spec.order_cells["default"][0] != spec.cells["default"]
            paper.refinement_orders(spec, "default", None, {})
    expected = 0.0 if name == "bai_5_1" else paper.ARC_CHORDS
    assert ratios == [expected] and spec.arc_chords == expected
    case_file = read_case_data(Path(__file__).parents[1] / "cases" / f"{spec.name}.toml")
    assert case_file["solver"].get("arc_chords", 0.0) == spec.arc_chords


@pytest.mark.parametrize("name", ["bai_5_1", "bai_6_1_1", "bai_6_1_2", "bai_6_2_1", "bai_6_2_2"])
def test_the_coarse_paper_cases_run_no_refinement_runs(name, monkeypatch):
    """At the coarse resolution (the test suite's background report) a paper case solves its
    three kinematics on its own mesh and nothing more: its observed orders, on pre-asymptotic
    meshes and checked at no tolerance there, cost about a quarter of its time
    (validation/paper/case.py ``order_cells``). The default and fine resolutions keep theirs."""
    import importlib

    import validation.paper.case as paper

    spec = importlib.import_module(f"validation.cases.{name}").SPEC

    def unexpected(*args, **kwargs):
        raise AssertionError("a refinement run at the coarse resolution")

    monkeypatch.setattr(paper, "solve", unexpected)
    orders, cost = paper.refinement_orders(spec, "coarse", None, {})
    assert orders is None and cost["runs"] == []
    assert "coarse" not in spec.order_cells
    assert {"default", "fine"} <= set(spec.order_cells)
