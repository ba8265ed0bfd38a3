"""validation/studies/hemisphere_forming_order.py on manufactured inputs whose answers are
known in closed form: results f0 + C h^p over the meshes (their order p and limit f0), shear
fields that differ from the net by c(X) h^p (the rms against the net and the field's changes
both of order p), and a centre line laid on the die's entry round or a known distance off it."""

from __future__ import annotations

import math

import numpy as np
import pytest

from validation.cases import hemisphere_forming as case
from validation.references.centre_line_draw_in import flange_start
from validation.studies import hemisphere_forming_order as study
from validation.studies.hemisphere_plies_fields import material_grid, net_on_sphere

CELLS = [20, 28, 40, 56]  # the study's meshes: ratios near sqrt 2, unequal
SIZES = np.array([200.0 / n for n in CELLS])


def _records(p: float, f0: float = 13.0, c: float = 0.05) -> list[dict]:
    values = f0 + c * SIZES**p
    return [{"cells": n, **dict.fromkeys(study.QUANTITIES, v)} for n, v in zip(CELLS, values)]


@pytest.mark.parametrize("p", [1.0, 2.0])
def test_orders_of_a_power_law_give_its_order_and_limit(p):
    # observed_order solves for p by root finding: 1e-8 is far above its tolerance
    for row in study.orders(_records(p)).values():
        assert row["p"] == pytest.approx(p, abs=1e-8)
        assert row["f0"] == pytest.approx(13.0, abs=1e-8)
        assert np.allclose(row["consecutive"], p, atol=1e-8)
        # through three meshes of an exact power law Roache's band is Fs |f3 - f0|
        error = 0.05 * SIZES[-1] ** p
        assert row["gci"] == pytest.approx(1.25 * error, rel=1e-6)


def test_orders_need_three_runs():
    with pytest.raises(ValueError, match="three or more runs"):
        study.orders(_records(1.0)[:2])


def test_field_orders_of_a_field_converging_to_the_net_at_order_two():
    grid = material_grid(case.HALF, study.SPACING)
    net = net_on_sphere(case.DIE - 0.5 * case.THICKNESS, case.NET_CELL, 0.0, grid)["shear"]
    pattern = 1e-4 * np.sin(grid[:, 0] / 17.0) * np.cos(grid[:, 1] / 23.0)  # rad / mm^2
    fields = [net + pattern * h**2 for h in SIZES]
    table = study.field_orders(CELLS, fields)
    names = [f"within {limit:g} deg" for limit in study.POLAR_DEG]
    assert list(table) == names + [f"{n}, {study.BAND_MM:g} mm off the planes" for n in names]
    for row in table.values():
        # the rms against the net is rms(pattern) h^2 and each change rms(pattern) (h_i^2 -
        # h_i+1^2): both of order 2 exactly (root finding to 1e-8)
        ratio = np.array(row["against net"]) / SIZES**2
        assert np.allclose(ratio, ratio[0], rtol=1e-12)
        assert np.allclose(row["against net orders"], 2.0, atol=1e-8)
        assert np.allclose(row["change orders"], 2.0, atol=1e-8)
        assert row["points"] > 0


def _centre_line(points: np.ndarray) -> np.ndarray:
    """The centre line's nodes (y = 0, x >= 0) of ``points``, from the pole out."""
    line = np.flatnonzero(np.isclose(points[:, 1], 0.0) & (points[:, 0] >= 0.0))
    return line[np.argsort(points[line, 0])]


def test_centre_line_on_the_round_is_at_zero_height_and_a_lifted_node_at_its_lift():
    # nodes laid on the die's profile half a ply above it: the bowl (radius DIE), the round
    # (radius DIE_RIM about (start, -DIE_RIM) in the (r, z) plane), the flange (z = 0)
    mesh = case.model(40, "fibrous", holder_force=0.0)[0]
    points = mesh.points
    start = flange_start(case.DIE, case.DIE_RIM)
    mid = 0.5 * case.THICKNESS
    line = _centre_line(points)
    # the round's angles about its centre, from the flange (pi / 2) to the bowl's tangent
    span = 0.5 * math.pi - math.atan2(case.DIE_RIM, start)
    angles = np.linspace(0.5 * math.pi, 0.5 * math.pi + span, 7)[1:-1]
    on_round = np.column_stack(
        [
            start + (case.DIE_RIM + mid) * np.cos(angles),
            np.zeros_like(angles),
            -case.DIE_RIM + (case.DIE_RIM + mid) * np.sin(angles),
        ]
    )
    positions = points.copy()
    inner, rounded, outer = line[:-8], line[-8:-3], line[-3:]
    positions[inner] = [0.0, 0.0, mid - case.DIE]  # at the pole, off the round
    positions[rounded] = on_round
    positions[outer] = np.column_stack([start + np.arange(1.0, 4.0), np.zeros(3), np.full(3, mid)])
    state = study.centre_line_state(points, positions)
    assert state["height_over_round_mm"] == pytest.approx(0.0, abs=1e-12)
    assert state["flange_start_mm"] == pytest.approx(start, rel=1e-15)
    # one node moved 3 mm off the round along its normal: the largest height is 3 mm
    normal = np.array([math.cos(angles[2]), 0.0, math.sin(angles[2])])
    positions[rounded[2]] += 3.0 * normal
    state = study.centre_line_state(points, positions)
    assert state["height_over_round_mm"] == pytest.approx(3.0, abs=1e-12)


def test_orders_refuse_runs_of_different_variants_and_old_records_are_the_case():
    records = _records(1.0)
    assert study.variant(records[0]) == {"friction": 0.0, "fibre_bending_N_mm": 0.0}
    same = {"friction": 0.2, "fibre_bending_N_mm": 0.5}
    assert study.orders([{**r, "variant": dict(same)} for r in records])  # one variant: fine
    records[2]["variant"] = same
    with pytest.raises(ValueError, match="different variants"):
        study.orders(records)


def test_the_run_verb_hands_the_variant_to_measure_and_writes_its_record(monkeypatch, tmp_path):
    given = []

    def measure(cells, kinematics, positions, friction, fibre_bending):
        given.append((cells, kinematics, friction, fibre_bending))
        return {"cells": cells}

    monkeypatch.setattr(study, "measure", measure)
    study._main(["run", "fibrous", "20", "--out", str(tmp_path), "--friction", "0.2",
                 "--fibre-bending", "0.5"])  # fmt: skip
    study._main(["run", "fibrous", "28", "--out", str(tmp_path)])
    assert given == [(20, "fibrous", 0.2, 0.5), (28, "fibrous", 0.0, 0.0)]
    assert (tmp_path / "fibrous-20.json").exists()


@pytest.mark.parametrize("strain", [-0.004, 0.0, 0.003])
def test_the_centre_lines_strain_to_the_flange_is_its_stretch_along_the_line(strain):
    # the flat blank stretched uniformly along x by ``strain`` (every node inside the
    # flange's start moves out by strain x): its chords over their flat lengths less 1 is
    # that strain; a node outside the flange's start moved anyhow changes nothing
    mesh = case.model(20, "fibrous", holder_force=0.0)[0]
    points = mesh.points
    positions = points.copy()
    positions[:, 0] *= 1.0 + strain
    outside = np.abs(points[:, 0]) > 70.0
    positions[outside, 2] += 5.0
    state = study.centre_line_state(points, positions)
    assert state["strain_to_flange"] == pytest.approx(strain, abs=1e-12)
