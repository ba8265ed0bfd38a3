"""The plies' contact penalty against its limit on the two-ply hemisphere
(validation/studies/hemisphere_plies_penalty.py): the study's instrument scales the ply
penalties alone, its penalty per area is the automatic rule's closed form, its extrapolation
in 1 / k recovers a limit, and the case's default penalty (the coarse report's fibrous [0/90]
run) gives results within the stated tolerances of four times it."""

from __future__ import annotations

import math

import numpy as np
import pytest

from elements.ply_block import PENALTY_SHARE
from validation.studies import hemisphere_plies_penalty as penalty
from validation.studies.hemisphere_plies_run import NAME, run_key
from validation.studies.hemisphere_plies_setup import FABRIC, HOLDER_FORCES, LAYUPS, model


def _compiled():
    return model(8, LAYUPS["0/90"], "fibrous", HOLDER_FORCES[0])[1].compile()


def _plies(compiled) -> list:
    return [b for b in compiled.interactions if hasattr(b, "node_stiffness")]


def _tools(compiled) -> list:
    return [b for b in compiled.interactions if hasattr(b, "tool")]


def test_the_factor_scales_the_ply_penalties_and_their_springs_alone():
    """scaled(c) multiplies both ply contact passes' node and point penalties, and so the
    springs the explicit step takes in (linear in them), by c; the tools' penalties are left
    as they were, or scaled too with ``tools``."""
    compiled = _compiled()
    plies, tools = _plies(compiled), _tools(compiled)
    assert len(plies) == 2 and len(tools) == 3  # the two passes; the die, the punch, the holder
    before = [(b.node_stiffness.copy(), b.stiffness.copy(), b.springs()) for b in plies]
    held = [t.stiffness.copy() for t in tools]
    penalty.scaled(4.0)(compiled)
    for block, (nodes, points, springs) in zip(plies, before):
        np.testing.assert_allclose(block.node_stiffness, 4.0 * nodes, rtol=1e-15)
        np.testing.assert_allclose(block.stiffness, 4.0 * points, rtol=1e-15)
        nodes_now, springs_now = block.springs()  # (nodes, N/mm)
        np.testing.assert_array_equal(nodes_now, springs[0])
        np.testing.assert_allclose(springs_now, 4.0 * springs[1], rtol=1e-14)
    for tool, stiffness in zip(tools, held):
        np.testing.assert_array_equal(tool.stiffness, stiffness)
    penalty.scaled(0.5, tools=True)(compiled)
    for tool, stiffness in zip(tools, held):
        np.testing.assert_allclose(tool.stiffness, 0.5 * stiffness, rtol=1e-15)


def test_the_penalty_per_area_is_the_automatic_rules():
    """k_j / A_j = PENALTY_SHARE rho_A (2 / dt)^2 (elements/ply_contact.py, "Penalty": k_j =
    PENALTY_SHARE m_j (2 / dt)^2 with the fibrous ply's lumped mass m_j = rho_A A_j), dt the
    compiled model's critical step without contact; both passes, to round-off."""
    compiled = _compiled()
    dt = compiled.stable_dt(compiled.initial_state())
    expected = PENALTY_SHARE * FABRIC.areal_density * (2.0 / dt) ** 2
    np.testing.assert_allclose(penalty.penalty_per_area(compiled), [expected] * 2, rtol=1e-12)


@pytest.mark.parametrize("factor", [0.0, -1.0, math.nan, math.inf])
def test_a_factor_that_is_not_a_positive_number_is_refused(factor):
    with pytest.raises(ValueError, match="positive number"):
        penalty.scaled(factor)
    with pytest.raises(SystemExit):
        penalty._arguments(["fibrous", "0/90", "--factors", "1", str(factor)])


def test_a_factor_given_twice_is_refused_before_the_runs():
    with pytest.raises(SystemExit):
        penalty._arguments(["fibrous", "0/90", "--factors", "1", "2", "2"])


def test_the_extrapolation_in_one_over_k_recovers_the_limit():
    """f(c) = f0 + a / c (a penetration p / k and results smooth in it): the three stiffest
    runs that reached the end give p = 1 and f0 to round-off; a stopped run is left out;
    fewer than three ended runs give nothing."""

    def run(factor, stopped=()):
        return {"factor": factor, "stopped": list(stopped), "values": {"x": 3.0 + 0.5 / factor}}

    runs = [run(c) for c in (0.5, 1.0, 2.0, 4.0)] + [run(8.0, ["diverged"])]
    order, limit = penalty.extrapolated(runs)["x"]
    assert order == pytest.approx(1.0, abs=1e-9)
    assert limit == pytest.approx(3.0, abs=1e-12)
    assert penalty.extrapolated(runs[:2] + runs[4:]) == {}
    runs[3]["values"]["x"] = math.inf  # a ply with no cell in the die
    assert all(math.isnan(v) for v in penalty.extrapolated(runs)["x"])


# The stated tolerances of the default penalty against its limit (docs/hemisphere_plies.md,
# "The plies' penalty"): measured, fibrous [0/90] at 8 cells, the default against 8 times it
# within 0.03 deg (rms), 0.13 mm (draw-in), 2.2 % (punch force); a factor 1.05 moves them by
# 0.0004 deg, 0.04 mm, 0.15 %; at half the default ply 1 has other cells in the die (the test
# fails there) and an rms of 2.36 deg against 3.46.
RMS_DEG, DRAW_IN_MM, PUNCH_SHARE, HOLDER_N = 0.15, 0.5, 0.05, 0.5


def _four_times(once_per_run) -> dict:
    """The study's run at four times the plies' penalty (fibrous [0/90], 8 cells, 20 N; ~13k
    steps, 23 s of CPU): made once per run of the suite, by the slow test below that needs no
    report, among the first of a run while the coarse report takes the other core, and read
    back by the test that compares it with the report (run last: alone at the end of a run,
    the other worker idle, it took a minute of one core's wall)."""
    return once_per_run(
        "hemisphere-plies-penalty-x4",
        lambda out: penalty.measure("fibrous", "0/90", HOLDER_FORCES[0], 8, 4.0),
    )[1]


@pytest.mark.slow
def test_the_run_at_four_times_the_ply_penalty_reaches_the_end_at_that_penalty(once_per_run):
    """The stiff run ends its stroke (no ply stopped it), with both passes' penalty per area
    four times the automatic rule's on the same model (to round-off)."""
    stiff = _four_times(once_per_run)
    assert not stiff["stopped"]
    np.testing.assert_allclose(
        stiff["penalty_per_area"], 4.0 * np.array(penalty.penalty_per_area(_compiled())),
        rtol=1e-12,
    )  # fmt: skip


@pytest.mark.slow
def test_the_default_ply_penalty_is_within_tolerance_of_four_times_it(coarse_report, once_per_run):
    """The coarse report's fibrous [0/90] run (8 cells, 20 N, the automatic penalty) against
    the same run at four times the plies' penalty (the study's ``measure``, ~13k steps, 23 s
    of CPU): each ply's rms of shear - net over the same cells in the die, the draw-in of
    the edge middle and of the corner, the punch's force and the holder's reaction within
    the tolerances above: about four times the differences measured against eight times the
    penalty (the punch's force, 85.9-89.3 N from c = 1 to 8 and not monotone, twice), below
    what half the penalty moves (the bottom ply's cells in the die and its rms, 3.46 -> 2.36
    deg: the test fails there, run on the study's c = 0.5 run in place of the report's). The
    penetration, which is the penalty's, is not compared (0.13 against 0.06 mm)."""
    _, report = coarse_report
    values = report["cases"][NAME]["parameters"]
    stiff = _four_times(once_per_run)
    assert not stiff["stopped"]
    key = run_key("0/90", "fibrous", HOLDER_FORCES[0]).replace(" ", "_").replace("/", "-")
    for k, angle in enumerate(LAYUPS["0/90"]):
        ply = f"{key}_ply{k + 1}_{angle:g}deg"
        stiffer = {q: v for q, v in stiff["values"].items() if q.startswith(f"ply {k + 1} ")}
        assert values[f"{ply}_cells_in_die"] == stiffer[f"ply {k + 1} cells_in_die"], ply
        assert values[f"{ply}_rms_shear_error_deg"] == pytest.approx(
            stiffer[f"ply {k + 1} rms_shear_error_deg"], abs=RMS_DEG
        ), ply
        for where in ("edge_middle", "corner"):
            assert values[f"{ply}_draw_in_{where}_mm"] == pytest.approx(
                stiffer[f"ply {k + 1} draw_in_{where}_mm"], abs=DRAW_IN_MM
            ), (ply, where)
    assert values[f"{key}_punch_force_N"] == pytest.approx(
        stiff["values"]["punch_force_N"], rel=PUNCH_SHARE
    )
    assert values[f"{key}_holder_force_last_tenth_mean_N"] == pytest.approx(
        stiff["values"]["holder_force_last_tenth_mean_N"], abs=HOLDER_N
    )
