"""A ply laid on a ply held whole, clamped at one edge and pressed on it by its weight, solved
by Static at its default settings with the automatic penalty: wholly on the lower ply, and
overhanging its outline.

The plies start laid on each other (g = 0), where the smoothed penalty has no stiffness; the
first Newton step sees no contact and drops the upper ply through the lower one by its free
sag (2.5 mm at the full load, 5 ply thicknesses, 1e5 times the equilibrium's penetration),
and the line search's backtracking, which stopped at 1/64 of the step, failed the first
increment in 8 cuts on both models. From an increment's first iterate in a model with
interactions it now goes back as far as 1e-9 of the step (solvers/line_search.py,
``SMALLEST_FIRST_STEP``; benchmarks/ply_overhang.py has the figures)."""

from types import SimpleNamespace
from typing import Any

import numpy as np
import pytest

from elements import RigidPlane
from elements.plies import mindlin_ply
from elements.ply_contact import SMOOTHING
from femcore import Mesh, Model
from solvers import DynamicRelaxation, Static
from validation.studies.ply_overhang_setup import HALF, PLY, two_plies, upper_ply

# The smoothed penalty's ramp, mm: a pressed contact penetrates up to delta / 2 further than
# the plain penalty does, so the plies' faces are defined to about delta.
DELTA = SMOOTHING * 2.0 * HALF


def _upper(shift: float) -> np.ndarray:
    """The upper ply's nodes, 10 x 10 mm on 6 x 6 cells, its mid-surface at z = 0.5 (laid
    on the lower ply's upper face, z = 0.25), clamped at its edge of largest y."""
    return upper_ply(shift).points


def _two_plies(shift: float, **options: Any) -> tuple[Model, np.ndarray]:
    """The upper ply on a lower ply (20 x 20 mm, 4 x 4 cells, mid-surface z = 0) held
    whole (validation/studies/ply_overhang_setup.py); ``shift`` mm places the upper ply's
    edge of least y (-4: 4 mm past the lower ply's outline edge y = 0); ``options`` to the
    ply contact (friction, stick), the automatic penalty. Returns the model and the upper
    ply's node ids."""
    model, first, up = two_plies(shift, **options)
    return model, first + np.arange(len(up))


def test_a_ply_laid_on_a_ply_held_whole_rests_as_on_a_rigid_flat():
    """Wholly on the lower ply: Static's defaults converge, and the upper ply rests where
    its twin rests on a rigid plane at the lower ply's upper face (RigidPlane, node-to-plane
    penalty contact, an independent contact code): every node within delta (5e-4 mm, the
    smoothed penalty's own definition of the face) of the twin's. Measured: 3.5e-5 mm (both
    lie flat, the weight carried at penetrations of 3e-5 mm and less), in 39 Newton
    iterations (11 in the first increment). Static failed the first increment before (8
    cuts, the line search)."""
    model, upper = _two_plies(5.0)
    result = Static(progress=False).solve(model)
    assert result.converged and result.info["cuts"] == 0

    up = _upper(5.0)
    twin = Model(Mesh(up, triangles=Mesh.rectangle(10.0, 10.0, nx=6, ny=6).triangles))
    twin.add(mindlin_ply(PLY))
    twin.contact(RigidPlane((0.0, 0.0, HALF), (0.0, 0.0, 1.0)))
    twin.fix(np.flatnonzero(up[:, 1] >= up[:, 1].max() - 1e-9))
    twin.gravity((0.0, 0.0, -9810.0))
    rested = Static(progress=False).solve(twin)
    assert rested.converged
    assert np.abs(result.positions[upper] - rested.positions).max() <= DELTA


@pytest.mark.slow
def test_a_ply_overhanging_the_outline_of_a_ply_held_whole():
    """4 mm past the lower ply's outline edge, the overhang droops over it: Static's defaults
    converge (measured 17 Newton iterations in the first increment, 4 in the nine others,
    no cut) to the equilibrium dynamic relaxation finds on the same model (an independent
    solver, no tangent, stopped at a residual ratio of 1e-4): the upper ply's nodes within
    1e-3 of the tip's droop (9e-5 mm; measured 1.1e-5 mm, 1.2e-4 of the droop 0.090 mm).
    Static failed the first increment before (8 cuts, the line search)."""
    model, upper = _two_plies(-4.0)
    result = Static(progress=False).solve(model)
    assert result.converged and result.info["cuts"] == 0
    relaxed = DynamicRelaxation(progress=False).solve(_two_plies(-4.0)[0])
    assert relaxed.converged
    droop = 2.0 * HALF - relaxed.positions[upper, 2].min()
    assert droop > 0.05  # it hangs over the edge
    assert np.abs(result.positions[upper] - relaxed.positions[upper]).max() <= 1e-3 * droop


def test_friction_does_not_move_a_ply_pressed_flat_by_its_weight():
    """With Coulomb friction (mu = 0.2) between the plies and the ply contact's default stick
    spring, the normal law's (``stick="normal law"``: k_t = W''(g), elements/ply_friction.py),
    wholly on the lower
    ply: the load is normal, so the frictional equilibrium is the frictionless one up to what
    the friction can hold back, the in-plane motion of the upper ply's lower face in the
    frictionless answer (6.1e-6 mm, its directors turning near the clamp): every node within
    1e-5 mm of the frictionless answer (2 % of delta); measured 9.1e-7 mm (8.2e-7 before the
    stick spring derived from its potential, docs/theory.md). Static's defaults converge in 40
    iterations (frictionless 39). With the stick spring k_p at any normal force
    (``stick="penalty"``, the default before) the laid points, pressed 3e-5 mm
    deep on the smoothed penalty's ramp with N ~ 1e-5 N, switch between stick and slip on a
    cone of radius mu N / k_p ~ 1e-8 mm against the iterates' slips of 1e-7 mm, and the
    first increment fails (residual ratio 0.022 after 50 iterations, 8 cuts)."""
    frictionless, upper = _two_plies(5.0)
    reference = Static(progress=False).solve(frictionless)
    assert reference.converged
    model, _ = _two_plies(5.0, friction=0.2)
    result = Static(progress=False).solve(model)
    assert result.converged and result.info["cuts"] == 0
    assert np.abs(result.positions[upper] - reference.positions[upper]).max() <= 1e-5


def test_the_ply_contact_refuses_an_unknown_stick_spring():
    with pytest.raises(ValueError, match="stick must be one of"):
        _two_plies(5.0, friction=0.2, stick="normal")


def test_an_imposed_first_step_leaves_the_deep_backtracking_to_the_first_free_iterate(
    monkeypatch,
):
    """An increment whose first iterate imposes prescribed motion takes that step whole (it
    cannot back off); the deep backtracking of a model with interactions
    (solvers/line_search.py SMALLEST_FIRST_STEP) is then the next iterate's, the first that can
    fall through a contact its tangent does not hold."""
    import solvers.line_search as line_search

    model = SimpleNamespace(
        interactions=[object()],
        dofs=SimpleNamespace(free=np.ones((2, 5), bool)),
        internal_force=lambda state: None,
        reference_positions=np.zeros((2, 3)),
    )
    run = SimpleNamespace(model=model, counts={"residual": 0}, info={})
    residual = SimpleNamespace(residual=lambda *args: (np.zeros((2, 5)), 0.0, None))
    watchdog = line_search.Watchdog(run, residual, True)
    monkeypatch.setattr(line_search, "step_cap", lambda extent, delta, turn: 1.0)
    monkeypatch.setattr(watchdog, "_take", lambda state, frames, delta, cap: (1.0, state, None))
    ones = np.ones((2, 5))
    watchdog.step("imposed", None, ones, ones, True)
    watchdog.step("free", None, ones, ones, False)
    assert watchdog.best["deepest"] == line_search.SMALLEST_FIRST_STEP
    assert watchdog.deepest == line_search.SMALLEST_STEP  # the iterates after it: 1/64


def test_a_diverged_state_is_named_by_the_ply_contact():
    """A NaN position (a diverged state) gets one ValueError naming it from the ply contact,
    whatever the block's size (the small search returned empty rows and an IndexError came
    from deep inside the facing; a k-d tree gave scipy's message)."""
    compiled = _two_plies(5.0)[0].compile()
    state = compiled.initial_state()
    state.positions[-1, 2] = np.nan
    with pytest.raises(ValueError, match="NaN or infinite"):
        compiled.interactions[0].facing(state)
