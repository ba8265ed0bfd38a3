"""The arc-length step length (solvers/arc_step.py, docs/theory.md §6.6 "Step length"): a path
that is stiff and then soft (a column past its buckling load) is followed to its end in a few
dozen steps, where every step used to be capped at the first one's length; the cases that
passed keep their steps (tests/test_static.py's truss, tests/test_arc_chords.py)."""

import math

import numpy as np
import pytest

from elements import FibrousShell, MindlinShell
from femcore import Mesh, Model
from materials import ElasticShell, Fabric
from solvers import Static
from solvers.arc_length import Motion
from solvers.arc_step import SETTLED_RATIO, SOFTER, TURN_LIMIT, ArcStep, iterations_spent
from validation.references.elastica import buckled_cantilever_column

LENGTH, WIDTH = 100.0, 5.0


def imperfect_column(kind: str, cells: int = 20):
    """A strip 100 x 5 mm clamped at x = 0 under a dead tip load 1.5 Pcr along -x and a side
    load of 1e-4 Pcr along z (the imperfection that picks the side): (model, tip nodes, EI)."""
    mesh = Mesh.rectangle(LENGTH, WIDTH, nx=cells, ny=1)
    model = Model(mesh)
    if kind == "mindlin":
        model.add(MindlinShell(ElasticShell(E=1e5, nu=0.0, thickness=1.0, density=1e-9)))
        bending = 1e5 * WIDTH / 12
    else:
        fabric = Fabric(
            thickness=0.3, areal_density=2.85e-10, tension=6000.0, shear=0.2, bending=0.375
        )
        model.add(FibrousShell(fabric, clamped="left"))
        bending = 0.375 * WIDTH
    model.fix("left")
    tip = mesh.nodes("right")
    critical = math.pi**2 * bending / (4 * LENGTH**2)
    model.force(tip, (-1.5 * critical / len(tip), 0.0, 1e-4 * critical / len(tip)))
    return model, tip, bending


def test_the_column_elastica_is_timoshenko_and_gere_s_table():
    # Timoshenko and Gere, Theory of Elastic Stability (1961), Table 2-5: the tip turn alpha,
    # P / Pcr, and the tip's place along (x / L) and across (delta / L) the load, to the
    # table's last digit (1e-3: its delta / L at 20 deg reads 0.220 for 0.2194).
    bending = 1.0
    critical = math.pi**2 * bending / 4
    for alpha, ratio, along, across in [
        (20, 1.015, 0.970, 0.220),
        (60, 1.152, 0.741, 0.593),
        (100, 1.518, 0.349, 0.792),
        (120, 1.884, 0.123, 0.803),
    ]:
        k = math.sin(math.radians(alpha) / 2)
        load = critical * (2 / math.pi * _quarter_period(k)) ** 2
        assert load / critical == pytest.approx(ratio, abs=1e-3)
        shape = buckled_cantilever_column(1.0, load, bending)
        assert math.degrees(shape["alpha"]) == pytest.approx(alpha, abs=1e-9)
        assert shape["tip_x"] == pytest.approx(along, abs=1e-3)
        assert shape["lateral"] == pytest.approx(across, abs=1e-3)
    with pytest.raises(ValueError, match="must exceed the critical load"):
        buckled_cantilever_column(1.0, critical, bending)


def _quarter_period(k: float) -> float:
    from scipy.special import ellipk

    return float(ellipk(k * k))


# The 20-cell strips' error against the elastica (lateral tip 78.858 mm, tip at x = 36.359 mm
# at 1.5 Pcr), measured when this was written by the arc length at 10, 20 and 40 cells:
# MindlinShell lateral +0.42 %, +0.11 %, +0.034 %, x -0.84, -0.24, -0.09 % of L; FibrousShell
# +0.25 %, +0.062 %, +0.016 %, x -0.27, -0.069, -0.019 % of L: second order, to the closed
# form. The tolerances hold three times the 20-cell error.
LATERAL_TOLERANCE = {"mindlin": 3.3e-3, "fibrous": 1.9e-3}
ALONG_TOLERANCE = {"mindlin": 7e-3 * LENGTH, "fibrous": 2.1e-3 * LENGTH}
# The most increments each path may take (taken when this was written: Mindlin 27-31 at 3, 5
# and 10 increments, fibrous 60-66; before, every run stopped near 0.65 Pcr after its
# max_increments of steps of the first one's length, 20 x increments + 20).
MOST_STEPS = {"mindlin": 40, "fibrous": 80}


@pytest.mark.parametrize("kind", ["mindlin", "fibrous"])
@pytest.mark.parametrize("increments", [3, 10])
def test_the_arc_length_follows_a_column_past_its_buckling_load_to_the_elastica(kind, increments):
    # Stiff, then soft: to 0.66 (Pcr) the strip only shortens (3e-3 mm a step of 1 /
    # increments), then its tip swings 79 mm across for the last third of the load.
    model, tip, bending = imperfect_column(kind)
    result = Static(increments=increments, path="arc_length", progress=False).solve(model)
    expected = buckled_cantilever_column(
        LENGTH, 1.5 * math.pi**2 * bending / (4 * LENGTH**2), bending
    )
    assert result.frames[-1].load_factor == 1.0
    assert len(result.frames) - 1 <= MOST_STEPS[kind]
    x, _, z = result.positions[tip].mean(axis=0)
    assert z == pytest.approx(expected["lateral"], rel=LATERAL_TOLERANCE[kind])
    assert x == pytest.approx(expected["tip_x"], abs=ALONG_TOLERANCE[kind])
    assert result.info["negative_eigenvalues"][-1] == 0  # the stable, buckled branch


def test_the_load_path_reaches_the_same_elastica():
    # MindlinShell by 10 equal load steps: past Pcr the line search and the stability search
    # take it onto the buckled branch, to the same equilibrium as the arc length.
    model, tip, bending = imperfect_column("mindlin")
    result = Static(increments=10, progress=False).solve(model)
    expected = buckled_cantilever_column(
        LENGTH, 1.5 * math.pi**2 * bending / (4 * LENGTH**2), bending
    )
    x, _, z = result.positions[tip].mean(axis=0)
    assert z == pytest.approx(expected["lateral"], rel=LATERAL_TOLERANCE["mindlin"])
    assert x == pytest.approx(expected["tip_x"], abs=ALONG_TOLERANCE["mindlin"])


def _motion(direction, length: float, load: float) -> Motion:
    """A motion of one node along ``direction`` (3,) with this length and load change."""
    unit = np.asarray(direction, dtype=float) / np.linalg.norm(direction)
    return Motion(length * unit[None, :], np.zeros((1, 3)), load, size=1.0)


def test_a_step_is_capped_by_the_first_one_while_the_path_keeps_its_stiffness():
    # Crisfield's factor sqrt(5 / 2) would lengthen the step, but the load factor per length
    # stays within SOFTER of the first step's: the first step's length (1 / increments of
    # load) is the longest, as before.
    step = ArcStep(increments=10, aim=5)
    assert step.after(_motion((1, 0, 0), 1.0, 0.1), spent=2) == pytest.approx(1.0)
    softer = 0.1 / (0.9 * SOFTER)  # softer than the first step, but not SOFTER times
    assert step.after(_motion((1, 0, 0), 1.0, softer), spent=2) == pytest.approx(1.0)


def test_a_step_grows_with_the_path_once_it_has_softened():
    # A secant that carries 1e-3 of the first step's load per length: the cap is the length
    # that carries a load step of 1 / increments, so Crisfield's factor decides (x2 at one
    # iteration, x sqrt(5/4) at four).
    step = ArcStep(increments=10, aim=5)
    step.after(_motion((1, 0, 0), 1.0, 0.1), spent=2)
    assert step.after(_motion((1, 0, 0), 1.0, 1e-4), spent=1) == pytest.approx(2.0)
    assert step.after(_motion((1, 0, 0), 2.0, 2e-4), spent=4) == pytest.approx(2.0 * 1.25**0.5)
    # ... and never past a load step of 1 / increments: 0.02 of load factor on 2 mm allows 10
    # mm (Crisfield's 4 mm decides), 0.1 on 4 mm allows 4 mm.
    assert step.after(_motion((1, 0, 0), 2.0, 0.02), spent=1) == pytest.approx(4.0)
    assert step.after(_motion((1, 0, 0), 4.0, 0.1), spent=1) == pytest.approx(4.0)


def test_a_softened_path_that_turns_is_stepped_by_its_turn():
    # Past the first step's cap, a step is at most TURN_LIMIT / theta of the last where the
    # path turned by theta over it (here 0.5 rad); never below the first step's cap.
    step = ArcStep(increments=10, aim=5)
    step.after(_motion((1, 0, 0), 1.0, 0.1), spent=2)
    step.after(_motion((1, 0, 0), 4.0, 1e-3), spent=5)
    turned = _motion((math.cos(0.5), math.sin(0.5), 0.0), 4.0, 1e-3)
    assert step.after(turned, spent=5) == pytest.approx(4.0 * TURN_LIMIT / 0.5)
    sharp = _motion((-1.0, 0.2, 0.0), 4.0, 1e-3)
    assert step.after(sharp, spent=5) == pytest.approx(1.0)
    # A push along a buckling mode turns the path on purpose (here by 90 deg): not measured.
    assert step.after(_motion((0, 0, 1), 4.0, 1e-3), spent=5, pushed=True) == pytest.approx(4.0)


def test_crisfield_s_rule_counts_the_iterations_down_to_the_settled_ratio():
    # Iterations below SETTLED_RATIO are the tolerance's tail (one where Newton converges
    # quadratically, several at the round-off floor of stiff fibres): not counted.
    floor = [2.4e-2, 2.5e-6, 8e-7, 2.7e-7, 3.1e-7]
    assert SETTLED_RATIO == 1e-6
    assert iterations_spent(floor, count=4, chord_steps=0, tol=1e-8) == 2
    assert iterations_spent([1.0, 0.8, 5e-4, 3e-5, 3e-7], 4, 0, 1e-8) == 4
    assert iterations_spent([1e-2, 1e-5, 1e-10], 2, 0, 1e-8) == 2
    # The chord steps are not counted either (they do not factorise).
    assert iterations_spent([1e-1, 1e-3, 1e-4, 1e-5, 1e-7, 1e-9], 5, 2, 1e-8) == 3
    # A tolerance looser than the settled ratio is the gate.
    assert iterations_spent([1e-2, 1e-5, 1e-7], 2, 0, 1e-4) == 1
