"""Static on the inter-ply friction test forming engineers run first (docs/theory.md §6.5,
"Prescribed motion against stuck points"): two G986 plies (``g986_stack(2)``, 2 x 2 cells a
ply), Coulomb mu = 0.3 between them, the lower ply held, 1 N pressing the upper ply onto it
and the upper ply pulled 2 mm along x, its directors and uy free. Once it slides the pull is
Coulomb's mu F (the reference), and the supports carry the press: the sum of the z reactions
is the applied 1 N (statics, no model needed)."""

from types import SimpleNamespace

import numpy as np
import pytest

from elements.plies import PlyStack
from femcore import Mesh
from materials import presets
from solvers import Static, newton

MU, PRESS, PULL = 0.3, 1.0, 2.0  # -, N, mm
# How far the supports' z reactions may sum off the press. Every internal force sums to zero
# over the nodes (the plies' and the contact's forces are translation invariant, action and
# reaction), so the sum of the z reactions differs from the press by the sum of the free z
# rows of the residual: at most sqrt(9) ||r_F|| over the upper ply's nine nodes, and Static
# converges at ||r_F|| <= tol F_ref, tol = 1e-8 and F_ref (the norm of the internal forces,
# reactions included) 2.0-3.4 N at the end of these pulls, under 4 N: 3 x 1e-8 x 4 N.
# Measured 5e-13 to 6e-11 N.
BALANCE = 3 * 1e-8 * 4.0  # N


def _pulled(mu: float, press_first: bool = False):
    """(model, lower nodes, upper nodes): the pull of the module docstring at friction
    ``mu``."""
    stack = PlyStack(Mesh.rectangle(20.0, 20.0, nx=2, ny=2), presets.g986_stack(2), 2, friction=mu)
    model = stack.model()
    lower, upper = stack.ply_nodes
    model.fix(lower)
    amplitude = {"amplitude": "step"} if press_first else {}
    model.force(upper, (0.0, 0.0, -PRESS / len(upper)), **amplitude)
    model.displace(upper, ux=PULL)
    return model, lower, upper


def pulled(mu: float, press_first: bool = False, increments: int = 4):
    """(result, lower nodes, upper nodes): the upper ply pressed by PRESS and pulled PULL
    along x over the held lower one, in ``increments`` (each phase with ``press_first``)."""
    model, lower, upper = _pulled(mu, press_first)
    solver = Static(increments=increments, step_loads_first=press_first, progress=False)
    return solver.solve(model), lower, upper


@pytest.mark.parametrize("press_first", [False, True], ids=["together", "press_first"])
def test_a_pressed_ply_pulled_over_another_pulls_mu_times_the_press(press_first):
    """Every point of the upper ply slides, so the pull is mu times the sum of the points'
    normal forces, which the upper ply's vertical balance makes the press F to Newton's
    tolerance (1e-8 of the reference force); the points' slip directions lie off x by the
    draped ply's in-plane motion only (uy up to 3e-3 mm against 0.5 mm of slip an
    increment), cos 1 - 2e-5 at most: tolerance 1e-4 of mu F. Measured 1.2e-6 (pressed and
    pulled together, 12-6-6-5 Newton iterations an increment) and 2e-15 (pressed in 4
    increments, then pulled: 4-3-2-2). Before, the first Newton step of a pulled increment,
    on the tangent of the converged state where every point sticks, turned the free
    directors by 2 rad and Static stopped in its first increment (and in the first pull
    increment when pressed first)."""
    result, lower, upper = pulled(MU, press_first)
    assert result.converged
    pull = result.reactions[upper, 0].sum()
    assert pull == pytest.approx(MU * PRESS, rel=1e-4)
    assert np.all(np.asarray(result.info["iterations_per_increment"]) <= 15)
    assert result.reactions[lower, 2].sum() == pytest.approx(PRESS, abs=BALANCE)
    # Every attempt converges, each first step turns past the cap: neither the lift-off's
    # rule nor the retry changes a step.
    assert result.info["imposed_alone_retries"] == 0
    assert result.info["imposed_alone_opened"] == 0


@pytest.mark.parametrize("mu", [1.0, 2.5, 5.0])
def test_the_supports_of_pulled_plies_carry_the_press_and_the_pull_mu_times_it(mu):
    """At every increment of the pull the lower ply's supports carry the press applied so far,
    lambda F, within BALANCE (statics), and at its end the pull is mu F (Coulomb; 1e-4 as
    above, measured 1.1e-6-1.2e-6). The reactions are the converged state's: the commit moves
    each sliding point's anchor to the friction limit, where rounding counts some of them
    stuck, and their stick potential's lift (docs/theory.md §6.5, "Reactions of a frictional
    increment") made the supports' z reaction 1.013 N at mu 1, 1.088 at 2.5 and 1.58 at 5
    (1.0011 at mu 0.3), where the free DOFs' residual at the committed state was 7.6e-3,
    5.1e-2 and 0.33 N against 1e-11 N at the converged one."""
    result, lower, upper = pulled(mu)
    assert result.converged
    for frame in result.frames[1:]:
        carried = frame.reactions[lower, 2].sum()
        assert carried == pytest.approx(frame.load_factor * PRESS, abs=BALANCE)
    assert result.reactions[upper, 0].sum() == pytest.approx(mu * PRESS, rel=1e-4)


@pytest.mark.parametrize(
    ("increments", "mu", "press_first"),
    [(8, MU, False), (16, MU, False), (4, 1.5, False), (4, 2.0, False), (16, MU, True)],
    ids=["8 increments", "16 increments", "mu 1.5", "mu 2", "pressed first, 16 increments"],
)
def test_more_increments_or_more_friction_pull_mu_times_the_press(increments, mu, press_first):
    """The same pull in more increments or at a larger friction: mu F again. Static's
    converged residual is within 1e-8 of its force reference (about 2 N at the end: 2e-8 N,
    1e-7 of mu F at mu = 0.3), and the slip directions lie off x by the draped ply's in-plane
    motion (cos 1 - 2e-5 at most, above): tolerance 1e-4 of mu F. Measured 1.0e-6 to
    1.2e-6 pressed and pulled together, 1.3e-11 pressed first (DynamicRelaxation on the
    same model, 4 increments: 6.6e-5, 2.2e-5, 1.4e-5 at mu 0.3, 1.5, 2). A later
    increment's first step on the stuck tangent turns the directors under the update cap
    but lifts the ply off points that press it: its prescribed motion is applied alone
    (``info["imposed_alone_opened"]``: 1, 8, 1, 1, 5). Newton iterations per increment
    11-5-5-6-5-5-5-4; 11-5-5-4-4-5-5-5-5-5-4-4-4-4-4-4; 11-6-6-5; 11-6-6-5; the pull pressed
    first 4-3-3-2-2-2-2-2-2-2-2-2-2-1-1-1. Before, Static stopped after 8 cuts in the
    second increment (in the second pull increment pressed first)."""
    result, lower, upper = pulled(mu, press_first, increments)
    assert result.converged
    assert result.reactions[lower, 2].sum() == pytest.approx(PRESS, abs=BALANCE)
    pull = result.reactions[upper, 0].sum()
    assert pull == pytest.approx(mu * PRESS, rel=1e-4)
    assert np.all(np.asarray(result.info["iterations_per_increment"]) <= 15)


def test_an_attempt_that_fails_on_the_stuck_tangents_step_is_tried_again_with_the_motion_alone(
    monkeypatch,
):
    """Where the prediction misses (here switched off: the first step's lift-off never
    seen), the attempt on the stuck tangent's step fails and the increment is tried once
    more from its start with its prescribed motion applied alone before it is cut: the pull
    in 8 increments converges to mu F (tolerance 1e-4, above; measured 1.1e-6, the same
    bits as with the prediction: the retry's attempt is the predicted one) with one retry,
    11-29-5-6-5-5-5-4 Newton iterations an increment (the failed attempt's 24 counted); since
    the Mindlin plies' fibre curvature is the deformed fibre's (docs/theory.md §5.7), with
    two, in the second and fourth increments, 11-54-5-25-5-5-5-4, the same pull to 5e-12.
    Without the retry it stopped after 8 cuts in the second increment."""
    monkeypatch.setattr(newton, "opens_contact", lambda *_: False)
    result, _, upper = pulled(MU, increments=8)
    assert result.converged
    assert 1 <= result.info["imposed_alone_retries"] <= 2
    assert result.info["imposed_alone_opened"] == 0
    pull = result.reactions[upper, 0].sum()
    assert pull == pytest.approx(MU * PRESS, rel=1e-4)


def test_a_retry_that_fails_too_says_both_attempts_reasons(monkeypatch):
    """Where the attempt with the motion applied alone fails as well, the increment's
    failure (the cut's message, the final error) names both reasons and the retry, and
    counts both attempts' iterations (before, only the retry's reason was said)."""
    reasons = iter(["the line search found no step", "the residual stalled"])

    def failing(run, state, load_factor, max_iterations, frozen, history, *rest):
        history.extend([1.0, 0.5, 0.4])
        raise newton.IncrementFailed(next(reasons))

    monkeypatch.setattr(newton, "_iterate", failing)
    monkeypatch.setattr(newton, "imposes_alone", lambda model: True)
    monkeypatch.setattr(newton, "moves_prescribed", lambda run, state, load_factor: True)
    run = SimpleNamespace(info={"imposed_alone": 0, "imposed_alone_retries": 0}, model=None)
    with pytest.raises(newton.IncrementFailed) as failed:
        newton._newton(run, None, 0.5, None, False)
    said = str(failed.value)
    assert said.startswith("the residual stalled (tried again with the prescribed motion")
    assert said.endswith("first attempt's: the line search found no step)")
    assert failed.value.iterations == 4 and run.info["imposed_alone_retries"] == 1
