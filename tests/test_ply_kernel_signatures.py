"""The ply contact's kernels are built once, whether their inputs come read-only (the faces
and directions a block keeps, elements/ply_block.py) or writable (fresh arrays of a caller):
numba builds a kernel once for each set of argument types, and a writable array is a type
apart from a read-only one, so each such pair was a second compilation of the same machine
code (benchmarks/suite_signatures.py: 12 kernels, about 7 s of CPU from an empty cache). The
wrappers hand those inputs through ``elements.kernel_inputs.read_only``.

Reference: numba's own record of its builds, ``dispatcher.signatures``; no tolerance. The
numbers of the compiled kernels against numpy's are tests/test_ply_kernels.py's.
"""

import numpy as np
import pytest
from test_ply_wedge import _fan

from elements import (
    ply_choice,
    ply_chosen,
    ply_edge_kernels,
    ply_face_points,
    ply_facing_pass,
    ply_facing_whole,
    ply_fade_kernels,
    ply_friction_kernels,
    ply_friction_pass,
    ply_kernels,
    ply_load_kernels,
    ply_projection,
    ply_search,
)
from elements.kernel_inputs import read_only
from femcore import jit
from femcore.state import State

pytestmark = pytest.mark.skipif(not jit.AVAILABLE, reason="numba is not installed")

KERNELS = {
    "choose": ply_choice._choose_compiled,
    "fade pass": ply_fade_kernels._outline_compiled,
    "face points": ply_face_points._points,
    "edge parts": ply_edge_kernels._parts_compiled,
    "edge sides": ply_edge_kernels._sides_compiled,
    "planes": ply_kernels._facets_at_compiled,
    "grown corners": ply_kernels._grown_compiled,
    "loads": ply_load_kernels._loads,
    "moves": ply_search._moves_compiled,
}
# (the helpers they call, ply_feature_normals' fan_parts, signing_at and _unit_normal and
# ply_load_kernels._add and _add_upper, take their callers' arrays: built once with them; a
# build loaded from numba's cache brings its helpers' machine code along and leaves their
# dispatchers empty)


def _signatures(kernel) -> list:
    """numba's builds of ``kernel`` in this process (a ``jit`` loop's: its plain build's)."""
    return list((kernel.serial if hasattr(kernel, "serial") else kernel).signatures)


def _writable(array: np.ndarray) -> np.ndarray:
    copy = array.copy()
    assert copy.flags.writeable
    return copy


def test_each_ply_kernel_is_built_once_for_read_only_and_writable_inputs(monkeypatch):
    """The fan of tests/test_ply_wedge.py (cut growths, edges, fades) faced and loaded by its
    block (its faces and directions read-only), then again with the same faces and directions
    writable, and the faces' and grown corners' kernels called with both: each of the nine
    kernels gains at most one build (two on the old wrappers, which passed the flag through)."""
    monkeypatch.setattr(ply_projection, "COMPILED", True)
    # the chained kernels (a small facing runs them fused, elements/ply_facing_pass.py, and
    # would leave ``choose`` unbuilt unless another test had built it in this process)
    monkeypatch.setattr(ply_projection, "SMALL_LOOP", 0)
    # builds made before this test by other tests' direct calls (writable arrays of their
    # own) are not this test's: it counts the builds its own calls add
    before = {name: len(_signatures(kernel)) for name, kernel in KERNELS.items()}
    block, positions, directors, _ = _fan()
    zero = np.zeros_like(positions[0])
    # the directors read-only at the first two states (as the faces along the plies' normals
    # are kept, ``faces="normal"``), writable at the third (a state's own)
    kept = directors.copy()
    kept.setflags(write=False)
    states = [State(x, kept, zero, zero) for x in positions[[100, 700]]]
    states.append(State(positions[750], directors.copy(), zero, zero))
    # the block's own path: its candidates' lists made, then moved; faces kept read-only
    for state in states[:2]:
        block.facing(state, second=True)
        block.internal_force(state)
    p, y = block._faces(states[1])
    directions = block.offset_directions(states[1])
    assert not (p.flags.writeable or y.flags.writeable or directions.flags.writeable)
    assert block.offset_directions(states[2]).flags.writeable
    # the same at the third state with writable faces and directions (a caller's fresh ones)
    state = states[2]
    x = state.positions
    fresh_p, fresh_y, _ = ply_face_points.face_points(
        x,
        _writable(block.offset_directions(state)),
        block.above,
        block.upper_offset,
        block.shape,
        block.cells,
        block.corner_offset,
    )
    assert fresh_p.flags.writeable and fresh_y.flags.writeable
    block._faces_at = (x.copy(), state.directors.copy(), fresh_p, fresh_y)
    block._facing_at = None
    facing = block.facing(state, second=True)
    block.internal_force(state)
    assert facing.touching.any()
    reach = np.full((len(y), 3), ply_projection.MARGIN)
    for corners in (y, _writable(y)):
        ply_kernels.grown_corners(corners, reach)
    built = {name: len(_signatures(kernel)) for name, kernel in KERNELS.items()}
    added = {name: built[name] - before[name] for name in KERNELS}
    assert all(count >= 1 for count in built.values()), built
    assert all(count <= 1 for count in added.values()), added


def test_the_fused_passes_run_the_kernels_own_plain_builds(monkeypatch):
    """The fused passes (elements/ply_facing_pass.py, ply_facing_whole.py,
    ply_friction_pass.py) run each stage by its kernel's own plain build (femcore/jit.py
    ``plain_part``), with argument types the kernel's wrapper gives it: the fan faced by
    the fused pass (a small facing without the gap's Hessian) and then by the chained
    kernels adds at most one build to each. A helper compiled apart from the same source was
    a second build of each of the eight loops (8.5 s of CPU from an empty cache,
    benchmarks/suite_kernels.py); a literal True given for a flag built a callee again. (The
    edges' fans of the whole facing's first call are ``ply_edge_kernels._parts_once``, a
    loop of its own that makes each vertex's fan once, not ``_parts``' plain build.)"""
    fused = {
        "planes": (ply_facing_pass._facets_here, ply_kernels._facets_at_compiled),
        "choose": (ply_facing_pass._choose_here, ply_choice._choose_compiled),
        "chosen": (ply_facing_pass._chosen_here, ply_chosen._chosen_compiled),
        "edge sides": (ply_facing_whole._sides_here, ply_edge_kernels._sides_compiled),
        "fade pass": (ply_facing_whole._outline_here, ply_fade_kernels._outline_compiled),
        "mapping": (
            ply_friction_pass._mapping_here,
            ply_friction_kernels._return_mapping_compiled,
        ),
        "moved": (ply_friction_pass._moved_here, ply_friction_kernels._moved_compiled),
    }
    for name, (stage, kernel) in fused.items():
        assert stage is kernel.serial, name
    monkeypatch.setattr(ply_projection, "COMPILED", True)
    facing = {name: kernel for name, (_, kernel) in list(fused.items())[:5]}
    before = {name: len(_signatures(kernel)) for name, kernel in facing.items()}
    block, positions, directors, _ = _fan()
    zero = np.zeros_like(positions[0])
    state = State(positions[700], directors, zero, zero)
    assert block.facing(state).touching.any()  # fused (elements/ply_facing_whole.py)
    monkeypatch.setattr(ply_projection, "SMALL_LOOP", 0)
    block._facing_at = None
    block.facing(state, second=True)  # the kernels one by one
    added = {name: len(_signatures(kernel)) - before[name] for name, kernel in facing.items()}
    assert all(count <= 1 for count in added.values()), added


def test_read_only_gives_a_read_only_c_contiguous_view_and_leaves_the_caller_s_array():
    """``read_only``: no copy of a C-contiguous float64 array (a view, the caller's flag
    kept), the array itself where it is read-only already, a copy of another layout or
    dtype."""
    a = np.arange(12.0).reshape(4, 3)
    view = read_only(a)
    assert not view.flags.writeable and np.shares_memory(view, a) and a.flags.writeable
    a.setflags(write=False)
    assert read_only(a) is a
    strided = np.arange(24.0).reshape(4, 6)[:, ::2]
    copied = read_only(strided)
    assert copied.flags.c_contiguous and not copied.flags.writeable
    assert np.array_equal(copied, strided)
    assert read_only(np.arange(4), np.float64).dtype == np.float64


def test_the_loads_are_built_once_with_a_fresh_and_a_kept_return_mapping(monkeypatch):
    """The two-ply Mindlin [0/90] hemisphere blank (8 cells) bent 5 then 5.2 mm: its loads from
    a history's fresh return mapping and from the one its history's pass kept for them
    (ply_friction_kernels) reach ``ply_load_kernels._loads`` as arrays of one type: one
    build (a kept mapping made read-only was a second)."""
    from test_ply_kernels import _bent

    from elements.ply_block import PlyContactBlock
    from validation.studies import hemisphere_plies_setup as setup

    monkeypatch.setattr(ply_projection, "COMPILED", True)
    _, model = setup.model(8, setup.LAYUPS["0/90"], "mindlin", 20.0)
    compiled = model.compile()
    first, second = _bent(compiled, 3, 5.0), _bent(compiled, 3, 5.2)
    for block in (b for b in compiled.interactions if isinstance(b, PlyContactBlock)):
        history = block.update_history(first, block.initial_history())
        block.internal_force(first, history)  # a fresh mapping
        later = block.update_history(second, history)
        block.internal_force(second, later)  # the kept one
        assert block._next_sliding is not None and block._next_sliding[0] is later
    assert len(_signatures(ply_load_kernels._loads)) == 1
