"""The flat ply contact's committed friction history and the next step's loads in one compiled
call (docs/theory.md §9.3a; elements/ply_friction_pass.py ``history_pass`` then
elements/ply_load_kernels.py ``ply_loads``).

Why. An explicit step asks a frictional ply contact block for its history at the accepted
state (the commit: ``PlyContactBlock.update_history``) and, at the next step, for its loads at
that same state from the history just accepted. Both read the same facing and faces, and the
loads read the return mapping the history's pass makes for them (``following``,
elements/ply_friction_kernels.py). Each was a compiled call wrapped in numpy and Python glue
(the loads' masks of the touching, stuck and sliding points, the stick couples' rows, some
thirty conversions of arguments). Here the loads run in the history's pass, right after the
mapping they read, and are kept on the block with that mapping; ``PlyContactBlock.
internal_force`` serves them where the history, facing and penalties are the ones they were
made for (``kept_loads``: the same test as the kept mapping's), and computes them as before
otherwise.

The same bits. The pass calls the very kernels the chained calls run (``_history``, the stick
couples' ``_couples`` and the loads' ``_loads``) with the same inputs: the touching points'
rows, the stuck or sliding points' rows, the stuck points that face a plane, and those facing
an edge or a vertex, whose couples are scattered into a (P, 4, 3) array of zeros, chosen in a
loop over the points in their order as ``np.flatnonzero`` chooses them; the ramp's cubes are
numpy's (``ply_penalty.ramp_cubes``, from the same min(g, 0) as the history's, which numpy
takes point by point). So the kept loads are the chained ones to the last bit, and the numpy
reference's (``ply_projection.COMPILED = False``) as the chained ones are
(tests/test_ply_commit_pass.py).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from elements import ply_edge_couple_kernels, ply_load_kernels, ply_penalty
from elements.kernel_inputs import read_only
from elements.ply_edge_couple import END
from elements.ply_friction_kernels import _kept_mapping
from elements.ply_friction_pass import _history_compiled
from elements.ply_wedge import KEEP
from femcore.jit import lanes

if TYPE_CHECKING:
    from elements.ply_block import PlyContactBlock
    from elements.ply_friction import PlyFrictionHistory
    from elements.ply_projection import Facing
    from femcore.state import State

__all__ = ["LOADS_IN_PASS", "block_arrays", "kept_loads", "loads_inputs"]

#: The next step's loads made in the committed history's pass and kept on the block
#: (module docstring); False: the loads' own call at the next step, as before.
LOADS_IN_PASS = True


@lanes
def _rows(touching, stuck, sliding, flagged, on_edge):
    """(on (t,) the touching points' rows, rows (f,) the stuck or sliding ones', plane (P,)
    the stuck points that face a plane, at (e,) the stuck points facing an edge or a vertex
    where ``flagged``): ``ply_load_kernels.ply_loads``' masks, each list in the points'
    order."""
    count = touching.shape[0]
    touched = 0
    held = 0
    edges = 0
    plane = np.empty(count, dtype=np.bool_)
    for i in range(count):
        touched += touching[i]
        held += stuck[i] or sliding[i]
        on = flagged and stuck[i] and on_edge[i]
        edges += on
        plane[i] = stuck[i] and not on
    on_rows = np.empty(touched, dtype=np.int64)
    rows = np.empty(held, dtype=np.int64)
    at = np.empty(edges, dtype=np.int64)
    a = b = c = 0
    for i in range(count):
        if touching[i]:
            on_rows[a] = i
            a += 1
        if stuck[i] or sliding[i]:
            rows[b] = i
            b += 1
        if flagged and stuck[i] and on_edge[i]:
            at[c] = i
            c += 1
    return on_rows, rows, plane, at


@lanes
def _history_loads(history, loads):
    """``_history`` (elements/ply_friction_pass.py) with the arguments ``history`` (its tuple,
    in its order), then the loads from the mapping it made for the next step: ``loads`` is
    (cube (t,) the touching points' ramp cubes, fade_gradient (P, 6, 3),
    fade_edge (P,), smoothing_squared, the block's arrays (``block_arrays``), direction
    (n, 3), flagged, on_edge (P,), reach (P, 3), keep, end, bilateral (False: a bool given,
    not a literal, for which numba would build ``_loads`` again), force, moment (n, 3)
    written). Each input of the type the chained calls hand the kernels (kernel_inputs.py):
    one build of each. The couples of the stuck points facing an edge or a vertex by
    ``_couples``, scattered to zeros at the other rows, as ``ply_loads`` makes them."""
    _history_compiled(*history)
    (
        touching, gap, stiffness, smoothing, fade, _, _, _, _, _, _, face, normal, y, _,
        triangle, weights, gradients,
    ) = history[:18]  # fmt: skip
    (
        next_force, _, next_stuck, next_sliding, _, next_offset, next_triangle, _,
        next_lift, next_stored,
    ) = history[34:44]  # fmt: skip
    anchor = history[31]
    (
        cube, fade_gradient, fade_edge, smoothing_squared, shape, above, cells, upper_offset,
        corner_offset, lever, outline_nodes, outline_offsets, lines, far, cut, direction,
        flagged, on_edge, reach, keep, end, bilateral, force, moment,
    ) = loads  # fmt: skip
    on, rows, plane, at = _rows(touching, next_stuck, next_sliding, flagged, on_edge)
    if at.shape[0]:
        couples = np.empty((at.shape[0], 4, 3))
        ply_edge_couple_kernels._couples(
            at, weights, reach, triangle, gap, normal, face, next_offset, next_force, y,
            lines, far, cut, keep, end, couples,
        )  # fmt: skip
        turn = np.zeros((touching.shape[0], 4, 3))
        for i in range(at.shape[0]):
            for a in range(4):
                for c in range(3):
                    turn[at[i], a, c] = couples[i, a, c]
    else:
        turn = np.zeros((0, 4, 3))
    ply_load_kernels._loads(
        on, cube, gap, normal, weights, triangle, fade, fade_gradient, fade_edge, stiffness,
        smoothing, smoothing_squared, shape, above, cells, upper_offset, corner_offset, lever,
        direction, outline_nodes, outline_offsets, rows, next_triangle, next_force, anchor,
        next_lift, next_stored, plane, next_offset, gradients, turn, bilateral, force, moment,
    )  # fmt: skip


def block_arrays(block: PlyContactBlock) -> tuple:
    """The block's fixed arrays the loads read, C-contiguous of the loads' types, made once
    and kept on the block (they change only with its mesh, which a bound block keeps):
    shape, above, cells, upper_offset, corner_offset, lever, outline_nodes, outline_offsets
    (E, 2), the cuts' lines, far ends and flags (ply_edge_couple_kernels.edge_couples')."""
    kept = getattr(block, "_loads_arrays", None)
    if kept is not None:
        return kept
    cuts = block.cuts
    m = len(block.cells)
    if cuts is None:
        lines = far = np.zeros((m, 3, 3))
        cut = np.zeros(m, dtype=np.bool_)
    else:
        lines, far, cut = cuts.lines, cuts.ends, cuts.cut
    kept = (
        np.ascontiguousarray(block.shape, dtype=float),
        np.ascontiguousarray(block.above, dtype=np.int64),
        np.ascontiguousarray(block.cells, dtype=np.int64),
        np.ascontiguousarray(block.upper_offset, dtype=float),
        np.ascontiguousarray(block.corner_offset, dtype=float),
        float(block.lever),
        np.ascontiguousarray(block.outline_nodes.reshape(-1, 2), dtype=np.int64),
        np.ascontiguousarray(block.outline_offsets.reshape(-1, 2), dtype=float),
        np.array(lines, dtype=float),
        np.array(far, dtype=float),
        np.array(cut, dtype=np.bool_),
    )
    setattr(block, "_loads_arrays", kept)  # noqa: B010 (a cache, as the block's others)
    return kept


def loads_inputs(block: PlyContactBlock, state: State, facing: Facing, bounded: np.ndarray):
    """(``_history_loads``' ``loads`` tuple, force, moment): the loads' inputs at ``state``
    (``facing`` there, ``bounded`` numpy's min(g, 0) of its gaps (P,)) and their outputs,
    (n, 3) each, uninitialised (the pass writes every entry)."""
    smoothing = block.smoothing
    on = np.flatnonzero(facing.touching)
    # numpy's power, as ply_loads takes it (numpy's min(g, 0) point by point: the same bits)
    cube = ply_penalty.ramp_cubes(bounded[on], smoothing)
    count = len(facing.gap)
    flags = facing.on_edge
    flagged = flags is not None
    reach = np.zeros((count, 3)) if facing.reach is None else facing.reach
    force = np.empty((block.n_nodes, 3))
    moment = np.empty((block.n_nodes, 3))
    fixed = block_arrays(block)
    loads = (
        cube,
        np.ascontiguousarray(facing.fade_gradient, dtype=float),
        np.ascontiguousarray(facing.fade_edge, dtype=np.int64),
        float(smoothing**2),
        *fixed[:8],
        *fixed[8:],
        read_only(block.offset_directions(state)),  # as ply_loads hands it: one build
        flagged,
        np.ascontiguousarray(flags if flagged else np.zeros(0), dtype=np.bool_),
        read_only(reach),  # as edge_couples hands it
        float(KEEP),
        float(END),
        False,  # the ramp (not the frozen set's bilateral law), a bool as ply_loads gives it
        force,
        moment,
    )
    return loads, force, moment


def kept_loads(
    block: PlyContactBlock, history: PlyFrictionHistory, facing: Facing
) -> tuple[np.ndarray, np.ndarray] | None:
    """The loads the commit's pass kept for ``history`` (unedited since) at ``facing`` and
    the block's penalties now (``ply_friction_kernels._kept_mapping``'s test), as fresh
    copies (a caller may add into them); None where none serves."""
    kept = getattr(block, "_next_loads", None)
    if kept is None or kept[0] is not history or _kept_mapping(block, history, facing) is None:
        return None
    return kept[1].copy(), kept[2].copy()
