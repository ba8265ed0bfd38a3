"""Newton-Raphson at one load factor for the static solver (solvers.static.Static), with the
watchdog line search on the total potential energy and the residual (docs/theory.md §6.5).

Unknowns per node: ux uy uz and, at shell nodes, alpha beta: small rotations of the director
about V2 and V1 of its nodal frame (Bai Eq. 7, 13; docs/theory.md §1.3), applied as finite
rotations.

Each Newton iteration:

- tangent: the blocks' own ``tangent`` where they give one, assembled in the generalised
  coordinates of femcore.dofs by femcore.assembly; for the other blocks, K = dF_int/dq by
  central differences with a colouring of the node graph (femcore.assembly.NodeGraph), 10 x
  (number of colours) force evaluations whatever the mesh size (``Tangent``);
- linear solve: an LDL^T of K_ff whose symbolic factorisation is kept between iterations
  (solvers.linear), its negative pivots counting the negative eigenvalues of K_ff
  (solvers.stability turns the steps on an indefinite tangent downhill);
- line search (load path), a watchdog (Chamberlain, Powell, Lemarechal and Pedersen, Math.
  Prog. Study 16 (1982) 1; solvers.line_search): full Newton steps are taken as long as, within
  WATCHDOG iterations, one of them lowers the residual norm below that of the best iterate so
  far or the total potential energy (by the Armijo fraction of the first-order decrease of the
  step that left the best iterate; the energy is evaluated only when the residual does not show
  the decrease). Otherwise the iteration goes back to the best iterate and backtracks along its
  Newton step (halving, down to 1/64; from the increment's first iterate in a model with
  interactions, or the first after its contact sets changed, down to 1e-9,
  ``SMALLEST_FIRST_STEP``: a contact the first tangent does not hold, plies laid on each other
  under a smoothed penalty, lets the step run into it by the ratio of the penalty to the
  structure's stiffness) until one of the two falls; when none does, the line search says no
  and the increment is cut. Full steps first because the first iterations of a large rotation
  climb the energy on the way (the straight update stretches the membrane) and still reach the
  equilibrium in a few steps, where a monotone line search would crawl.

Curved steps (``Static(curved=True)``, the default; solvers.newton_curvature): a step on a
definite tangent gets the second-order term of its path, so that the straight update no
longer stretches a turning strip by theta^2 / 2; the line search backtracks along the straight
step.

Fibre-length projection (``Static(fibre_projection=True)``, the default;
solvers.newton_fibres): each step's end, curved or not, is moved back onto the fibre lengths
its first order asks for, on the blocks that give fibre edges (a fabric's nearly inextensible
warp and weft lines).

Chord corrections (``Static(chords=N)``, one by default, ``chord_corrections``): after a
whole step, up to N steps K^-1 r with the factorisation just made, each kept while it lowers
the total potential energy: where the straight update of a turning strip has stretched it (or
a curved step left its third-order remainder), they take the membrane back at the cost of a
solve and two evaluations each, instead of a tangent and its factorisation.

Contact (the active-set strategy of implicit contact codes; elements/contact.py): the contact
sets of the interactions (which nodes touch, which stick, which slide and in what direction)
are frozen at the start of the increment, so that the contact forces are smooth and the tangent
exact while Newton iterates: the unilateral law would lose every node of a cable sliding over a
curved tool at each linearised step (the straight step lifts it by s^2 / 2R, more than the
penalty's penetration), and the return mapping's slip direction turns over wherever a node
reverses. A node that penetrates joins the set at once, and a frozen node more than the body's
thickness off the tool and facing another feature of it (its normal turned) leaves it
(elements/contact.py, ``Contact(release=..., release_turn=...)``): joining at a touch and
leaving a thickness away, the set does not chatter. A state that
converges is checked under the unilateral law; when the sets were wrong, the solve goes on with
the sets that state shows, from that state when its residual is already below that of the
increment's first iterate, else from the start of the increment (a node held by its stick
spring where it slides leaves a state far off). After MAX_CONTACT_UPDATES wrong sets the
increment goes on with the unilateral law itself, which settles the nodes whose contact force
is near zero (a lift-off) where frozen sets alternate; at once where only the stick and slip
states were wrong (solvers.slip_sets).

Contact sets predicted (solvers.contact_sets): where an interaction's set is an active set of a
bilateral penalty (the ply contact's ``static_law="active_set"``, elements/ply_active_set.py; a
tool contact's frozen set, elements/contact_set_model.py), the set of each step's
end is chosen on the step's own linear model before the step is taken (the switched points'
rank-one terms by Sherman-Morrison-Woodbury on the factors made), so that the step and its set
agree; the line search starts again from the new set. An attempt of such an interaction that
fails is cut without the unilateral attempt (its ``unilateral_fallback``); one of a tool's
contact is tried again with the sets chosen between iterations alone before the unilateral
attempt (``_unpredicted``). The first increment of a phase of several increments of the load
path (``run.opening``, set by solvers.load_path) is iterated with such interactions' own
explicit law instead, no set frozen (``opening_law = "ramp"``: the ply contact's ramped
penalty): there plies laid at g = 0, or an imposed step that carries hundreds of points through
the ply below, change the set by hundreds of points an iterate and the predicted sets stall;
the later increments freeze and predict their sets from the state it reached (docs/theory.md
§9.3a).

Stalled attempts (``Static(stall_iterations=N)``, off by default; ``stalled``): an attempt
whose residual ratio stayed above STALLED_RATIO over its last N iterations is cut at once.

Prescribed motion against stuck points (solvers.imposed_alone): with the plies' friction, the
first iteration of an increment applies its prescribed motion alone, the free unknowns held,
where the first step turns a director past the update cap or lets go of a touching point, and
on a second attempt where the first attempt with the coupled step fails (``_newton``;
docs/theory.md §6.5).

Increments sized by their first step (``Static(first_turn=theta)``, off by default;
``StepTooLong``): with ``newton(turn_limit=theta)`` an attempt whose first Newton step turns a
director by more than theta stops before the update, and the load path (solvers.load_path) cuts
the increment to the share whose first step turns none by more.

Convergence is the force-reference test of solvers.convergence (``Residual``), no stricter than
the residual's rounding at the iterate (solvers.round_off).
"""

from __future__ import annotations

from dataclasses import replace
from typing import TYPE_CHECKING

import numpy as np
import scipy.sparse as sp

from femcore.assembly import FreeTangentAssembler, TangentPart
from femcore.dofs import N_COLUMNS, Frames
from femcore.interaction import InteractionBlock
from femcore.model import CompiledModel
from femcore.state import State
from solvers import contact_sets
from solvers.common import IncrementFailed, StepTooLong
from solvers.convergence import Equilibrium
from solvers.floor_acceptance import note_floor_acceptance
from solvers.imposed_alone import imposes_alone, moves_prescribed, opens_contact
from solvers.inertia import convexified_step
from solvers.line_search import Watchdog
from solvers.linear import Factorisation
from solvers.neutral_modes import unstable_modes
from solvers.newton_chords import chord_corrections
from solvers.newton_curvature import curved_step
from solvers.round_off import RoundOffFloor
from solvers.saddles import judged
from solvers.slip_sets import release_slips, slips_alone
from solvers.stabilisation import Dashpots
from solvers.stability import downhill, lowest_modes
from solvers.stop_diagnosis import iterations_spent

if TYPE_CHECKING:
    from solvers.static import StaticRun

__all__ = [
    "COMPRESSION_FREE",
    "STALLED_RATIO",
    "IncrementFailed",
    "StepTooLong",
    "Residual",
    "Tangent",
    "at_round_off_floor",
    "chord_corrections",
    "compression_free_ratio",
    "keeps_contact_sets",
    "mechanism",
    "newton",
    "stalled",
]

# How many times an increment may find its contact sets wrong at convergence and solve again
# with new ones; then it goes on with the unilateral law itself (a semi-smooth Newton), which
# settles the nodes whose contact force is near zero (the lift-off of a wrapped strip), where
# the frozen sets would alternate.
MAX_CONTACT_UPDATES = 3
# ``Static(stall_iterations=N)``: an attempt whose residual ratio stayed above this over its
# last N iterations is cut at once (``stalled``; docs/theory.md §6.5, "Stalled attempts").
STALLED_RATIO = 0.1
# The residual ratio above which the fibrous shell's tangent leaves its fibres' compression out
# of its stress terms by default (``Static(compression_free=None)``; docs/theory.md §6.5).
COMPRESSION_FREE = 1e-2


def newton(
    run: StaticRun,
    state: State,
    load_factor: float,
    max_iterations: int | None = None,
    turn_limit: float | None = None,
):
    """Newton-Raphson at one load factor from ``state``.

    Returns (converged state, iterations, final ratio, ratio per iteration starting with
    the ratio before the first update); raises IncrementFailed when the increment has to be
    cut. With contact, the frozen contact sets first (module docstring); where they fail,
    the unilateral law from ``state`` again before the increment is cut (the iterations of
    both are counted), unless no interaction keeps a contact set (``keeps_contact_sets``),
    when the two attempts would be one, or every one that keeps a set says its unilateral law
    stalls (``unilateral_fallback = False``: the ply contact's active set). ``turn_limit``
    (rad): StepTooLong, before any update, when the first Newton step turns a director by
    more (Static's ``first_turn``, solvers.load_path).
    """
    if not run.model.interactions:
        return _newton(run, state, load_factor, max_iterations, False, turn_limit)
    if getattr(run, "opening", False) and opens_on_ramp(run.model):
        # The phase's first increment on the set-keeping interactions' ramp (module
        # docstring): no set frozen, so no unilateral attempt either; a tool's contact in
        # the model takes its unilateral law in this increment too (docs/theory.md §9.3a).
        released = replace(state, history=on_ramp(run.model, state.history))
        return _newton(run, released, load_factor, max_iterations, False, turn_limit)
    predicted = run.info.get("predicted_sets", 0)
    try:
        return _newton(run, state, load_factor, max_iterations, True, turn_limit)
    except StepTooLong:
        raise
    except IncrementFailed as failure:
        failure.predicted = run.info.get("predicted_sets", 0) - predicted
        # Without a contact set to freeze (only interactions such as the plies' contact, whose
        # force is decided by the gaps alone) the unilateral attempt would repeat the frozen
        # one iteration for iteration and fail alike: the increment is cut at once.
        if not keeps_contact_sets(run.model):
            raise
        # Nor where each set-keeping interaction's unilateral law is known to stall
        # (``unilateral_fallback = False``: the ply contact's active set, whose unilateral law
        # is the plain penalty; elements/ply_active_set.py).
        if not any(
            part.unilateral_fallback for part in run.model.interactions if part.keeps_contact_sets
        ):
            raise
        if predicted_in(run, failure):
            try:
                return _unpredicted(run, state, load_factor, max_iterations, turn_limit, failure)
            except StepTooLong:
                raise
            except IncrementFailed as again:
                failure = again
        run.info["contact_set_fallbacks"] += 1
        try:
            converged, count, ratio, history = _newton(
                run, state, load_factor, max_iterations, False
            )
        except IncrementFailed as fallback:
            fallback.iterations += failure.iterations  # both attempts' iterations
            raise
        return converged, count + failure.iterations, ratio, failure.history + history


def predicted_in(run: StaticRun, failure: IncrementFailed) -> bool:
    """Whether the failed frozen attempt ``failure`` predicted a contact set
    (solvers/contact_sets.py; its count in ``run.info`` rose since the attempt began, kept on
    the failure by ``newton``) and the sets are predicted at all."""
    return bool(failure.predicted) and not run.sets_unpredicted


def _unpredicted(run, state, load_factor, max_iterations, turn_limit, failure):
    """The frozen attempt again with the contact sets chosen between iterations alone, not
    predicted (``run.sets_unpredicted``): a prediction is a path, and where the linear model's
    set misleads the steps (a node pressed into a meshed tool's crease, where the normal the
    rows take turns between facets: the Mindlin drape of tests/test_hemisphere_static.py
    stopped at load factor 0.41 with it) the sets chosen on the iterates still converge.
    Returns as ``newton``; the failure carries both attempts' iterations."""
    run.info["unpredicted_retries"] += 1
    run.sets_unpredicted = True
    try:
        converged, count, ratio, history = _newton(
            run, state, load_factor, max_iterations, True, turn_limit
        )
    except IncrementFailed as again:
        again.iterations += failure.iterations
        again.history = failure.history + again.history
        raise
    finally:
        run.sets_unpredicted = False
    return converged, count + failure.iterations, ratio, failure.history + history


def compression_free_ratio(ratio: float | None, model: CompiledModel) -> float:
    """The residual ratio above which the iterations take the compression-free tangent: the
    solver's own ``ratio`` (``Static.compression_free``), or for None COMPRESSION_FREE on a
    model with a block that offers that tangent and no interaction (with contact the
    hemisphere drape cut more increments with it), else 0 (never)."""
    if ratio is not None:
        return ratio
    offered = any(block.compression_free_tangent for block in model.blocks)
    return COMPRESSION_FREE if offered and not model.interactions else 0.0


def keeps_contact_sets(model: CompiledModel) -> bool:
    """Whether an interaction of ``model`` has contact sets that the iterations freeze
    (``InteractionBlock.keeps_contact_sets``: the tools' contact and the ply contact's active
    set, elements/ply_active_set.py): without one,
    the frozen iterations of ``newton`` are those of the unilateral law itself."""
    return any(part.keeps_contact_sets for part in model.interactions)


def _opening_on_ramp(part: InteractionBlock) -> bool:
    """Whether the interaction ``part``'s law under Static opens each phase of the load path
    with its explicit law (``opening_law == "ramp"``, its history ``released``: the ply
    contact's active set, elements/ply_active_set.py)."""
    return part.opening_law == "ramp"


def opens_on_ramp(model: CompiledModel) -> bool:
    """Whether ``model`` has a set-keeping interaction that opens each phase on its ramp
    (``_opening_on_ramp``)."""
    return any(_opening_on_ramp(part) for part in model.interactions)


def on_ramp(model: CompiledModel, history: tuple) -> tuple:
    """``history`` with each interaction that opens on its ramp (``opens_on_ramp``) given its
    history without a set or its marker (its ``released``): its forces the ramp's."""
    first = len(model.parts) - len(model.interactions)
    entries = list(history)
    for i, part in enumerate(model.interactions):
        if _opening_on_ramp(part):
            entries[first + i] = part.released(entries[first + i])
    return tuple(entries)


def curves_with_contact(model: CompiledModel, history: tuple) -> bool:
    """Whether ``Static(curved_with_contact=True)`` curves the steps of ``model`` at a state
    of ``history``: no interaction keeps contact sets (the tools' contact and the ply
    contact's active set do: their steps are never curved) or a history
    beyond the gaps' (the plies' friction: its return mapping may cross a stick limit on a
    probe of the path; on a frictional two-ply deck 54 curved steps took 302 iterations cut
    against 47 uncurved). The plies' sides (``InteractionBlock.gaps_decide``,
    elements/ply_block.py), held through an increment, count as none."""
    if keeps_contact_sets(model):
        return False
    first = len(model.parts) - len(model.interactions)
    return all(
        part.gaps_decide(entry)
        for part, entry in zip(model.interactions, history[first:], strict=True)
    )


def _newton(
    run: StaticRun,
    state: State,
    load_factor: float,
    max_iterations: int | None,
    frozen: bool,
    turn_limit: float | None = None,
):
    """``newton`` with the contact sets frozen or not; a failure carries the attempt's
    iterations and residual ratios. In a model whose prescribed motion may be applied alone
    (``imposes_alone``), an attempt whose first step took that motion with the free unknowns
    and that fails is tried once more from ``state`` with the motion applied alone at its
    first iteration, before the increment is cut (``info["imposed_alone_retries"]``; the
    iterations and ratios of both attempts are counted; docs/theory.md §6.5, "Prescribed
    motion against stuck points")."""
    history: list[float] = []
    applied_alone = run.info["imposed_alone"]
    try:
        return _iterate(run, state, load_factor, max_iterations, frozen, history, turn_limit)
    except StepTooLong as long:
        long.iterations, long.history = 0, history
        raise
    except IncrementFailed as failure:
        failure.iterations, failure.history = max(len(history) - 1, 0), history
        # The retry only where the first attempt's first step was not already the motion
        # alone (then the retry would repeat it bit for bit) and the increment moves
        # prescribed unknowns (without, ``_iterate`` has nothing to apply alone).
        if run.info["imposed_alone"] != applied_alone or not imposes_alone(run.model):
            raise
        if not moves_prescribed(run, state, load_factor):
            raise
        failed = failure
    run.info["imposed_alone_retries"] += 1
    again: list[float] = []
    try:
        converged, count, ratio, _ = _iterate(
            run, state, load_factor, max_iterations, frozen, again, turn_limit, True
        )
    except IncrementFailed as failure:
        failure.iterations = failed.iterations + max(len(again) - 1, 0)
        failure.history = history + again
        # both attempts' reasons: the cut's message and the final error say a retry happened
        failure.args = (
            f"{failure} (tried again with the prescribed motion applied alone after the "
            f"first attempt's: {failed})",
        )
        raise
    return converged, failed.iterations + count, ratio, history + again


def _iterate(
    run: StaticRun,
    state: State,
    load_factor: float,
    max_iterations: int | None,
    frozen: bool,
    history: list[float],
    turn_limit: float | None = None,
    alone_first: bool = False,
    escapes: int = 0,
):
    """The Newton iterations of ``newton``; ``history`` receives the residual ratios.
    ``alone_first``: the increment's prescribed motion applied alone at the first iteration
    whatever its first step turns (``_newton``'s retry). ``escapes``: the saddles of this
    increment ``state`` was pushed off so far (``_escape``); its steps are turned downhill."""
    solver = run.solver
    model = run.model
    dofs = model.dofs
    equilibrium = run.equilibrium(load_factor)
    index, moved_index = dofs.free_slots, dofs.prescribed_slots
    size = model.element_size
    singular = False
    factor: Factorisation | None = None
    forces = None  # the internal forces of the accepted trial, reused next iteration
    watchdog = Watchdog(run, equilibrium, solver.line_search, solver.update_turn)
    allowed = max_iterations or solver.max_iterations
    # The tools' prescribed motions are where the load factor puts them from the first
    # iteration on (a tool is placed by ``state.load_factor``).
    state = replace(state, load_factor=load_factor, time=load_factor)
    # The contact sets stay frozen while Newton iterates (module docstring).
    if frozen:
        state, _ = model.freeze(state)
    start = state
    updates = 0
    # The residual's round-off floor (solvers.round_off): measured once an iterate is within
    # ROUND_OFF_GATE, on models whose forces a rigid translation leaves as they are.
    rounding = RoundOffFloor(solver.tol, not model.interactions and run.dashpots is None, run.info)
    alone = imposes_alone(model)

    def resume(pushed: State):
        """Newton from a saddle's push (solvers.saddles.judged), its steps turned downhill."""
        more: list[float] = []
        return _iterate(run, pushed, load_factor, max_iterations, frozen, more, escapes=escapes + 1)

    for iteration in range(1, allowed + 1):
        frames = dofs.frames(state.directors)
        if frozen:
            # A node that penetrates joins the frozen set at once, one more than a thickness off
            # the tool leaves it (no chatter in between); one just pulled off waits for the
            # converged check.
            state, grown = model.freeze(state, grow=True)
            if grown:
                forces = None
                watchdog = Watchdog(run, equilibrium, solver.line_search, solver.update_turn)
        r, ratio, forces = equilibrium.residual(state, frames, forces)
        left = equilibrium.remaining(state)
        history.append(ratio)
        if not np.isfinite(ratio):
            raise IncrementFailed("non-finite residual")
        if stalled(history, solver.stall_iterations):
            window = solver.stall_iterations
            raise IncrementFailed(
                f"the residual ratio stayed above {STALLED_RATIO:g} for {window} iterations"
            )
        tol = rounding.tolerance(ratio, equilibrium, state, frames, r, forces)
        settled_here = ratio <= tol and np.abs(left).max(initial=0.0) <= 1e-9 * size
        run.info["round_off_converged"] += int(settled_here and ratio > solver.tol)
        if settled_here:
            unfrozen: State | None = state
            if frozen:
                unfrozen, ratio = settle_contacts(model, equilibrium, state, frames, solver.tol)
            if unfrozen is None:  # converged with the wrong contact set: a new one
                updates += 1
                near = len(history) > 1 and ratio < history[1]
                slips = slips_alone(model, state, run.info)  # the return mapping finishes
                state, forces, watchdog = refreeze(run, equilibrium, start, state, near)
                if slips:  # the stick and slip states to the return mapping
                    state = release_slips(model, state)
                elif updates >= MAX_CONTACT_UPDATES:  # nodes at zero force (module docstring)
                    state, frozen = model.thaw(state), False
                continue
            state = unfrozen
            state, escape = judged(run, equilibrium, state, factor, load_factor, escapes, resume)
            if escape is None:
                return state, iteration - 1, ratio, history
            return state, iteration - 1 + escape[0], escape[1], history + escape[2]
        # Far from equilibrium the fibres' compression is left out of the fibrous tangent's
        # stress terms (docs/theory.md §6.5); near it, and at every converged state whose
        # stability is judged, the tangent is exact.
        # The first iterate of an increment starts from a converged state (or a predictor
        # of one): its fibres' compression is real, not a step's remainder, and there the
        # exact tangent is kept (a corner lowered by 40 mm, benchmarks/static_solver.py
        # line 1: 4-4-6-4 iterations with the compression-free tangent there, 4-4-4-4
        # without); so is the compression of the last converged state at the later iterates
        # (a column carries its load in compression: elements/fibrous/compression_floor.py;
        # not the increment's start, which a predictor extrapolates: a straight update
        # shortens turning fibres).
        slack = 0.0 < run.compression_free < ratio and iteration > 1
        run.info["compression_free_tangents"] += int(slack)
        k_ff, k_fp = run.tangent(state, frames, slack, run.state if slack else None)
        rhs = r.ravel()[index]
        if moved_index.size:
            rhs = rhs - k_fp @ left.ravel()[moved_index]
        factor = run.factorise(k_ff)
        # An exact tangent's negative pivot on the way (StaticRun.note_jump); not the
        # compression-free one's, which is not the state's.
        run.met_indefinite |= bool(factor.negative) and not slack
        delta_free = factor.solve(rhs)
        regularised = delta_free is None
        if delta_free is None:
            # Exactly singular: a straight stress-free cable or membrane has no transverse
            # stiffness until it sags. A spring of 1e-6 x the largest diagonal on every
            # free unknown, for this update only, gives a finite step; the residual stays
            # exact, so a converged state is still an exact equilibrium. A mechanism or a
            # rigid motion under load keeps failing and is reported as singular.
            shift = 1e-6 * np.abs(k_ff.diagonal()).max(initial=0.0)
            factor = run.factorise(k_ff + shift * sp.identity(index.size, format="csc"))
            delta_free = factor.solve(rhs)
            singular = True
            run.info["regularised_iterations"] += 1
            if delta_free is None:
                raise IncrementFailed(f"singular tangent stiffness: {mechanism(model)}")
        if alone and iteration == 1 and np.abs(left).max(initial=0.0) > 0.0:
            # The tangent of the converged state holds every touching point stuck, and its
            # linear step may take the prescribed motion up where the stick springs are softest:
            # a pulled ply's free directors turned 2 rad for 0.5 mm. Where it turns a director
            # past the update cap or lets go of a touching point, the increment's prescribed
            # motion is applied alone, the free unknowns held, and the return mapping at the
            # moved state says which points slide (solvers/imposed_alone.py; docs/theory.md
            # §6.5, "Prescribed motion against stuck points").
            turns = np.zeros((model.n_nodes, N_COLUMNS))
            turns.ravel()[index] = delta_free
            turned_past = np.linalg.norm(turns[:, 3:], axis=1).max(initial=0.0) > watchdog.turn
            opened = False
            if not (alone_first or turned_past):
                linear = left.ravel().copy()
                linear[index] = delta_free
                step = linear.reshape(-1, N_COLUMNS)
                opened = opens_contact(model, state, dofs.advance(state, step, frames))
                run.info["imposed_alone_opened"] += int(opened)
            if alone_first or turned_past or opened:
                scale, state, forces = watchdog.step(state, frames, left.copy(), r, True)
                run.info["imposed_alone"] += 1
                continue
        # Steps on an indefinite tangent are turned downhill, except on the way from a kept
        # saddle: the path of saddles no push descends from is followed by plain Newton (a
        # turned step there heads off the path and finds no lower branch), and each converged
        # state of it is checked again.
        turn = escapes or (factor.negative and not run.on_kept_saddle)
        turned = turn and solver.seek_stable
        predicting = contact_sets.PREDICTED and not run.sets_unpredicted
        if frozen and not regularised and not turned and predicting:
            # The sets of the step's end chosen on its linear model (solvers/contact_sets.py):
            # the step with them, the residual at ``state`` under them, a new line search. Not
            # on a step turned below: the turn takes the tangent and right-hand side of the
            # sets the step began with, and a predicted step would mix the two systems.
            predicted = contact_sets.predicted_sets(run, state, frames, factor, delta_free, left)
            if predicted is not None:
                state, delta_free, change = predicted
                r = r - np.where(dofs.free, change.reshape(r.shape), 0.0)
                forces = None  # the accepted trial's, made with the new sets
                watchdog = Watchdog(run, equilibrium, solver.line_search, solver.update_turn)
        if turn_limit is not None and iteration == 1:
            # The first step is linear in the increment: one that turns a director too far
            # asks for a smaller increment before any iteration is spent (solvers.load_path).
            turns = np.zeros((model.n_nodes, N_COLUMNS))
            turns.ravel()[index] = delta_free
            first_turn = float(np.linalg.norm(turns[:, 3:], axis=1).max(initial=0.0))
            if first_turn > turn_limit:
                raise StepTooLong(first_turn)
        if turned:
            # More negative modes than downhill turns: the shifted tangent's step (inertia).
            shifted = convexified_step(run, k_ff, rhs, factor.negative, delta_free)
            if shifted is None:  # shift-invert with the factorisation just made
                # every negative pivot's mode, the neutral ones too (they lie nearest zero and
                # come first), then those beyond round-off (solvers.neutral_modes)
                pivots = (factor.negative or 0) + factor.neutral
                modes = unstable_modes(k_ff, lowest_modes(k_ff, pivots, factor.inverse()))
                run.info["mode_searches"] += 1
                shifted = downhill(k_ff, rhs, delta_free, factor.negative, modes)
            delta_free = shifted
        flat = left.ravel().copy()
        flat[index] = delta_free
        delta = flat.reshape(-1, N_COLUMNS)
        imposing = bool(np.abs(left).max(initial=0.0) > 0.0)
        # Curved steps and chords only where the residual is smooth: with contact it is smooth
        # only piecewise, and a probe of the path or a chord may cross a stick limit or a touch
        # (with chords the Mindlin hemisphere drape of tests/test_hemisphere_static.py stopped
        # at load factor 0.66). The frozen contact sets exist only with contact.
        smooth = not model.interactions
        # Static(curved_with_contact=True): curved steps with interactions that keep no contact
        # set (the plies' contact, decided by the gaps alone; docs/theory.md §6.5, "Curved steps
        # of a sliding stack").
        curving = smooth or (
            solver.curved_with_contact and curves_with_contact(model, state.history)
        )
        # The second-order term of a plain step on a definite tangent (solvers.newton_curvature);
        # the line search falls back along the straight step.
        straight = None
        if solver.curved and curving and not (turn or regularised or factor.negative):
            curved = curved_step(run, equilibrium, state, frames, delta, r, factor)
            if curved is not None:
                straight, delta = delta, curved
        # The fibre lengths back where the step's first order puts them (solvers.newton_fibres).
        # Where the projected step fails, the line search backtracks along the Newton step
        # itself: a strip bending past the knee of a bilinear law (tests/test_compare.py)
        # stopped at load factor 0.3 when it backtracked along the projected one.
        if run.fibres is not None and smooth:
            if straight is None:
                straight = delta
            delta = run.fibres.project(run, state.positions, straight, delta)
            run.info["fibre_projections"] += 1
        # Every level's fibre strains and shear angles where the step's first order puts them,
        # at the least energy in the tangent (solvers.newton_levels).
        # Only on plain steps of a definite tangent, as the curved steps.
        plain = not (imposing or turn or regularised or factor.negative)
        if run.levels is not None and smooth and plain:
            if straight is None:
                straight = delta
            delta = run.levels.project(run, state, frames, straight, delta, k_ff)
        scale, state, forces = watchdog.step(state, frames, delta, r, imposing, straight)
        if solver.chords and smooth and scale == 1.0 and not imposing:
            state, forces = chord_corrections(
                run, equilibrium, watchdog, state, frames, forces, factor, solver.chords
            )
        # Round-off floor: the internal forces come from differences of nearly equal
        # metrics, so a tiny load on a stiff shell can leave a residual of ~1e-4 of the
        # load that no update removes. A full step that moves nothing (1e-9 of an element,
        # 1e-9 rad) with the residual already small is converged.
        if at_round_off_floor(scale, delta, ratio, size):
            frames = dofs.frames(state.directors)
            unfrozen = state
            if frozen:
                unfrozen, ratio = settle_contacts(model, equilibrium, state, frames, 0.0, True)
            else:
                _, ratio, forces = equilibrium.residual(state, frames)
            history.append(ratio)
            if unfrozen is not None:
                note_floor_acceptance(run.info, ratio, solver.tol, load_factor)  # counted, told
                unfrozen, escape = judged(
                    run, equilibrium, unfrozen, factor, load_factor, escapes, resume
                )
                if escape is None:
                    return unfrozen, iteration, ratio, history
                return unfrozen, iteration + escape[0], escape[1], history + escape[2]
            updates += 1
            near, slips = ratio < history[1], slips_alone(model, state, run.info)
            state, forces, watchdog = refreeze(run, equilibrium, start, state, near)
            if slips:
                state = release_slips(model, state)
            elif updates >= MAX_CONTACT_UPDATES:
                state, frozen = model.thaw(state), False
            continue
        run.progress(
            f"load factor {load_factor:.4g}: iteration {iteration}, residual ratio "
            f"{history[-1]:.3g} (tol {solver.tol:g})"
        )
    raise IncrementFailed(
        iterations_spent(history, solver.tol, allowed, bool(model.interactions) and not frozen)
        + (f"; the tangent was singular: {mechanism(model)}" if singular else "")
    )


def refreeze(run: StaticRun, equilibrium: Residual, start: State, state: State, near: bool = False):
    """(the state to go on from, with the contact sets of ``state`` frozen; no forces; a new
    watchdog). ``near``: ``state`` itself (its residual under the new sets is already below
    that of the increment's first iterate: a node that came onto or off the tool). Otherwise
    the start of the increment, an equilibrium: the state converged with the wrong sets can
    be far off (a node held by its stick spring where it slides)."""
    run.info["contact_set_updates"] += 1
    frozen = run.model.freeze(state)[0]
    restart = frozen if near else replace(start, history=frozen.history)
    solver = run.solver
    return restart, None, Watchdog(run, equilibrium, solver.line_search, solver.update_turn)


def settle_contacts(
    model: CompiledModel,
    equilibrium: Residual,
    state: State,
    frames: Frames,
    tol: float,
    floor: bool = False,
) -> tuple[State | None, float]:
    """A state converged with its contact sets frozen: (the state with them thawed, its
    residual ratio under the unilateral contact law) when it is in equilibrium under that law
    too, else (None, that ratio): the sets were wrong (a frozen node pulled off the tool, a
    free node pressed into it) and the solve goes on with the state's own."""
    thawed = model.thaw(state)
    if not model.interactions:
        return state, equilibrium.residual(state, frames)[1]
    _, changed = model.freeze(state)
    _, unilateral, _ = equilibrium.residual(thawed, frames)
    if floor:  # at the round-off floor (at_round_off_floor): the same sets, a small residual
        return (thawed if not changed and unilateral <= 1e-3 else None), unilateral
    return (thawed if unilateral <= tol else None), unilateral


def stalled(history: list[float], window: int | None) -> bool:
    """Whether the last ``window`` residual ratios of an attempt (``history``: the ratio
    before the first update, then one per update) all stayed above STALLED_RATIO: Newton
    making no headway, which on plies in contact (points stepping on and off each other from
    one iterate to the next) goes on for a hundred iterations before the attempt fails or
    crawls in, where the half step converges in a few (docs/theory.md §6.5). None: never."""
    if window is None or len(history) <= window:
        return False
    return min(history[-window:]) > STALLED_RATIO


def at_round_off_floor(scale: float, delta: np.ndarray, ratio: float, size: float) -> bool:
    """A full Newton update delta (n, 5) that moves no translation by more than 1e-9 of an
    element (size) and no rotation by more than 1e-9 rad, from a residual ratio already below
    1e-3: converged at the round-off floor of the internal forces."""
    moved = scale * np.abs(delta)
    return (
        scale == 1.0
        and ratio <= 1e-3
        and float(moved[:, :3].max(initial=0.0)) <= 1e-9 * size
        and float(moved[:, 3:].max(initial=0.0)) <= 1e-9
    )


def mechanism(model: CompiledModel) -> str:
    """What a singular tangent means for this model, naming the rigid motions no support
    holds when there are any."""
    free = model.unheld_rigid_motions(loaded_only=False)
    if free:
        return "a mechanism: nothing holds the " + ", ".join(free)
    return "a mechanism (a part or a node that nothing holds) or a bifurcation"


class Residual:
    """The residual at one load factor: dead loads, the prescribed target and the ratio by
    which convergence is judged (solvers.convergence.Equilibrium: moments over one element,
    M_ref = F_ref L_e, F_ref at least 1e-300, and a non-finite state never converged).

    model : the compiled model. f_ext, m_ext : (n, 3) dead forces N and moments N mm.
    imposed : (n, 3) prescribed displacements, mm. counts : the evaluation counts of the run
    (its "residual" entry counts the internal-force evaluations). dashpots : the viscous
    stabilisation of the increment (solvers.stabilisation), or None. floor : the least F_ref,
    N (StaticRun.reference_floor).
    """

    def __init__(
        self,
        model: CompiledModel,
        f_ext,
        m_ext,
        imposed,
        counts=None,
        dashpots: Dashpots | None = None,
        floor: float = 1e-300,
    ):
        self.model, self.f_ext, self.m_ext = model, f_ext, m_ext
        self.dashpots = dashpots
        self.counts = counts if counts is not None else {"residual": 0}
        self.target = model.reference_positions + imposed if model.has_prescribed else None
        # One scale for both: a moment M counts as the force M / (element size), so that a
        # pure-moment load (zero forces at equilibrium) has a force reference too.
        self.test = Equilibrium(f_ext, m_ext, model.element_size, floor=floor)

    def remaining(self, state: State) -> np.ndarray:
        """(n, 5) prescribed motion not yet applied."""
        out = np.zeros((self.model.n_nodes, N_COLUMNS))
        if self.target is not None:
            out[:, :3] = np.where(
                self.model.translation_prescribed, self.target - state.positions, 0.0
            )
        return out

    def load(self, frames: Frames) -> np.ndarray:
        """(n, 5) external loads in generalised components."""
        return self.model.dofs.generalised(frames, self.f_ext, self.m_ext)

    def residual(self, state: State, frames: Frames, forces=None):
        """(r (n, 5) on the free DOFs, ratio, internal forces) at ``state``; ``forces`` reuses
        an evaluation of the internal forces at that state."""
        model, f_ext, m_ext = self.model, self.f_ext, self.m_ext
        if forces is None:
            self.counts["residual"] += 1
            try:
                forces = model.internal_force(state)
            except ZeroDivisionError as error:  # e.g. a node's normal sum vanished
                raise IncrementFailed(f"the internal forces cannot be evaluated: {error}") from None
        f_int, m_int = forces
        f_out, m_out = f_ext - f_int, m_ext - m_int
        if self.dashpots is not None:
            f_dashpots, m_dashpots = self.dashpots.forces(state)
            f_out, m_out = f_out + f_dashpots, m_out + m_dashpots
        r = np.where(model.dofs.free, model.dofs.generalised(frames, f_out, m_out), 0.0)
        ratio = self.test.ratios(r[:, :3], r[:, 3:], f_int, m_int).checked()
        return r, ratio, (f_int, m_int)


class Tangent:
    """(K_ff, K_fp) of the model at a state in the iteration's frames: the blocks' own tangents
    (``own``: block indices) assembled by femcore.assembly, plus coloured finite differences
    of the other blocks' forces."""

    def __init__(self, model: CompiledModel, own: list[int], others: list[int], first=None):
        """``first``: (state, {block index: parts}) already evaluated, reused at that state."""
        self.model, self.own, self.others = model, own, others
        self.first = first
        self.assemble = FreeTangentAssembler(model.dofs, superset=True)
        self.graph = model.node_graph(others) if others else None

    def __call__(
        self,
        state: State,
        frames: Frames,
        compression_free: bool = False,
        real: State | None = None,
    ):
        """(K_ff, K_fp) at ``state``; ``compression_free``: the fibrous blocks' tangent with
        their fibres' compression (beyond that of ``real``, the last converged state) left out
        of its stress terms (docs/theory.md §6.5)."""
        model, dofs = self.model, self.model.dofs
        parts: list[TangentPart] | None
        if self.first is not None and state is self.first[0] and not compression_free:
            parts = [part for i in self.own for part in self.first[1][i]]
        else:
            parts = model.tangent_parts(state, self.own, compression_free, real)
        if parts is None:
            raise RuntimeError(
                "an element block gave a tangent at the start of the solve and none later: a "
                "block's tangent() returns None always or never"
            )
        k_ff, k_fp = self.assemble(parts, frames)
        if self.graph is not None:
            k = model.finite_difference_stiffness(state, self.others, self.graph, frames)
            free, moved = dofs.free_slots, dofs.prescribed_slots
            k_ff = (k_ff + k[free][:, free]).tocsc()
            k_fp = k_fp + k[free][:, moved]
        return k_ff, k_fp
