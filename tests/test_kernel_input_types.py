"""Kernels handed one set of argument types whoever calls them: numba builds a kernel once for
each set of types it is called with, and an array's type holds its layout and whether it is
writable, so a kernel called with a read-only array in one place and a writable (or strided)
one in another is compiled twice, the second build the same machine code. A run of the ply
tests on an empty cache built five kernels twice (benchmarks/suite_signatures.py: the return
mapping, the faces' offsets' directions, the edge couples, the cut's closest point and the
rows' comparison); their wrappers now hand their inputs through ``elements.kernel_inputs``.

Each test calls a kernel's wrapper the ways the library and the tests do (the block's
read-only facing and a caller's writable arrays, C-ordered and strided) and records the types
the compiled kernel is handed (``numba.typeof``, the types numba's dispatcher builds for):
one set. Recorded rather than read from the dispatchers, whose builds depend on what numba's
cache held and what ran before in the process. Reference: numba's typing; no tolerance. The
kernels' numbers against numpy's are their own tests' (tests/test_ply_kernels.py,
test_ply_stick_spring_pass.py, test_ply_edge_couple.py, test_ply_cut_kernels.py,
test_node_rows.py).
"""

import dataclasses
from types import SimpleNamespace

import numpy as np
import pytest

from elements import (
    node_rows,
    ply_cut_kernels,
    ply_edge_couple_kernels,
    ply_face_points,
    ply_fade_kernels,
    ply_friction_kernels,
    ply_projection,
)
from femcore import jit

pytestmark = pytest.mark.skipif(not jit.AVAILABLE, reason="numba is not installed")


def _recorded(monkeypatch, module, name: str) -> list[tuple]:
    """The numba types of the arguments of each call of ``module.name`` from now on (the
    kernel still runs)."""
    import numba

    kernel = getattr(module, name)
    calls: list[tuple] = []

    def record(*arguments):
        calls.append(tuple(numba.typeof(a) for a in arguments))
        return kernel(*arguments)

    monkeypatch.setattr(module, name, record)
    return calls


def _frozen(namespace):
    """A copy of a facing (a dataclass or a namespace) with its arrays read-only, as
    ``PlyContactBlock.facing`` keeps them."""

    def read_only(value):
        if not isinstance(value, np.ndarray):
            return value
        copy = value.copy()
        copy.setflags(write=False)
        return copy

    if dataclasses.is_dataclass(namespace):
        fields = {
            f.name: read_only(getattr(namespace, f.name)) for f in dataclasses.fields(namespace)
        }
        return dataclasses.replace(namespace, **fields)
    return SimpleNamespace(**{k: read_only(v) for k, v in vars(namespace).items()})


def _thawed(namespace):
    """A copy of a facing with its arrays writable (a caller's fresh ones)."""
    fields = {
        f.name: (v.copy() if isinstance(v := getattr(namespace, f.name), np.ndarray) else v)
        for f in dataclasses.fields(namespace)
    }
    return dataclasses.replace(namespace, **fields)


def test_the_return_mapping_is_handed_one_set_of_types(monkeypatch):
    """tests/test_ply_stick_spring_pass.py's 600 points: its facing's arrays writable (the
    test's own) and read-only (as the block keeps a facing). Two sets before."""
    from tests.test_ply_stick_spring_pass import _contact

    monkeypatch.setattr(ply_projection, "COMPILED", True)
    calls = _recorded(monkeypatch, ply_friction_kernels, "_return_mapping_compiled")
    block, facing, history = _contact(0.05, "normal law", 0)
    for given in (facing, _frozen(facing)):
        ply_friction_kernels.friction_state(block, None, history, given)
    assert len(calls) == 2 and len(set(calls)) == 1


def test_the_offsets_directions_are_handed_one_set_of_types(monkeypatch):
    """``offset_toward`` with the directions the block keeps (read-only) and a caller's
    (writable), and with its other inputs read-only: one set (two before)."""
    calls = _recorded(monkeypatch, ply_face_points, "_toward")
    rng = np.random.default_rng(0)
    d = rng.normal(size=(12, 3))
    above = rng.integers(0, 12, (20, 3))
    offset, shape = rng.uniform(size=(20, 3)), rng.dirichlet(np.ones(3), 20)
    ply_face_points.offset_toward(d, above, offset, shape)
    frozen = [a.copy() for a in (d, above, offset, shape)]
    for a in frozen:
        a.setflags(write=False)
    ply_face_points.offset_toward(*frozen)
    assert len(calls) == 2 and len(set(calls)) == 1


def test_the_edge_couples_are_handed_one_set_of_types(monkeypatch):
    """tests/test_ply_edge_couple.py's cut strip faced by 400 points: the couples of its
    points facing an edge from the facing read-only (the block's) and writable (a caller's),
    offsets and forces writable and read-only. One set (two before)."""
    from tests.test_ply_edge_couple import _cut_strip_facing

    monkeypatch.setattr(ply_projection, "COMPILED", True)
    calls = _recorded(monkeypatch, ply_edge_couple_kernels, "_couples")
    rng, y, cuts, facing = _cut_strip_facing(0, hessian=False)
    rows = np.flatnonzero(facing.on_edge)
    offset, force = rng.normal(size=(len(facing.gap), 3)), rng.normal(size=(len(facing.gap), 3))
    frozen = [a.copy() for a in (y, offset, force)]
    for a in frozen:
        a.setflags(write=False)
    ply_edge_couple_kernels.edge_couples(_thawed(facing), y, cuts, rows, offset, force)
    ply_edge_couple_kernels.edge_couples(_frozen(facing), frozen[0], cuts, rows, *frozen[1:])
    assert len(calls) == 2 and len(set(calls)) == 1


def test_the_cuts_closest_point_is_handed_one_set_of_types_by_both_its_callers(monkeypatch):
    """``closest_cut_at``, a helper compiled with each kernel that calls it: the rows the
    cut's pass (``closest_on_cut``) hands it and those the fade's pass (``outline_fade_at``)
    hands it have one set of types, each caller's inputs writable or read-only. Facing the
    cut strip of tests/test_ply_edge_couple.py calls both passes. Two sets before (the
    fade's points and corners read-only, the cut's pass's writable)."""
    from tests.test_ply_edge_couple import _cut_strip_facing

    monkeypatch.setattr(ply_projection, "COMPILED", True)
    # the chained passes (a small facing without the Hessian runs them in two fused calls,
    # elements/ply_facing_whole.py, which compiles the helper with its own kernels)
    monkeypatch.setattr(ply_projection, "WHOLE", False)
    cut_calls = _recorded(monkeypatch, ply_cut_kernels, "_closest_compiled")
    fade_calls = _recorded(monkeypatch, ply_fade_kernels, "_outline_compiled")
    _cut_strip_facing(0, hessian=False)
    rng = np.random.default_rng(3)
    # p (5, 3), corners (5, 3, 3), q (5, 3), lines, ends, gradients (5, 3, 3)
    arrays = [rng.normal(size=(5, 3) if k in (0, 2) else (5, 3, 3)) for k in range(6)]
    ply_cut_kernels.closest_on_cut(*arrays, 0.5)
    for a in arrays:
        a.setflags(write=False)
    ply_cut_kernels.closest_on_cut(*arrays, 0.5)
    assert cut_calls and fade_calls

    def row(kind):  # the type of one row of an array of numba type ``kind``
        return kind.copy(ndim=kind.ndim - 1)

    # _closest(p, corners, q, lines, ends, gradients, keep, out, cut, segment, along) hands
    # closest_cut_at p[i], corners[i], q[i], lines[i], ends[i], gradients[i], keep, out[i],
    # segment[i]; _outline hands it p[i], y[t], q[j], lines[t], cut_ends[t], grad[i], keep,
    # cut_q[j], cut_segment[j] (its arguments 1, 2, 27, 18, 19, 5, 21, 29, 30)
    from_cut = {
        tuple(row(c[k]) if k != 6 else c[k] for k in (0, 1, 2, 3, 4, 5, 6, 7, 9)) for c in cut_calls
    }
    from_fade = {
        tuple(row(c[k]) if k != 21 else c[k] for k in (1, 2, 27, 18, 19, 5, 21, 29, 30))
        for c in fade_calls
    }
    assert len(from_cut) == 1 and from_cut == from_fade


def test_the_rows_comparison_is_handed_one_set_of_types(monkeypatch):
    """``same_rows`` on C-ordered rows, writable and read-only, and on strided ones (tests/
    test_node_rows.py's every other row): one set (the strided rows were a second build)."""
    calls = _recorded(monkeypatch, node_rows, "_same_rows")
    a = np.random.default_rng(0).normal(size=(40, 3))
    frozen = a.copy()
    frozen.setflags(write=False)
    for x, y in ((a, a.copy()), (a[::2], a[::2].copy()), (frozen, a)):
        assert node_rows.same_rows(x, y) == np.array_equal(x, y)
    assert len(calls) == 3 and len(set(calls)) == 1
