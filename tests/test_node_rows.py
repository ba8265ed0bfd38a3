"""A contact's compiled passes over its rows (elements/node_rows.py) give the numbers of the
numpy expressions they replace to the last bit, on one thread and on all; a contact block
adds its forces into the model's sums in place as the sum of its ``internal_force``."""

import numpy as np
import pytest

from elements import node_rows
from elements.node_rows import add_node_forces, distinct_nodes, row_sums, shifted
from femcore import jit
from femcore.assembly import Scatter
from validation.cases import hemisphere_forming

pytestmark = pytest.mark.skipif(not jit.AVAILABLE, reason="numba is not installed")


def bits(array: np.ndarray) -> bytes:
    return np.ascontiguousarray(array).tobytes()


def rows(count: int, seed: int = 3) -> np.ndarray:
    """(count, 3) forces of mixed signs and sizes, with exact zeros of both signs."""
    rng = np.random.default_rng(seed)
    forces = rng.normal(size=(count, 3)) * 10.0 ** rng.integers(-6, 4, size=(count, 1))
    forces[::7] = 0.0
    forces[3::11, 1] = -0.0
    return forces


@pytest.mark.parallel
def test_the_passes_give_numpys_numbers_to_the_last_bit():
    """x - c, f.sum(axis=0) and the bincount scatter of -f (the rows' nodes -f, a driven
    tool's node the sum f of every row, in row order) added to a model's sums, bit for bit,
    over more rows than a loop runs on one thread."""
    count, n_nodes = 6017, 8000
    forces = rows(count)
    x = rows(count, seed=5)
    c = np.array([0.3, -1e-3, 7.0])
    assert bits(shifted(x, c)) == bits(x - c)
    assert bits(row_sums(forces)) == bits(forces.sum(axis=0))
    nodes = np.random.default_rng(7).permutation(n_nodes - 1)[:count]
    tool = n_nodes - 1
    for connectivity in (nodes[:, None], np.column_stack([nodes, np.full(count, tool)])):
        assert distinct_nodes(connectivity)
        per_row = forces[:, None, :]
        if connectivity.shape[1] == 2:
            per_row = np.concatenate([per_row, -per_row], axis=1)
        before = rows(n_nodes, seed=9) + 0.0  # a sum from +0 holds no -0 (module docstring)
        expected = before + Scatter(connectivity, n_nodes).vectors(-per_row)
        added = before.copy()
        add_node_forces(connectivity, forces, added)
        assert bits(added) == bits(expected)
    assert not distinct_nodes(np.array([[1], [2], [1]]))
    # One build of the loop for both shapes of rows (a column of (s, 2) rows is strided, of
    # (s, 1) rows contiguous: two builds, each compiled in a fresh checkout, before).
    loop = node_rows._add_rows
    builds = [b for b in (loop.serial, loop._parallel) if b is not None and b.signatures]
    assert builds and [len(b.signatures) for b in builds] == [1] * len(builds)


@pytest.mark.parallel
def test_a_contact_adds_its_forces_in_place_as_the_sum_of_its_internal_force():
    """The forming blank's die (a meshed tool), punch and driven holder
    (``ContactBlock.add_internal_force``, each node once; the holder's node takes the
    reaction) and the model's sum of its parts: the numbers of the protocol's default, the
    arrays of ``internal_force`` added, bit for bit, on all threads."""
    _, model = hemisphere_forming.model(36, "fibrous")  # 1369 nodes a contact
    compiled = model.compile()
    state = compiled.initial_state()
    rng = np.random.default_rng(2)
    state.positions = state.positions + rng.normal(scale=0.05, size=state.positions.shape)
    state.positions[:, 2] -= 0.3  # into the die, the holder pressing
    state.load_factor = 1.0  # the punch at the end of its stroke, through the blank
    histories = compiled._histories(state)
    total_force, total_moment = np.zeros_like(state.positions), np.zeros_like(state.positions)
    for part, history in zip(compiled.parts, histories):
        force, moment = part.internal_force(state, history)
        total_force += force
        if moment is not None:
            total_moment += moment
    for part, history in zip(compiled.interactions, histories[len(compiled.blocks) :]):
        assert np.abs(part.contact_forces(state, history)).max() > 0.0  # each one presses
        before = rows(compiled.n_nodes) + 0.0
        expected = before + part.internal_force(state, history)[0]
        moment = np.zeros_like(before)
        part.add_internal_force(state, history, before, moment)
        assert bits(before) == bits(expected)
        assert not moment.any()
    force, moment = compiled.internal_force(state)
    assert bits(force) == bits(total_force)
    assert bits(moment) == bits(total_moment)


def test_same_rows_answers_as_numpys_array_equal():
    """``same_rows`` (a tool asked about the points of its last call) against np.array_equal:
    equal arrays, a copy, one entry changed at the first, a middle and the last row, -0
    against +0 (equal), a NaN (equal to nothing, itself included), another length, a
    strided view, no rows."""
    from elements.node_rows import same_rows

    a = rows(5000)
    cases = [(a, a), (a, a.copy()), (a, a[:-1]), (a[::2], a[::2].copy()), (a[:0], a[:0])]
    for row in (0, 2500, 4999):
        b = a.copy()
        b[row, 2] = np.nextafter(b[row, 2], np.inf)
        cases.append((a, b))
    signed = a.copy()
    signed[a == 0.0] = -0.0
    cases.append((a, signed))
    with_nan = a.copy()
    with_nan[100, 1] = np.nan
    cases += [(with_nan, with_nan), (with_nan, with_nan.copy())]
    answers = [same_rows(x, y) for x, y in cases]
    assert answers == [bool(np.array_equal(x, y)) for x, y in cases]
    assert answers == [True, True, False, True, True, False, False, False, True, False, False]
