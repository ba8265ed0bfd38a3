"""The work arrays a shell block keeps between its compiled passes (femcore/workspace.py):
they save the step the system's zeroing of fresh pages, and must carry nothing from one call
to the next. Every answer here is held to the bits of the same block computing with arrays
made afresh at each call (``Fresh``, what the passes did before the workspace): two blocks
stepping in turns, blocks of other sizes sharing one workspace, a block pickled and
unpickled, threads calling one block at once, one and all numba threads."""

from __future__ import annotations

import copy
import dataclasses
import pickle
import sys
import threading

import numpy as np
import pytest

from elements import FibrousShell, MindlinShell
from elements.fibrous.fold_branch import branch_view, initial_branch
from femcore import Mesh, Model
from femcore.workspace import Fresh, Workspace, workspace_of
from materials import ElasticShell, Fabric
from solvers.step import LumpedMasses, explicit_step
from tests.thread_runs import on_one_thread_and_on_all


def _element(kind: str):
    if kind == "fibrous":
        return FibrousShell(
            Fabric(thickness=1.0, areal_density=1e-9, tension=500.0, shear=0.5, bending=2.0)
        )
    return MindlinShell(ElasticShell(E=70e3, nu=0.3, thickness=1.0, density=2.7e-9))


def _model(kind: str, cells: int):
    """A pinned square sheet of 2 cells^2 triangles under gravity (compiled kernels)."""
    model = Model(Mesh.rectangle(10.0 * cells, 10.0 * cells, nx=cells, ny=cells))
    model.add(_element(kind))
    for edge in ("left", "right", "bottom", "top"):
        model.fix(edge, ["ux", "uy", "uz"])
    model.gravity((0.0, 0.0, -9.81e3))
    return model.compile()


def _jittered(compiled, seed: int):
    """The initial state with its positions and directors moved at random."""
    state = compiled.initial_state()
    rng = np.random.default_rng(seed)
    state.positions = state.positions + rng.normal(scale=0.3, size=state.positions.shape)
    directors = state.directors + rng.normal(scale=0.2, size=state.directors.shape)
    state.directors = directors / np.linalg.norm(directors, axis=1)[:, None]
    return state


def _loads(block, state) -> np.ndarray:
    """(n, 7): the block's forces, moments and (in the last column) its strain energy, from
    ``internal_force_and_energy``, then ``internal_force`` and ``strain_energy`` alone."""
    force, moment, energy = block.internal_force_and_energy(state)
    again = np.hstack(block.internal_force(state))
    np.testing.assert_array_equal(again, np.hstack([force, moment]))
    assert block.strain_energy(state) == energy
    return np.hstack([force, moment, np.full((len(force), 1), energy)])


def _fresh_loads(block, state) -> np.ndarray:
    """``_loads`` with every work array made afresh (the passes before the workspace)."""
    kept = block._workspace
    block._workspace = Fresh()
    try:
        return _loads(block, state)
    finally:
        block._workspace = kept


KINDS = ["fibrous", "mindlin"]


def test_a_workspace_keeps_an_array_of_the_same_shape_and_makes_another_for_a_new_one():
    work = Workspace()
    with work.lease() as lent:
        first = lent.empty("force", (5, 3, 3))
        assert lent.empty("force", (5, 3, 3)) is first
        assert lent.empty("force", (5, 3, 3), np.float32) is not first
        other = lent.empty("force", (7, 3, 3))
        assert other.shape == (7, 3, 3)
        assert lent.empty("force", (0, 3, 3)).shape == (0, 3, 3)  # made, not kept
        assert lent.empty("force", (7, 3, 3)) is other
    assert work.nbytes == 7 * 9 * 8
    work.clear()
    assert work.nbytes == 0


def test_a_second_lease_while_one_is_held_gets_arrays_of_its_own():
    work = Workspace()
    with work.lease() as outer:
        kept = outer.empty("a", (4,))
        with work.lease() as inner:
            assert isinstance(inner, Fresh)
            assert inner.empty("a", (4,)) is not kept
    with work.lease() as again:  # released: the kept array again
        assert again.empty("a", (4,)) is kept


def test_a_pickled_or_deep_copied_workspace_is_empty_and_a_shallow_copy_of_its_owner_shares_it():
    class Owner:
        pass

    owner = Owner()
    work = workspace_of(owner)
    assert workspace_of(owner) is work
    with work.lease() as lent:
        lent.empty("a", (1000,))
    assert work.nbytes == 8000
    for copied in (pickle.loads(pickle.dumps(work)), copy.deepcopy(work), copy.copy(work)):
        assert isinstance(copied, Workspace) and copied.nbytes == 0
    assert len(pickle.dumps(work)) < 200
    assert copy.copy(owner)._workspace is work


@pytest.mark.parametrize("kind", KINDS)
def test_two_blocks_in_turns_each_give_the_bits_of_arrays_made_afresh(kind):
    """Two models of different sizes, their loads asked in turns at two states each: each
    the same to the bit as with fresh arrays, the workspace kept (it holds the cell pass's
    arrays after a call: the fibrous (m, 3, 3) corner loads; the Mindlin cells' energies, its
    one-thread pass adding its loads to the nodes without a buffer, elements/kernels.py)."""
    models = [_model(kind, 6), _model(kind, 9)]
    states = [[_jittered(c, seed) for seed in (1, 2)] for c in models]
    expected = [[_fresh_loads(c.blocks[0], s) for s in pair] for c, pair in zip(models, states)]
    for _ in range(2):
        for i in (1, 0):
            for j in (0, 1):
                got = _loads(models[i].blocks[0], states[i][j])
                np.testing.assert_array_equal(got, expected[i][j])
    for compiled in models:
        cells = len(compiled.blocks[0].connectivity)
        assert compiled.blocks[0]._workspace.nbytes >= 8 * (9 if kind == "fibrous" else 1) * cells


@pytest.mark.parametrize("kind", KINDS)
def test_blocks_of_other_cell_counts_sharing_one_workspace_give_their_own_bits(kind):
    """One workspace lent to a 4-cell^2 and a 7-cell^2 sheet in turns (a block whose cell
    count changed between calls): each call gets arrays of its own shape."""
    small, large = _model(kind, 4), _model(kind, 7)
    shared = small.blocks[0]._workspace
    large.blocks[0]._workspace = shared
    pairs = [(small, _jittered(small, 3)), (large, _jittered(large, 4))]
    expected = [_fresh_loads(c.blocks[0], s) for c, s in pairs]
    for _ in range(2):
        for (compiled, state), want in zip(pairs, expected):
            np.testing.assert_array_equal(_loads(compiled.blocks[0], state), want)


@pytest.mark.parametrize("kind", KINDS)
def test_a_pickled_block_carries_no_work_arrays_and_gives_the_same_bits(kind):
    compiled = _model(kind, 8)
    block, state = compiled.blocks[0], _jittered(compiled, 5)
    before = len(pickle.dumps(block))
    expected = _loads(block, state)
    assert block._workspace.nbytes > 0
    assert len(pickle.dumps(block)) - before < 200  # not the kept arrays' bytes
    copied = pickle.loads(pickle.dumps(block))
    assert copied._workspace is not block._workspace and copied._workspace.nbytes == 0
    np.testing.assert_array_equal(_loads(copied, state), expected)
    np.testing.assert_array_equal(_loads(block, state), expected)


def test_the_fibrous_blocks_view_past_a_flat_fold_shares_its_workspace():
    compiled = _model("fibrous", 5)
    block = compiled.blocks[0]
    history = initial_branch(block)
    turns = history.turns.copy()
    turns[tuple(np.argwhere(block.interior_side)[0])] = 1.0  # one side turned once
    history = dataclasses.replace(history, turns=turns)
    view = branch_view(block, history)
    assert view is not block and view._workspace is block._workspace


@pytest.mark.parametrize("kind", KINDS)
def test_a_call_while_the_workspace_is_lent_leaves_the_lent_arrays_alone(kind):
    """What a second caller (another thread) meets when the block's arrays are lent: it
    computes its own loads, to the bit, and does not write the arrays the first one holds."""
    compiled = _model(kind, 8)
    block = compiled.blocks[0]
    first, second = _jittered(compiled, 8), _jittered(compiled, 9)
    expected = _fresh_loads(block, second)
    _loads(block, first)
    with block._workspace.lease():
        held = {name: array.copy() for name, array in block._workspace._arrays.items()}
        np.testing.assert_array_equal(_loads(block, second), expected)
        for name, array in block._workspace._arrays.items():
            np.testing.assert_array_equal(array, held[name])
    assert held


@pytest.mark.parametrize("kind", KINDS)
def test_threads_asking_one_block_at_once_get_their_own_bits(kind):
    """Two threads asking one block for its loads at two states, switching as often as the
    interpreter allows: each answer that of its state (the second caller gets fresh arrays
    while the first holds the kept ones)."""
    compiled = _model(kind, 8)
    block = compiled.blocks[0]
    states = [_jittered(compiled, seed) for seed in (6, 7)]
    expected = [_fresh_loads(block, s) for s in states]
    wrong: list[str] = []

    def ask(index: int) -> None:
        for _ in range(40):
            try:
                got = _loads(block, states[index])
            except Exception as error:  # noqa: BLE001 - reported by the test's own thread
                wrong.append(f"{index}: {error!r}")
                return
            if not np.array_equal(got, expected[index]):
                wrong.append(f"{index}: other loads")

    interval = sys.getswitchinterval()
    sys.setswitchinterval(1e-6)
    try:
        threads = [threading.Thread(target=ask, args=(i,)) for i in (0, 1)]
        for thread in threads:
            thread.start()
        for thread in threads:
            thread.join()
    finally:
        sys.setswitchinterval(interval)
    assert wrong == []


@pytest.mark.parametrize("kind", KINDS)
def test_explicit_steps_of_two_models_in_turns_are_each_models_own_on_one_and_all_threads(kind):
    """Twelve explicit steps of two models taken in turns (one step of each, every third
    step checking the energy): the positions and strain energies of each model's run alone
    with fresh arrays, to the bit, on one numba thread and on all."""

    def run(fresh: bool, alone: int | None):
        models = [_model(kind, 6), _model(kind, 8)]
        runs = []
        for compiled in models:
            if fresh:
                compiled.blocks[0]._workspace = Fresh()
            state = compiled.initial_state()
            dt = 0.5 * compiled.stable_dt(state)
            runs.append([compiled, state, dt, LumpedMasses.of(compiled, state), 0.0, []])
        for step in range(12):
            for index, run_ in enumerate(runs):
                if alone is not None and index != alone:
                    continue
                compiled, state, dt, masses, previous, energies = run_
                outcome = explicit_step(
                    compiled, state, dt, masses, dt_prev=previous, duration=12 * dt,
                    checking=step % 3 == 0,
                )  # fmt: skip
                run_[1], run_[4] = compiled.commit(outcome.state), dt
                energies.append(outcome.strain_energy)
        return [np.append(r[1].positions.ravel(), [e or 0.0 for e in r[5]]) for r in runs]

    one, every = on_one_thread_and_on_all(lambda: run(False, None))
    alone = [run(True, index)[index] for index in (0, 1)]
    for index in (0, 1):
        np.testing.assert_array_equal(one[index], alone[index])
        np.testing.assert_array_equal(every[index], alone[index])


def test_the_fibrous_normal_pulls_are_the_callers_own():
    """``normal_pulls`` (the static solver's level projection) returns an array of its own,
    not one the next call writes."""
    from elements.fibrous.kernels import normal_pulls

    compiled = _model("fibrous", 6)
    block = compiled.blocks[0]
    first, second = _jittered(compiled, 10), _jittered(compiled, 11)
    pulls = normal_pulls(block, first.positions, first.directors)
    kept = pulls.copy()
    other = normal_pulls(block, second.positions, second.directors)
    assert not np.array_equal(other, kept)
    np.testing.assert_array_equal(pulls, kept)


@pytest.mark.parametrize("kind", KINDS)
def test_the_forces_moments_and_energies_a_block_returns_are_the_callers_own(kind):
    """What ``internal_force`` and ``internal_force_and_energy`` return is made afresh (the
    workspace's rule, femcore/workspace.py): answers kept from one call, not copied, are
    unchanged by the next call on the same block at other positions."""
    compiled = _model(kind, 6)
    block = compiled.blocks[0]
    first, second = _jittered(compiled, 12), _jittered(compiled, 13)
    force, moment, energy = block.internal_force_and_energy(first)
    alone = block.internal_force(first)
    kept = [force.copy(), moment.copy(), np.copy(energy)] + [a.copy() for a in alone]
    other_force, other_moment, _ = block.internal_force_and_energy(second)
    block.internal_force(second)
    assert not np.array_equal(other_force, kept[0])
    for answer, copied in zip([force, moment, energy, *alone], kept, strict=True):
        np.testing.assert_array_equal(answer, copied)
