"""A node-to-tool contact's passes over its rows, compiled (on the threads of femcore/jit.py
where each row is its own): its nodes' positions less a translation, its forces added into
the model's nodal sums in place, and their total. Each gives the numbers of the numpy
expression it replaces to the last bit, on any number of threads.

* ``shifted(x, c)`` is ``x - c`` for x (s, 3) and c (3,): numpy's broadcast runs an inner
  loop of 3 a row, 0.3 ms for 50k nodes on one thread, where a driven tool's positions (less
  its translation) and a meshed tool's (in its frame) are asked at every step.
* ``add_node_forces`` is what ``InteractionBlock.add_internal_force`` does by default with
  the (n, 3) array that ``ContactBlock.internal_force`` scatters by ``np.bincount``, without
  that array. The bincount scatter of the forces -f (s, 3) gives a node listed once 0 + (-f),
  and a driven tool's own node, which takes the reaction of every row, 0 + f_0 + f_1 + ...
  in row order; the model then adds that array to its sums. Here a node gets 0 - f added
  (the same number: -f, and +0 for a zero force, as 0 + (-0)), each row on its own thread (a
  node listed once: no two rows write to the same place), and the tool's node the sum of the
  rows in row order, serial. (The nodes the rows miss keep their sums, where adding the
  array's +0 would turn a -0 into +0: the model's sums start from +0, and a sum from +0 is
  never -0 in round-to-nearest.)
* ``row_sums(f)`` is ``f.sum(axis=0)`` for f (s, 3): numpy sums along the first axis of a
  C-ordered array row after row (f_0 + f_1 + ..., each column apart), with an inner loop of
  3 a row (0.74 ms for 50k rows, the moving punch's work at every step); here the same
  additions in the same order, serial.
* ``same_rows(a, b)`` is ``np.array_equal(a, b)`` for two float arrays (s, 3): whether a
  tool is asked about the points of its last call again (its answer then from memory).
  numpy compares every entry into a boolean array before it reduces it; the points of two
  steps differ at their first row, where this loop stops: 0.14 ms a call of the die's
  contact on the 20k-triangle forming blank (10201 rows, one thread, load 8) on the main
  thread, now a few microseconds.

Why: on the 100k-triangle forming blank these made most of the die's, the punch's and the
holder's share of the step that ran on one thread whatever the threads
(benchmarks/threads.py).
"""

from __future__ import annotations

import numpy as np

from elements.kernel_inputs import writable
from femcore.jit import jit, prange, serial, unsigned

__all__ = ["add_node_forces", "distinct_nodes", "row_sums", "same_rows", "shifted"]


def _shifted(x, shift, out):
    """out = x - shift: x, out (s, 3); shift (3,)."""
    for row in prange(x.shape[0]):
        i = unsigned(row)  # an index numba need not test for < 0 (femcore/jit.py)
        out[i, 0] = x[i, 0] - shift[0]
        out[i, 1] = x[i, 1] - shift[1]
        out[i, 2] = x[i, 2] - shift[2]


def _add_rows(forces, connectivity, out):
    """out[connectivity[i, 0]] += 0 - forces[i] for each row i: forces (s, 3), N;
    connectivity (s, 1) or (s, 2) int, C-ordered, its first column's nodes each listed once;
    out (n, 3). (The whole rows, not their first column: a column of (s, 2) rows is a strided
    array and (s, 1) rows' a contiguous one, two builds of the kernel for one loop.)"""
    for row in prange(forces.shape[0]):
        i = unsigned(row)
        node = unsigned(connectivity[i, 0])  # a node id, not negative
        out[node, 0] += 0.0 - forces[i, 0]
        out[node, 1] += 0.0 - forces[i, 1]
        out[node, 2] += 0.0 - forces[i, 2]


def _row_sums(forces, first, out):
    """out (3,) += forces[first] + forces[first + 1] + ..., in row order."""
    x, y, z = out[0], out[1], out[2]
    for i in range(first, forces.shape[0]):
        x += forces[i, 0]
        y += forces[i, 1]
        z += forces[i, 2]
    out[0], out[1], out[2] = x, y, z


def _same_rows(a, b):
    """Whether a and b (s, 3) hold equal numbers everywhere (a NaN equals nothing)."""
    for i in range(a.shape[0]):
        for j in range(3):
            if not a[i, j] == b[i, j]:
                return False
    return True


_shifted = jit(_shifted)
_add_rows = jit(_add_rows)
_row_sums = serial(_row_sums)
_same_rows = serial(_same_rows)


def same_rows(a: np.ndarray, b: np.ndarray) -> bool:
    """``np.array_equal(a, b)`` for two float arrays: the same shape and equal numbers
    everywhere (-0 equals +0, a NaN equals nothing), compared in one compiled loop over (s, 3)
    rows that stops at the first difference (module docstring); numpy's comparison for other
    shapes."""
    if a.shape != b.shape:
        return False
    if a.ndim == 2 and a.shape[1] == 3 and a.dtype == b.dtype == np.float64:
        # C-contiguous and writable, as the contacts hand their rows (a copy of another
        # layout or of a read-only array): one build of the loop (elements/kernel_inputs.py)
        return bool(_same_rows(writable(a), writable(b)))
    return bool(np.array_equal(a, b))


def shifted(x: np.ndarray, shift: np.ndarray) -> np.ndarray:
    """x - shift, a new (s, 3) array: x (s, 3), shift (3,) (module docstring)."""
    x = np.ascontiguousarray(x, dtype=np.float64)
    out = np.empty_like(x)
    _shifted(x, np.ascontiguousarray(shift, dtype=np.float64), out)
    return out


def row_sums(forces: np.ndarray) -> np.ndarray:
    """(3,) the sum of the rows of ``forces`` (s, 3), in row order: ``forces.sum(axis=0)``'s
    numbers (module docstring); zeros for no row."""
    if not len(forces):
        return np.zeros(3)
    forces = np.ascontiguousarray(forces, dtype=np.float64)
    out = forces[0].copy()  # numpy's sum starts from the first row
    _row_sums(forces, 1, out)
    return out


def distinct_nodes(connectivity: np.ndarray) -> bool:
    """Whether the rows' first nodes ``connectivity[:, 0]`` ((s, 1) or (s, 2) int) are each
    listed once: the rows may then be added on several threads (``add_node_forces``)."""
    nodes = connectivity[:, 0]
    return len(np.unique(nodes)) == len(nodes)


def add_node_forces(connectivity: np.ndarray, forces: np.ndarray, out: np.ndarray) -> None:
    """The internal forces of a node-to-tool block added into ``out`` (n, 3) in place: -f at
    each row's node and, where the rows are (node, tool node) pairs, their sum f at the tool
    node (module docstring).

    Parameters
    ----------
    connectivity : (s, 1) or (s, 2) int
        Each row's node (listed once: ``distinct_nodes``) and the tool's node, the same in
        every row.
    forces : (s, 3) float
        The forces the tool exerts on the nodes, N.
    out : (n, 3) float, C-contiguous
        The model's nodal internal forces, N.
    """
    forces = np.ascontiguousarray(forces, dtype=np.float64)
    _add_rows(forces, np.ascontiguousarray(connectivity, dtype=np.int64), out)
    if connectivity.shape[1] > 1 and len(connectivity):
        total = np.zeros(3)  # bincount's 0 + f_0 + f_1 + ...
        _row_sums(forces, 0, total)
        out[connectivity[0, 1]] += total
