"""The ply contact's normal law under Static as a primal-dual active set
(``PlyContact(static_law="active_set")``, elements/ply_active_set.py, docs/theory.md §9.3a
"An active set under Static"): the option's checks, the ramp's forces kept to the bit where
no quasi-static solver froze a set, the frozen set's tangent against central differences,
the set's rule, and the sag's equilibrium against the ramp's and the heavy elastica."""

import numpy as np
import pytest

from elements.plies import PlyStack
from elements.ply_active_set import ActiveSetPlyContactBlock, FrozenSides
from elements.ply_contact import PlyContact
from elements.ply_projection import penalty_law
from femcore import Mesh, interaction
from femcore.interaction_checks import check_force_is_energy_gradient, check_tangent
from femcore.state import State
from materials import Fabric
from solvers import Static
from solvers.common import ConvergenceError
from validation.references.elastica import heavy_cantilever

SAG = Fabric(thickness=1.0, areal_density=1e-9, tension=1e4, shear=1.0, bending=100.0)


def _pair(static_law: str, penalty: float | None = 100.0):
    """Two plies of SAG (0.5 mm each) on a 20 x 10 mm mid-surface of 4 x 2 cells: (stack,
    the compiled model, its ply contact)."""
    stack = PlyStack(
        Mesh.rectangle(20.0, 10.0, nx=4, ny=2), SAG, 2, penalty=penalty, static_law=static_law
    )
    model = stack.model().compile()
    return stack, model, model.interactions[0]


def _pressed(stack: PlyStack, depth, tilt: float = 0.0, jitter: float = 0.0) -> State:
    """The upper ply moved down by ``depth`` (mm, a number or a function of x) onto the lower
    one (its face ``depth`` into the lower ply's), the directors turned by ``tilt`` rad
    about y, the nodes moved by ``jitter`` mm at random."""
    x = stack.mesh.points.copy()
    upper = stack.ply_nodes[1]
    sink = depth(x[upper, 0]) if callable(depth) else depth
    x[upper, 2] -= sink
    x += jitter * np.random.default_rng(3).standard_normal(x.shape)
    d = np.zeros_like(x)
    d[:, 0], d[:, 2] = np.sin(tilt), np.cos(tilt)
    zero = np.zeros_like(x)
    return State(x, d, zero, zero)


# ---------------------------------------------------------------------- the option
@pytest.mark.parametrize(
    "changes, message",
    [
        ({"static_law": "semismooth"}, "static_law must be one of"),
        ({"static_law": None}, "static_law must be one of"),
        ({"static_law": "active_set", "friction": 0.2}, "frictionless flat faces only"),
        ({"static_law": "active_set", "surface": "curved"}, "frictionless flat faces only"),
    ],
)
def test_the_ply_contact_refuses_a_bad_static_law(changes, message):
    with pytest.raises(ValueError, match=message):
        PlyContact("upper", "lower", **changes)
    if "surface" not in changes:  # the stack takes no surface: its plies' faces are flat
        with pytest.raises(ValueError, match=message):
            PlyStack(Mesh.rectangle(10.0, 5.0, nx=2, ny=1), SAG, 2, **changes)


def test_the_option_binds_the_active_set_block():
    _, _, ramp = _pair("ramp")
    _, _, active = _pair("active_set")
    assert not isinstance(ramp, ActiveSetPlyContactBlock)
    assert isinstance(active, ActiveSetPlyContactBlock)


# ---------------------------------------------------------------------- the ramp kept
def test_without_a_frozen_set_the_forces_are_the_ramps_to_the_bit():
    """No quasi-static solver froze a set (the explicit solver and dynamic relaxation never
    do): the active-set block's forces, moments, energy and tangent are the ramped penalty's,
    bit for bit, with points past the ramp, on it and apart (depths -2 delta to +delta along
    the strip, directors tilted, nodes jittered)."""
    stack, _, ramp = _pair("ramp")
    _, _, active = _pair("active_set")
    delta = ramp.smoothing
    state = _pressed(stack, lambda x: delta * (4.0 * x / 20.0 - 1.0), tilt=0.02, jitter=1e-5)
    history = ramp.initial_history()
    touching = ramp.facing(state).touching
    gap = ramp.facing(state).gap
    assert (gap[touching] < -delta).any() and (gap[touching] > -delta).any() and (gap > 0).any()
    for got, expected in zip(
        active.internal_force(state, active.initial_history()), ramp.internal_force(state, history)
    ):
        assert np.array_equal(got, expected)
    assert active.strain_energy(state, active.initial_history()) == ramp.strain_energy(
        state, history
    )
    got_parts, expected_parts = active.tangent(state, history), ramp.tangent(state, history)
    for got, expected in zip(got_parts, expected_parts):
        assert np.array_equal(got.nodes, expected.nodes)
        assert np.array_equal(got.blocks, expected.blocks)


def test_thawed_the_law_is_the_plain_penalty():
    """``thaw`` (a state converged with its set frozen, checked under the unilateral law)
    gives the plain k/2 min(g, 0)^2: the energy sum over the touching points, whatever the
    ramp's width."""
    stack, _, active = _pair("active_set")
    delta = active.smoothing
    state = _pressed(stack, lambda x: delta * (3.0 * x / 20.0 - 1.0))
    frozen, _ = active.freeze(state, active.initial_history())
    thawed = active.thaw(frozen)
    assert isinstance(thawed, FrozenSides) and thawed.active is None
    facing = active.facing(state)
    on = np.asarray(facing.touching)
    expected = float(np.sum(penalty_law(facing.gap[on], active.stiffness[on], 0.0)[0]))
    assert active.strain_energy(state, thawed) == pytest.approx(expected, rel=1e-12)
    assert expected > 0.0


# ---------------------------------------------------------------------- the frozen set
def test_the_frozen_sets_tangent_is_the_derivative_of_its_loads():
    """A frozen set holding pressed points and points pulled apart (every other point of
    those that may touch, gaps -2 delta to +delta): k/2 g^2 on each, the forces the gradient
    of the energy and the tangent their derivative (femcore.interaction_checks, central
    differences of every node's translations and director turns; 1e-6 of the largest entry,
    as the ply contact's other checks)."""
    stack, _, active = _pair("active_set")
    delta = active.smoothing
    state = _pressed(stack, lambda x: delta * (4.0 * x / 20.0 - 1.0), tilt=0.02, jitter=1e-5)
    sides = active.initial_history()
    held, reachable = active._reachable(state, sides)
    chosen = reachable & (np.arange(len(reachable)) % 2 == 0)
    gap = np.asarray(held.gap)
    assert (gap[chosen] > 0).any() and (gap[chosen] < 0).any()
    history = FrozenSides(sides.sides, sides.faces, sides.corners, chosen, np.zeros(len(chosen)))
    assert check_tangent(active, state, history)
    check_force_is_energy_gradient(active, state, history)
    # the pulled points pull: the upper ply's force is not one-sided
    force = active.internal_force(state, history)[0]
    assert (force[stack.ply_nodes[1], 2] > 0).any() and (force[stack.ply_nodes[1], 2] < 0).any()


@pytest.mark.parametrize("jitter", [1e-5, 3e-4])
def test_the_compiled_loads_of_the_frozen_and_thawed_laws_are_numpys_to_the_bit(
    monkeypatch, jitter
):
    """The bilateral law of a frozen set (points pressed in and pulled apart, gaps -2 delta
    to +delta, directors tilted, nodes jittered) and the thawed plain penalty, summed by the
    compiled pass (elements/ply_load_kernels.py, ``law``) and by the numpy reference
    (``ply_projection.COMPILED = False``: ``_pair_loads``, ``_end_loads`` and
    ``np.bincount``): the same forces and moments to the bit."""
    from elements import ply_projection

    stack, _, active = _pair("active_set")
    delta = active.smoothing
    state = _pressed(stack, lambda x: delta * (4.0 * x / 20.0 - 1.0), tilt=0.02, jitter=jitter)
    sides = active.initial_history()
    held, reachable = active._reachable(state, sides)
    chosen = reachable & (np.random.default_rng(5).random(len(reachable)) < 0.6)
    gap = np.asarray(held.gap)
    assert (gap[chosen] > 0).any() and (gap[chosen] < 0).any()
    frozen = FrozenSides(sides.sides, sides.faces, sides.corners, chosen, np.zeros(len(chosen)))
    for history in (frozen, active.thaw(frozen)):
        compiled = active.internal_force(state, history)
        monkeypatch.setattr(ply_projection, "COMPILED", False)
        reference = active.internal_force(state, history)
        monkeypatch.setattr(ply_projection, "COMPILED", True)
        assert np.abs(reference[0]).max() > 0.0
        for got, expected in zip(compiled, reference):
            assert np.array_equal(got, expected)


def test_the_set_follows_the_primal_dual_rule():
    """The set's rule (elements/ply_active_set.py): a point joins where it penetrates; a
    pressed point stays while its gap has opened by less than it was pressed in, and leaves
    once it has opened by more."""
    stack, _, active = _pair("active_set")
    depth = 1e-3
    sides = active.initial_history()
    frozen, count = active.freeze(_pressed(stack, depth), sides)
    assert frozen.active.all() and count == len(frozen.active)
    assert np.allclose(frozen.pressure, active.stiffness * depth, rtol=1e-6)
    opened_less = _pressed(stack, -0.5 * depth)  # the faces 0.5 depth apart
    kept, changed = active.freeze(opened_less, frozen, grow=True)
    assert kept.active.all() and changed == 0
    opened_more = _pressed(stack, -1.5 * depth)
    left, changed = active.freeze(opened_more, frozen, grow=True)
    assert not left.active.any() and changed == len(frozen.active)
    apart, _ = active.freeze(_pressed(stack, -depth), sides)
    assert not apart.active.any()
    joined, changed = active.freeze(_pressed(stack, 0.5 * depth), apart, grow=True)
    assert joined.active.all() and changed == len(joined.active)


def test_the_rule_without_hysteresis_is_the_gaps_sign(monkeypatch):
    """``ACTIVE_SET_HYSTERESIS = False`` (femcore.interaction): the set is the points of g < 0
    at every iterate."""
    monkeypatch.setattr(interaction, "ACTIVE_SET_HYSTERESIS", False)
    stack, _, active = _pair("active_set")
    frozen, _ = active.freeze(_pressed(stack, 1e-3), active.initial_history())
    left, _ = active.freeze(_pressed(stack, -0.5e-3), frozen, grow=True)
    assert not left.active.any()


# ---------------------------------------------------------------------- the equilibrium
def test_the_sag_reaches_the_ramps_equilibrium():
    """tests/test_plies.py's sag (4 frictionless plies, 10 x 1 cells, Static in one
    increment) with the active set: every ply's tip on the heavy elastica within 5e-4 (that
    test's tolerance; measured 9.2e-5, the ramp 9.1e-5), and the nodes where the ramp's
    solve puts them within (N - 1) delta / 2, what the penetration laws' difference (at
    most delta / 2 an interface) moves N plies pressed straight on each other; measured
    7.4e-7 mm against that 3.75e-4 mm (the plies sag together with nearly no contact force,
    penetrating by nearly nothing under either law). Not a bound where the plies slide:
    on plies-heavy-cantilever's coarse stack the two laws' nodes differ by 3.6e-3 mm against
    (N - 1) delta / 2 = 2.25e-3, the slip built up along the strip
    (benchmarks/static_plies_active_set.py --case heavy)."""
    mid = Mesh.rectangle(100.0, 5.0, nx=10, ny=1)
    positions = {}
    for law in ("ramp", "active_set"):
        stack = PlyStack(mid, SAG, 4, static_law=law)
        model = stack.model()
        model.fix(stack.nodes("left"))
        model.gravity((0.0, 0.0, -9810.0))
        result = Static(increments=1, progress=False).solve(model)
        assert result.converged
        positions[law] = result.positions
    reference = heavy_cantilever(100.0, 1e-9 * 9810.0, 100.0)
    tips = positions["active_set"][stack.ply_nodes[:, mid.nodes("right")], 2].mean(axis=1)
    assert np.abs((stack.offsets - tips) / reference["tip_deflection"] - 1.0).max() <= 5e-4
    delta = 1e-3 * stack.ply_thickness  # the ramp's default width
    moved = np.abs(positions["active_set"] - positions["ramp"]).max()
    assert moved <= (stack.count - 1) * delta / 2


# ---------------------------------------------------------------------- the predicted set
def _sag_model(count: int, static_law: str):
    mid = Mesh.rectangle(100.0, 5.0, nx=10, ny=1)
    stack = PlyStack(mid, SAG, count, static_law=static_law)
    model = stack.model()
    model.fix(stack.nodes("left"))
    model.gravity((0.0, 0.0, -9810.0))
    return model


def test_the_set_models_gradient_gives_the_points_forces(monkeypatch):
    """``set_model``'s rows are dg/dq in the generalised unknowns: the change of the internal
    forces a predicted set makes, sum over the switched points of s k g G_i
    (solvers/contact_sets.py), is the change of the block's own forces and moments between
    the two sets (evaluated, taken to the generalised unknowns), within 1e-9 of its largest
    entry (measured 4.9e-11 on the 2- and 4-ply sags)."""
    import solvers.contact_sets as contact_sets

    original = contact_sets.predicted_sets
    mismatches: list[float] = []

    def checked(run, state, frames, factor, delta_free, left):
        out = original(run, state, frames, factor, delta_free, left)
        if out is not None:
            new, _, change = out
            dofs = run.model.dofs
            before = dofs.generalised(frames, *run.model.internal_force(state)).ravel()
            after = dofs.generalised(frames, *run.model.internal_force(new)).ravel()
            free = dofs.free.ravel()
            difference = (after - before)[free]
            scale = max(np.abs(difference).max(), np.abs(change[free]).max())
            if scale > 0.0:  # (plies laid at g = 0 switch with no force)
                mismatches.append(np.abs(difference - change[free]).max() / scale)
        return out

    monkeypatch.setattr(contact_sets, "predicted_sets", checked)
    result = Static(increments=1, progress=False).solve(_sag_model(2, "active_set"))
    assert result.converged and mismatches
    assert max(mismatches) <= 1e-9


def test_the_predicted_set_converges_the_sag_in_a_few_iterations():
    """The 2-ply sag of tests/test_plies.py in one increment: with the set predicted on each
    step's linear model, 7 Newton iterations (measured); the ramped penalty takes 23 and the
    set chosen between iterations alone 27 (docs/theory.md §9.3a), both refused by the bound
    of 10; the same tips as the ramp's within (N - 1) delta / 2."""
    from solvers import contact_sets

    counts, tips = {}, {}
    for law, predicted in (("ramp", True), ("active_set", False), ("active_set", True)):
        contact_sets.PREDICTED = predicted
        try:
            result = Static(increments=1, progress=False).solve(_sag_model(2, law))
        finally:
            contact_sets.PREDICTED = True
        assert result.converged
        counts[law, predicted] = result.info["iterations_per_increment"][0]
        tips[law, predicted] = result.positions
    assert counts["active_set", True] <= 10
    assert counts["ramp", True] > 10 and counts["active_set", False] > 10
    delta = 1e-3 * 0.5
    assert np.abs(tips["active_set", True] - tips["ramp", True]).max() <= delta / 2


def test_no_set_is_predicted_on_a_step_that_is_turned_downhill(monkeypatch):
    """A step on an indefinite tangent is turned downhill (``Static(seek_stable=True)``, the
    default) with the tangent and right-hand side of the sets it began with: the sets are not
    predicted on such a step, whose predicted state would belong to another system than the
    turn's. The 2-ply sag's first iterates are indefinite (the plies laid at g = 0: one
    prediction was made on one before)."""
    from solvers import contact_sets

    original = contact_sets.predicted_sets
    negatives: list[int] = []

    def recorded(run, state, frames, factor, delta_free, left):
        negatives.append(int(factor.negative))
        return original(run, state, frames, factor, delta_free, left)

    monkeypatch.setattr(contact_sets, "predicted_sets", recorded)
    result = Static(increments=1, progress=False).solve(_sag_model(2, "active_set"))
    assert result.converged and negatives
    assert max(negatives) == 0, negatives


def test_a_failed_attempt_of_the_active_set_is_cut_without_the_unilateral_attempt():
    """An attempt of the active set that fails is cut at once (its ``unilateral_fallback``
    is False): the plain penalty's unilateral attempt, which the tools' frozen sets fall back
    on, stalls on nearly force-free points (solvers/newton.py ``newton``)."""
    with pytest.raises(ConvergenceError) as failed:
        Static(increments=1, max_iterations=2, max_cuts=0, progress=False).solve(
            _sag_model(2, "active_set")
        )
    result = failed.value.result
    assert result is not None and not result.converged
    assert result.info["contact_set_fallbacks"] == 0


def _pushed_model(static_law: str):
    """Two plies of SAG (10 x 1 cells) clamped at the left end, their right end pushed down
    by 5 mm and in by 1 mm (an imposed motion), under gravity."""
    mid = Mesh.rectangle(100.0, 5.0, nx=10, ny=1)
    stack = PlyStack(mid, SAG, 2, static_law=static_law)
    model = stack.model()
    model.fix(stack.nodes("left"))
    model.displace(stack.nodes("right"), ux=-1.0, uz=-5.0)
    model.gravity((0.0, 0.0, -9810.0))
    return model


def test_a_phase_of_several_increments_opens_on_the_ramp(monkeypatch):
    """In Static's load path the first increment of a phase of several is taken with the
    ramped penalty, no set frozen (``opening_law = "ramp"``, solvers/newton.py
    ``opens_on_ramp``): two plies whose end is pushed, and the 4-ply sag, each in 3
    increments, take the ramp's own iterations there (the same count as with
    static_law="ramp"), then the predicted sets', and end at the equilibrium of the active
    set without the opening within 1e-9 mm (the round-off of a state reached by another
    path, measured 3.3e-14 and 6.7e-13; the two laws' own equilibria differ by 2.6e-4 and
    7.4e-7 mm). On these small stacks the opening costs iterations (measured 64-7-7 and
    28-7-4, the ramp 64-8-8 and 28-15-11, the active set throughout 32-7-7 and 9-8-4): the
    rule is for plies-bai-5.1's stacks, docs/theory.md §9.3a."""
    for model in (_pushed_model, lambda law: _sag_model(4, law)):
        runs = {}
        for name, law, opening in (
            ("ramp", "ramp", "ramp"),
            ("opened", "active_set", "ramp"),
            ("unopened", "active_set", None),
        ):
            monkeypatch.setattr(ActiveSetPlyContactBlock, "opening_law", opening)
            runs[name] = Static(increments=3, progress=False).solve(model(law))
            assert runs[name].converged
        counts = {name: run.info["iterations_per_increment"] for name, run in runs.items()}
        assert counts["opened"][0] == counts["ramp"][0] != counts["unopened"][0]
        opened, unopened = runs["opened"].positions, runs["unopened"].positions
        assert np.abs(opened - unopened).max() <= 1e-9
        assert np.abs(runs["ramp"].positions - unopened).max() > 1e-7
