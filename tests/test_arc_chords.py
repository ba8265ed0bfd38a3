"""Chord steps of the arc-length path (``Static(arc_chords=...)``, solvers/arc_length.py,
docs/theory.md §6.6 "Chord steps"): iterations at small residual ratios step with the
increment's last factorisation; the path and its equilibria stay those of the closed forms."""

import pytest

from solvers import Static
from tests.test_static import (
    _von_mises_truss,
    assert_on_the_truss_closed_form,
    truss_limit_loads,
)
from validation.references.elastica import tip_loaded_cantilever
from validation.specimens import mindlin_strip


def test_chord_steps_keep_the_truss_on_its_closed_form_path_and_its_limit_points():
    # The von Mises truss of tests/test_static.py, followed over both limit points: with chord
    # steps every frame still lies on the closed form t(w) = 6 lambda to the 1e-6 of the plain
    # path (the residual is exact; the tolerance, 1e-8 of the forces, is far below it), the
    # unstable frames are those with dt/dw < 0 (their inertia read from a factorisation of their
    # own increment), the two limit loads those of the closed form to the step's resolution;
    # the chords replace tangents (189 -> 122 when this was written).
    model, rise, _, travel = _von_mises_truss()
    plain = Static(increments=12, path="arc_length").solve(model)
    result = Static(increments=12, path="arc_length", arc_chords=1e-3).solve(model)
    assert plain.info["arc_chords"] == 0 and result.info["arc_chords"] > 0
    assert result.info["evaluations"]["tangent"] < 0.8 * plain.info["evaluations"]["tangent"]
    assert_on_the_truss_closed_form(result, rise, travel)


def test_chord_steps_bend_the_cantilever_to_the_elastica():
    # A Mindlin strip under a tip load P L^2 / EI = 3 along the arc length: with chord steps
    # its tip lands where it lands without them to 1e-6 of the length (both within the
    # tolerance of one equilibrium), and both on the elastica's (Bisshopp and Drucker's closed
    # form, validation.references.elastica) within the 1 % the 20-cell strip gives.
    length, width, thickness, young = 100.0, 10.0, 1.0, 1e5
    mesh, model = mindlin_strip(length, width, thickness, young, cells=20)
    bending = young * width * thickness**3 / 12
    tip = mesh.nodes("right")
    model.force(tip, (0.0, 0.0, -3.0 * bending / length**2 / len(tip)))
    plain = Static(increments=4, path="arc_length").solve(model)
    chords = Static(increments=4, path="arc_length", arc_chords=1e-3).solve(model)
    assert chords.info["arc_chords"] > 0
    assert chords.positions[tip] == pytest.approx(plain.positions[tip], abs=1e-6 * length)
    reference = tip_loaded_cantilever(length, 3.0 * bending / length**2, bending)
    x, _, z = chords.positions[tip].mean(axis=0)
    assert x == pytest.approx(reference["tip_x"], rel=0.01)
    assert -z == pytest.approx(reference["tip_deflection"], rel=0.01)


@pytest.mark.parametrize("bad", [-1e-3, float("nan"), "1e-3", None])
def test_arc_chords_must_be_a_non_negative_ratio(bad):
    with pytest.raises(ValueError, match="arc_chords must be a non-negative number"):
        Static(path="arc_length", arc_chords=bad)


@pytest.mark.parametrize("increments", range(3, 21))
def test_the_largest_chord_ratio_keeps_both_limit_points_of_the_truss(increments):
    # The truss again at the largest ratio Static accepts (LARGEST_CHORD_RATIO): whatever the
    # increments, the path passes both limit points of the closed form t(w) = 6 lambda, each
    # recorded within 5 % of its load (a limit is recorded at the frame where the load turns,
    # so to a step's resolution: the path without chords records them up to 2 % off at these
    # increments, with chords at 1e-2 up to 3.7 %, the second limit at 20 increments, when
    # this was written). At arc_chords 0.5, which Static now refuses, a step jumped from the
    # near branch onto the far one past the unstable part and the path failed beyond both.
    model, rise, _, travel = _von_mises_truss()
    result = Static(increments=increments, path="arc_length", arc_chords=1e-2).solve(model)
    first_limit, second_limit = truss_limit_loads(travel)
    limits = result.info["limit_points"]
    assert len(limits) == 2
    assert limits[0] == pytest.approx(first_limit, abs=0.05 * abs(first_limit))
    assert limits[1] == pytest.approx(second_limit, abs=0.05 * abs(second_limit))


@pytest.mark.parametrize("too_large", [0.011, 0.5, 5.0])
def test_arc_chords_above_the_largest_ratio_is_refused(too_large):
    with pytest.raises(ValueError, match="arc_chords must be at most 0.01"):
        Static(path="arc_length", arc_chords=too_large)


@pytest.mark.parametrize(
    "option",
    [
        {"arc_chords": 1e-3},
        {"arc_iterations": 8},
        {"max_increments": 50},
        {"at_limit": "jump"},
    ],
)
def test_the_arc_length_options_are_refused_on_the_load_path(option):
    # The load path does not read them: given with it, they were silently ignored.
    ((name, value),) = option.items()
    with pytest.raises(ValueError, match=rf"{name}={value!r} given with path='load'.*arc_length"):
        Static(**option)
    Static(path="arc_length", **option)


def test_the_arc_length_options_at_their_defaults_pass_on_the_load_path():
    Static(arc_chords=0.0, arc_iterations=5, max_increments=None, at_limit="follow")
