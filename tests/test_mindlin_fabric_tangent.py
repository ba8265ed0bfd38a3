"""elements/mindlin_fabric_tangent.py and elements/mindlin_fabric_loads.py: the compiled tangent
and forces of MindlinShell(fabric) give the numbers of their numpy references
(MindlinFabricBlock.numpy_cell_tangent, the elastic block's numpy path through the fabric
section's level response, and numpy_cell_loads; the tangent is checked against central
differences of the forces by the conformance suite, tests/conformance_cases.py, cases
mindlin-fabric and mindlin-fabric-nonlinear), the same bits on one thread and on all, and in
pieces as whole."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from elements import MindlinShell
from elements.mindlin_fabric_tangent import AVAILABLE, fabric_tangent_blocks
from femcore import Model
from femcore.rotation import rotate_about
from materials import presets
from tests.test_fabric_section_kernels import FABRICS
from tests.test_mindlin import CYLINDER, MESH

pytestmark = pytest.mark.skipif(not AVAILABLE, reason="numba missing")

SECTIONS = {"g986": presets.g986_stack(), "non-linear": FABRICS["non-linear"]}


def _block(mesh, fabric):
    model = Model(mesh)
    model.add(MindlinShell(fabric, warp=(1.0, 0.3, 0.0)))
    compiled = model.compile()
    return compiled, compiled.blocks[0]


def _bent_state(model, rng):
    """Stretched 2 % along x, its nodes jittered by 0.1 mm, its directors turned by about
    0.3 rad at every node: fibres in tension and compression, curvatures past the bending
    laws' knees, transverse shear, short of the shear lock."""
    state = model.initial_state()
    positions = state.positions * np.array([1.02, 0.99, 1.0])
    positions += rng.normal(scale=0.1, size=positions.shape)
    spin = rng.normal(scale=0.3 / np.sqrt(3), size=state.directors.shape)
    directors = rotate_about(state.directors, spin)
    return dataclasses.replace(state, positions=positions, directors=directors)


@pytest.mark.parametrize("name", SECTIONS)
@pytest.mark.parametrize("mesh", [MESH, CYLINDER], ids=["flat", "cylinder"])
def test_the_compiled_fabric_tangent_gives_the_numpy_blocks_to_1e_12(name, mesh):
    # The same terms summed in another order (B_y^T H B_y against B^T (P^T H P) B): agreement
    # to round-off of the largest entry, on the reference state and on a bent, jittered one.
    model, block = _block(mesh, SECTIONS[name])
    assert block.tangent_kernel == "compiled"
    rng = np.random.default_rng(3)
    for state in (model.initial_state(), _bent_state(model, rng)):
        fast = block.tangent(state)[0]
        x, v = state.positions[block.connectivity], state.directors[block.connectivity]
        reference = block.numpy_cell_tangent(x, v, slice(None))
        block.tangent_kernel = "numpy"
        try:
            sliced = block.tangent(state)[0].blocks
        finally:
            block.tangent_kernel = "compiled"
        np.testing.assert_array_equal(sliced, reference)
        scale = np.abs(reference).max()
        assert scale > 0.0
        assert np.abs(fast.blocks - reference).max() <= 1e-12 * scale


def test_the_fabric_tangent_in_pieces_is_the_whole_one_to_the_bit():
    model, block = _block(CYLINDER, SECTIONS["non-linear"])
    state = _bent_state(model, np.random.default_rng(5))
    whole = block.tangent(state)[0]
    pieces = list(block.tangent_pieces(state))
    np.testing.assert_array_equal(np.concatenate([p.nodes for p in pieces]), whole.nodes)
    np.testing.assert_array_equal(np.concatenate([p.blocks for p in pieces]), whole.blocks)


def _small_chunks(monkeypatch):
    """5 cells a chunk, so that the test meshes' loops have several to share out."""
    from elements import mindlin_fabric_loads, mindlin_fabric_measures, mindlin_fabric_tangent

    for module in (mindlin_fabric_loads, mindlin_fabric_measures, mindlin_fabric_tangent):
        monkeypatch.setattr(module, "CELLS_PER_CHUNK", 5)


@pytest.mark.parallel
def test_the_fabric_tangent_is_the_same_bits_on_one_thread_and_on_all(monkeypatch):
    from tests.thread_runs import on_one_thread_and_on_all

    _small_chunks(monkeypatch)

    model, block = _block(CYLINDER, SECTIONS["g986"])
    state = _bent_state(model, np.random.default_rng(9))
    one, every = on_one_thread_and_on_all(lambda: block.tangent(state)[0].blocks)
    np.testing.assert_array_equal(one, every)


def test_the_fabric_tangent_refuses_derivatives_of_the_wrong_shape():
    x = np.zeros((2, 3, 3))
    metric = {key: np.zeros((2, 3)) for key in ("11", "22", "12")} | {"tying": np.zeros((2, 3, 4))}
    tables = (np.zeros((3, 7, 6, 5)), np.zeros((3, 7, 6, 6)))
    with pytest.raises(ValueError, match="section derivatives"):
        fabric_tangent_blocks(
            x, x, np.array([-1.0, 0.0, 1.0]), 1.0, np.eye(3), metric, np.zeros((2, 10)),
            np.zeros((3, 10, 10)), *tables,
        )  # fmt: skip


def test_the_stable_step_calibration_takes_the_compiled_tangent_of_chosen_cells():
    # element_omega2 asks for the tangent of cells given by indices (the stable step's
    # calibration): the same largest eigenvalues as by the numpy tangent, to round-off.
    model, block = _block(CYLINDER, SECTIONS["g986"])
    state = _bent_state(model, np.random.default_rng(2))
    cells = np.array([5, 0, 7, 3])
    nodes = block.connectivity[cells]
    x, v = state.positions[nodes], state.directors[nodes]
    fast = block.element_omega2(x, v, cells)
    block.tangent_kernel = "numpy"
    try:
        reference = block.element_omega2(x, v, cells)
    finally:
        block.tangent_kernel = "compiled"
    np.testing.assert_allclose(fast, reference, rtol=1e-12)


@pytest.mark.parametrize("name", SECTIONS)
@pytest.mark.parametrize("mesh", [MESH, CYLINDER], ids=["flat", "cylinder"])
def test_the_compiled_fabric_loads_are_the_numpy_ones_to_1e_12(name, mesh):
    # elements/mindlin_fabric_loads.py: sigma . B^psi summed in another order than numpy's
    # matmul; round-off of the largest load.
    model, block = _block(mesh, SECTIONS[name])
    assert block.loads_kernel == "compiled"
    state = _bent_state(model, np.random.default_rng(4))
    x, v = state.positions[block.connectivity], state.directors[block.connectivity]
    for fast, reference in zip(block._cell_loads(x, v), block.numpy_cell_loads(x, v)):
        scale = np.abs(reference).max()
        assert scale > 0.0
        assert np.abs(fast - reference).max() <= 1e-12 * scale


@pytest.mark.parallel
def test_the_fabric_loads_are_the_same_bits_on_one_thread_and_on_all(monkeypatch):
    from tests.thread_runs import on_one_thread_and_on_all

    _small_chunks(monkeypatch)

    model, block = _block(CYLINDER, SECTIONS["non-linear"])
    state = _bent_state(model, np.random.default_rng(6))
    one, every = on_one_thread_and_on_all(lambda: block.internal_force(state))
    for a, b in zip(one, every):
        np.testing.assert_array_equal(a, b)


@pytest.mark.parametrize("mesh", [MESH, CYLINDER], ids=["flat", "cylinder"])
def test_the_compiled_section_measures_are_the_numpy_ones_to_1e_12(mesh):
    # elements/mindlin_fabric_measures.py: the dot products summed component by component;
    # round-off of the largest level product (|g1|^2, mm^2), which the measures are
    # differences of.
    model, block = _block(mesh, SECTIONS["g986"])
    state = _bent_state(model, np.random.default_rng(8))
    x, v = state.positions[block.connectivity], state.directors[block.connectivity]
    fast = block._measures(x, v)
    reference = block.section_measures(block._vectors(x, v))
    scale = float(block.reference_metric["11"].max())
    assert np.abs(reference).max() > 1e-3 * scale
    assert np.abs(fast - reference).max() <= 1e-12 * scale
    cells = np.array([4, 1])
    np.testing.assert_array_equal(block._measures(x[cells], v[cells], cells), fast[cells])
    energy = block.strain_energy(state)
    block.loads_kernel = "numpy"
    try:
        assert energy == pytest.approx(block.strain_energy(state), rel=1e-12)
    finally:
        block.loads_kernel = "compiled"


def test_the_fabric_loops_are_parted_so_no_thread_shares_a_cells_scratch():
    # A loop that allocates its scratch before the prange keeps numba's parallel build, whose
    # threads share that scratch (a race: one run of the same-bits test above failed so);
    # allocated per chunk of cells, the loop runs as parts of the plain build (femcore/jit.py).
    from elements import mindlin_fabric_loads, mindlin_fabric_measures, mindlin_fabric_tangent

    for kernel in (
        mindlin_fabric_tangent._fabric_tangent_cells,
        mindlin_fabric_loads._fabric_loads_cells,
        mindlin_fabric_measures._measures_cells,
    ):
        assert kernel.parted, kernel


def test_a_block_pickled_before_the_compiled_paths_were_chosen_loads_and_takes_them():
    """A model pickled before the block kept ``tangent_kernel`` and ``loads_kernel`` (a
    checkpoint of an earlier version): unpickled, the block takes the compiled paths and
    gives the fresh block's tangent and forces to the bit."""
    import pickle

    model, block = _block(MESH, SECTIONS["g986"])
    state = _bent_state(model, np.random.default_rng(5))
    fresh = block.tangent(state)[0], block.internal_force(state, None)
    for kept in ("tangent_kernel", "loads_kernel"):  # as an earlier version pickled it
        block.__dict__.pop(kept, None)
    loaded = pickle.loads(pickle.dumps(model)).blocks[0]
    assert loaded.tangent_kernel == "compiled" and loaded.loads_kernel == "compiled"
    np.testing.assert_array_equal(loaded.tangent(state)[0].blocks, fresh[0].blocks)
    for mine, theirs in zip(loaded.internal_force(state, None), fresh[1]):
        np.testing.assert_array_equal(mine, theirs)
