"""What a stopped quasi-static solve can name as the cause: a contact node that Newton's
iterates carried back and forth across an edge between two facets of a meshed tool
(docs/theory.md §9.3).

Why. On the concave side of a faceted tool (inside a die's bowl) the closest-point normal
jumps by the facets' dihedral angle where a node crosses the edge between them, and the
contact force of a pressed node pushes it across that edge from either side: it has no
equilibrium on the edge, each Newton step carries it over and the next one back, and no cut
of the increment removes the cycle (benchmarks/hemisphere_static.py, the 16-cell drape on the
plain die). The residual then sits on that node, and the generic message (the residual ratio
after so many iterations) names neither. The meshed tool keeps each point's closest facet
over its last calls (``RigidSurface.facet_record``); a node whose record holds exactly two
facets sharing an edge, in turn at least CYCLE_SWITCHES times, is named with the two facets,
the angle between their normals and the remedy: the smoothed tool
(``RigidSurface(smooth=True)``), whose normal is continuous across the edges. That named
cause then stands alone in the message: the generic hint of a limit point or buckling (a
path to follow, smaller increments) would send the user the wrong way, for no cut removes a
crease's cycle.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from solvers.neutral_modes import zero_modes

__all__ = [
    "CYCLE_SWITCHES",
    "FRICTION_AT_START",
    "FRICTION_LATER",
    "STEP_LOADS_RAMPED",
    "crossing_cycles",
    "describe_cycles",
    "held_by_friction_alone",
    "iterations_spent",
    "neutral_hint",
    "stop_hint",
    "steps_ramped_with_others",
    "still_falling",
]

# The least number of changes between the two facets in a point's record (of
# elements/rigid_surface.py FACET_RECORD calls) that counts as a cycle (the node of the
# faceted trough of tests/test_tool_smoothing.py switched 8 times in 16, the line search's
# shorter trials keeping it on one side between).
CYCLE_SWITCHES = 6
# Facets whose normals differ by less than this (deg) make no crease (the plain 16-cell drape's
# flange node 81 went to and fro between two coplanar facets of the die's flange).
CREASE_DEG = 0.01
# The most nodes a message names.
NAMED = 3


def crossing_cycles(model: Any) -> list[dict[str, Any]]:
    """The contact nodes of ``model`` (a CompiledModel; its interactions with a meshed tool,
    not smoothed: ``RigidSurface(smooth=True)`` has no crease to name) that cycle across a
    facet edge, most switches first: each a dict with ``node`` (the
    body's node id), ``tool`` (the interaction's index), ``facets`` (the two), ``angle_deg``
    between their normals, ``switches``, ``edge`` (2, 3) its end points, mm."""
    found: list[dict[str, Any]] = []
    for index, part in enumerate(model.interactions):
        # None for an analytic tool, and a smoothed one, whose normal is continuous across
        # its edges: no crease (femcore.interaction ``facet_record``)
        facets = part.facet_record()
        if facets is None:
            continue
        record, connectivity = facets.record, part.connectivity
        if record.shape[0] != len(connectivity) or record.shape[1] <= CYCLE_SWITCHES:
            continue
        low, high = record.min(axis=1), record.max(axis=1)
        two = (
            (low >= 0)
            & (low != high)
            & np.all((record == low[:, None]) | (record == high[:, None]), axis=1)
        )
        switches = np.count_nonzero(np.diff(record, axis=1), axis=1)
        for row in np.flatnonzero(two & (switches >= CYCLE_SWITCHES)):
            a, b = int(low[row]), int(high[row])
            shared = _shared_corners(facets.corners[a], facets.corners[b])
            if len(shared) != 2:
                continue  # facets meeting at a vertex only, or apart: not an edge's crease
            cosine = float(np.clip(facets.normals[a] @ facets.normals[b], -1.0, 1.0))
            angle = float(np.degrees(np.arccos(cosine)))
            if angle < CREASE_DEG:
                continue  # coplanar facets (a flange): the normal does not jump there
            found.append(
                {
                    "node": int(connectivity[row, 0]),
                    "tool": index,
                    "facets": (a, b),
                    "angle_deg": angle,
                    "switches": int(switches[row]),
                    "edge": np.array(shared),
                }
            )
    found.sort(key=lambda entry: -int(entry["switches"]))
    return found


def _shared_corners(first: np.ndarray, second: np.ndarray) -> list[np.ndarray]:
    """The corners (3, 3) of ``first`` that are corners of ``second`` too (to 1e-9 of the
    facet's size)."""
    size = float(np.ptp(first, axis=0).max())
    return [c for c in first if np.min(np.linalg.norm(second - c, axis=1)) <= 1e-9 * size]


def describe_cycles(model: Any, positions: np.ndarray | None = None) -> str:
    """A sentence naming the nodes of ``crossing_cycles`` (at most NAMED; ``positions``
    (n, 3), mm, where to say each lies), the cause and the remedy; "" when there are none."""
    cycles = crossing_cycles(model)
    if not cycles:
        return ""
    named = []
    for entry in cycles[:NAMED]:
        node = entry["node"]
        where = ""
        if positions is not None:
            x = positions[node]
            where = f" (at {x[0]:.4g}, {x[1]:.4g}, {x[2]:.4g} mm)"
        named.append(
            f"node {node}{where} of interaction {entry['tool']} crossed the edge between "
            f"facets {entry['facets'][0]} and {entry['facets'][1]} of its meshed tool "
            f"(normals {entry['angle_deg']:.3g} deg apart) {entry['switches']} times in its "
            "last evaluations"
        )
    more = f" and {len(cycles) - NAMED} more node(s)" if len(cycles) > NAMED else ""
    return (
        "; ".join(named)
        + more
        + ": under the closest-point normal a node pressed into a concave crease between "
        "facets has no equilibrium on it; RigidSurface(smooth=True) (in a case file, smooth = "
        "true in the tool's [[contact]] table) gives the tool a normal continuous across its "
        "edges (docs/theory.md §9.3)"
    )


#: Said where a solve stopped in its first increment (after its retry with stiff stick springs
#: first, solvers/stick_start.py) and a body is held by friction alone
#: (``held_by_friction_alone``: its supports leave free a translation its loads push it
#: along): it has a static equilibrium only while its pull stays within mu times its press
#: (Coulomb: it slides otherwise, and a slide has no static state for Static or a relaxation
#: to find: a strip pulled past 2 mu F was sent to DynamicRelaxation), and pressing it first
#: is the way to that equilibrium that takes the contact's events one at a time.
FRICTION_AT_START = (
    "; a body held by friction alone has no static equilibrium where its pull passes mu "
    "times its press: it slides, which no quasi-static solver (Static, DynamicRelaxation) "
    "can find, and only an explicit run (CentralDifference) follows; below it, press it "
    "first, then pull it (the pressing loads at amplitude 'step' and "
    "Static(step_loads_first=True))"
)

#: Said after ``FRICTION_AT_START`` where that body's loads mix "step" ones with ramped ones
#: (``steps_ramped_with_others``) and Static ramps them together (not step_loads_first): a
#: press at amplitude "step" and a pull ramped with it keep their ratio at every load factor,
#: so a pull past mu times the press at load factor 1 is past it at the first increment too,
#: and no increment has an equilibrium (a ply pressed by 1 N at "step", pulled linearly to
#: 0.31 N on a floor of mu 0.3: the contact's press at load factor 0.1 was 0.1 N, its
#: friction at most 0.03 N against a pull of 0.031 N). Held whole from the first increment
#: (a callable amplitude of 1, or the press first), the same ply converges up to load factor
#: 0.967, where the pull reaches mu times the press (docs/theory.md §6.5).
STEP_LOADS_RAMPED = (
    "; Static ramps its 'step' loads with the load factor too unless "
    "step_loads_first=True, so a press at amplitude 'step' and a pull ramped with it keep "
    "their ratio at every load factor: a pull past mu times the press at load factor 1 is "
    "past it from the first increment. To hold the press whole from the first increment, "
    "give it a callable amplitude (amplitude=lambda load_factor: 1.0) or solve with "
    "Static(step_loads_first=True)"
)

#: Said where a solve stopped after converged increments and a body is held by friction alone
#: (``held_by_friction_alone``): its pull may have reached mu times its press there, past
#: which it slides and no quasi-static solver finds a state (``FRICTION_AT_START``'s reason);
#: not the press-first advice, which a converged increment no longer needs.
FRICTION_LATER = (
    "; a body held by friction alone has no static equilibrium once its pull passes mu times "
    "its press: if it reached that here, it slides, which no quasi-static solver (Static, "
    "DynamicRelaxation) can find, and only an explicit run (CentralDifference) follows"
)


def neutral_hint(factor, linear=None) -> str:
    """The cause of a stop whose last tangent ``factor`` (solvers.linear.Factorisation, or
    None) has eigenvalues within round-off of zero: zero-stiffness modes, a mechanism the load
    does not drive, along which a Newton step is the residual's round-off over the
    eigenvalue's; "" without them. Counted of either sign, and an exactly singular tangent,
    by ``solvers.neutral_modes.zero_modes`` with ``linear`` (a solvers.linear.LinearSolver of
    its own) where given, else the negative ones alone (``factor.neutral``, solvers.neutral_modes
    ``judge_pivots``): a zero mode whose rounding fell positive is the same mechanism (the
    K = 0 strip on 4 x 1 or 8 x 4 cells was sent to the arc length, which then stopped on its
    singular tangent). Named with its commonest cause and remedies: a fibrous fabric whose
    shear law has no stiffness at zero shear (K = 0) leaves the flat sheet's in-plane shear
    (trellising) and its directors' tilt free."""
    count = 0 if factor is None else int(getattr(factor, "neutral", 0) or 0)
    if not count and linear is not None:
        count = zero_modes(linear, factor)
    if not count:
        return ""
    return (
        "; the tangent has zero-stiffness modes (eigenvalues within its round-off of zero): "
        "a mechanism the load does not drive, along which "
        "each Newton step divides round-off by round-off (a fibrous fabric with shear K = 0 "
        "has no in-plane shear or director tilt stiffness in its flat state). Give the "
        "mechanism a small stiffness (a shear K small beside the other terms), hold it with "
        "supports, or solve with DynamicRelaxation, which needs no tangent"
    )


def stop_hint(
    model: Any,
    positions: np.ndarray | None,
    path: str,
    at_start: bool = False,
    step_loads_first: bool = False,
) -> str:
    """The end of a stopped static solve's message after its reason: "; " and the crease
    cycles of ``describe_cycles`` when there are some, else ". " and the contacts' hint on a
    model with interactions (with ``FRICTION_AT_START`` where it stopped ``at_start``, before
    any increment converged, not ``step_loads_first``, and a body is held by friction alone:
    ``held_by_friction_alone``; then with ``STEP_LOADS_RAMPED`` where its "step" loads are
    ramped with others, ``steps_ramped_with_others``; ``FRICTION_LATER`` where such a body's
    solve stopped after converged increments), else the generic hint of a limit point or
    buckling for the solver's ``path`` ("load" or "arc_length")."""
    cause = describe_cycles(model, positions)
    if cause:
        return f"; {cause}"
    if model.interactions:
        # A contact closing, opening or sliding inside an increment stops Newton more often
        # than a limit point does, and a path along a limit point (arc length) does not help
        # there; smaller increments meet the contact's events one at a time.
        hint = (
            ". The model has interactions (contacts, ties): a contact that closes, opens or "
            "slides within an increment can stop Newton; try more increments"
        )
        if at_start and not step_loads_first and held_by_friction_alone(model):
            # (no relaxation finds a slide's state either)
            ramped = STEP_LOADS_RAMPED if steps_ramped_with_others(model) else ""
            return hint + FRICTION_AT_START + ramped
        if not at_start and held_by_friction_alone(model):
            return hint + FRICTION_LATER
        return hint + (
            ", or DynamicRelaxation (path='arc_length' follows a limit point or buckling, not "
            "a contact's events)"
        )
    remedy = (
        "try path='arc_length' to follow a limit point"
        if path == "load"
        else "try smaller increments or DynamicRelaxation"
    )
    return f". A limit point or buckling may be near: {remedy}"


def steps_ramped_with_others(model: Any) -> bool:
    """Whether the loads of ``model`` (a CompiledModel) with a named amplitude mix "step"
    ones (full at any positive progress) with ramped ones or prescribed displacements, which
    Static without step_loads_first scales together by its load factor
    (``STEP_LOADS_RAMPED``; solvers.static.Static.loads)."""
    full, _ = model.external_load(1.0, quasi_static=True, user=False)
    step, _ = model.external_load(1e-300, quasi_static=True, user=False)
    imposed = model.prescribed_displacement(1.0, quasi_static=True, user=False)
    size = max(float(np.abs(full).max(initial=0.0)), 1e-300)
    stepped = float(np.abs(step).max(initial=0.0)) > 1e-9 * size
    ramped = float(np.abs(full - step).max(initial=0.0)) > 1e-9 * size
    return stepped and (ramped or bool(np.abs(imposed).max(initial=0.0) > 0.0))


def held_by_friction_alone(model: Any) -> bool:
    """Whether a body of ``model`` (a CompiledModel; a body: nodes joined by cells) that a
    frictional interaction acts on is pushed by the dead loads (at load factor 1, and at
    femcore.diagnostics USER_LEVELS where some loads have a user amplitude) along a
    translation that neither its supports nor a frictionless interaction holds: only its
    contacts hold it there, friction the pull (``FRICTION_AT_START``'s case). A body held
    by its supports (a clamped blank under a frictional punch) is not; an interaction that
    does not say what it holds (``held_directions`` None) is taken to hold every motion."""
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components

    from femcore.diagnostics import USER_LEVELS

    frictional = [block for block in model.interactions if block.friction > 0.0]
    if not frictional:
        return False
    n = model.n_nodes
    links = [np.zeros((0, 2), dtype=np.int64)]
    for entry in model.block_entries:
        cells = np.asarray(model.mesh.cells(entry.element.cell_type)[entry.cells])
        # a chain through each cell's nodes joins them all
        links.append(np.column_stack([cells[:, :-1].ravel(), cells[:, 1:].ravel()]))
    pairs = np.concatenate(links)
    graph = coo_matrix((np.ones(len(pairs)), (pairs[:, 0], pairs[:, 1])), shape=(n, n))
    count, body = connected_components(graph, directed=False)
    acted = np.zeros(count, dtype=bool)
    touched = np.unique(np.concatenate([np.ravel(b.connectivity) for b in frictional]))
    touched = np.setdiff1d(touched, model.rigid_nodes)  # a tool's own node is no body
    acted[body[touched]] = True
    # What holds each body without friction: its fixed or prescribed translations, and the
    # directions a frictionless interaction holds at its nodes.
    nodes = [np.flatnonzero(model.dofs.constrained[:, axis]) for axis in range(3)]
    held_nodes = np.concatenate(nodes)
    held = np.concatenate([np.tile(np.eye(3)[axis], (len(k), 1)) for axis, k in enumerate(nodes)])
    for block in model.interactions:
        if block.friction > 0.0:
            continue
        rows = block.held_directions()
        if rows is None:
            return False
        held_nodes = np.concatenate([held_nodes, np.asarray(rows[0], dtype=np.int64).ravel()])
        held = np.concatenate([held, np.asarray(rows[1], dtype=float).reshape(-1, 3)])
    levels = [1.0] + (list(USER_LEVELS) if model.user_amplitudes() else [])
    for level in levels:
        force, _ = model.external_load(level, quasi_static=True)
        force = np.where(np.isin(np.arange(n), model.rigid_nodes)[:, None], 0.0, force)
        net = np.zeros((count, 3))
        np.add.at(net, body, force)
        size = max(float(np.abs(force).sum()), 1e-300)
        for index in np.flatnonzero(acted & (np.linalg.norm(net, axis=1) > 1e-9 * size)):
            # The translations the body's holders leave free, and the net load along them.
            mine = held[body[held_nodes] == index]
            if len(mine):
                _, singular, vt = np.linalg.svd(mine, full_matrices=True)
                free = vt[int(np.sum(singular > 1e-9)) :]
            else:
                free = np.eye(3)
            if np.linalg.norm(free @ net[index]) > 1e-9 * size:
                return True
    return False


#: The iterations over which the residual ratio is judged still falling or stalled.
RECENT = 10
#: A ratio this many times the tolerance or less, no longer falling, is the forces' round-off.
NEAR_TOL = 1e3


def iterations_spent(
    history: list[float], tol: float, allowed: int, searching: bool = False
) -> str:
    """What an increment that ran out of Newton iterations says: "residual ratio r after N
    iterations (tol t)" and, from its ratios ``history``, what would help: where they were
    still falling (the last RECENT halved it), a larger max_iterations; where they stalled
    within NEAR_TOL of ``tol``, the round-off of the forces at the model's stiffness (a stiff
    penalty): a looser tol (a table's plane at penalty 10 stopped at 5.7e-7 with tol 1e-8, and
    converged in 3 iterations with 1e-6). ``searching``: the attempt ended on the unilateral
    contact law (its frozen sets found wrong solvers.newton.MAX_CONTACT_UPDATES times, or
    never frozen), whose sets change as it iterates: a lift-off front moves about a node per
    iteration, and a strip on a table at the automatic penalty ran out at 50 (ratio 0.993)
    where it needs 61 (every cut of it too): a larger max_iterations may help."""
    ratio = history[-1]
    said = f"residual ratio {ratio:.3g} after {allowed} iterations (tol {tol:g})"
    if searching and ratio > NEAR_TOL * tol:
        return said + (
            ", on the unilateral contact law, whose sets may still have been changing (a "
            "lift-off front moves about a node per iteration, and no cut shortens that): "
            f"raise max_iterations (it was {allowed})"
        )
    if still_falling(history):
        return said + f", still falling: raise max_iterations (it was {allowed})"
    if len(history) <= RECENT:
        return said
    if ratio <= NEAR_TOL * tol:
        return said + (
            f", no longer falling within {NEAR_TOL:g} times it: the round-off of the forces "
            f"at this stiffness (a stiff contact penalty?); a looser tol, e.g. "
            f"{10.0 ** math.ceil(math.log10(ratio)):g}, or a softer penalty"
        )
    return said


def still_falling(history: list[float]) -> bool:
    """Whether the residual ratios ``history`` of an attempt (its first: the start's) were
    still falling when its iterations ran out: the last halved it over its last RECENT
    iterations, or over all of them in an attempt of fewer (a cap of 3 iterations stopped a
    strip's first increment at 0.00135, from 1, still falling: the cap stopped it, not a limit
    point, which stalls the ratio)."""
    if len(history) < 2:
        return False
    return history[-1] < 0.5 * history[max(len(history) - RECENT - 1, 0)]
