"""elements/fibrous/hessian_kernels.py: the compiled cell Hessians, normal-share Jacobians and
node-pair sums of the fibrous shell's membrane tangent give the numbers of their numpy
references in elements/fibrous/tangent.py and geometry.py.

Tolerance: 1e-12 of the largest entry. The loops add the same terms as the numpy formulas in
another order (A^T H_w A over A's nonzero rows, the level sums one level at a time), so the
two differ by round-off: a few units in the last place of the largest terms, ~1e-15 of them
(measured 2e-16 to 7e-16); 1e-12 leaves room for that on any platform and still catches any
missing or wrong term (the smallest term of the Hessian that a mistake would change is far
above 1e-12 of its largest on these cells). The node-pair sums add the same terms in the same
order as numpy.bincount: equal to the last bit.
"""

import numpy as np
import pytest

from elements import FibrousShell
from elements.fibrous import geometry, hessian_kernels, membrane, tangent
from femcore import Mesh, Model
from femcore.rotation import rotate_about
from materials import BendingLaw, Fabric, ShearLaw, TensionLaw, presets


def _table_fabric():
    """Tension tables (a tension-only warp the jittered sheet compresses and stretches past
    its last knot, a weft that takes compression) and a tabulated shear law."""
    return Fabric(
        thickness=3.0,
        areal_density=1e-9,
        tension=TensionLaw.table([0.0, 0.01, 0.05], [0.0, 20.0, 400.0], tension_only=True),
        tension_weft=TensionLaw.table([-0.02, 0.0, 0.03], [-2.0, 0.0, 90.0]),
        shear=ShearLaw.table([0.0, 0.05, 0.2, 0.4], [0.0, 0.1, 1.0, 6.0]),
        bending=BendingLaw.linear(20.0),
    )


def _polynomial_fabric():
    """A linear tension-only warp, a bilinear weft table and a cubic-quintic shear."""
    return Fabric(
        thickness=2.0,
        areal_density=1e-9,
        tension=TensionLaw.linear(300.0, tension_only=True),
        tension_weft=TensionLaw.table([-0.1, 0.0, 0.02, 0.5], [-1.0, 0.0, 4.0, 400.0]),
        shear=ShearLaw.polynomial(0.2, -0.1, 2.0),
        bending=BendingLaw.bilinear(20.0, 2.0, knee=0.01),
    )


FABRICS = {
    "g986": presets.g986_stack,
    "tables": _table_fabric,
    "polynomials": _polynomial_fabric,
}


def _cells(fabric, variation, seed=3, clamped=None, nx=6, ny=4):
    """A jittered nx x ny sheet (6 x 4: 48 cells) with tilted directors, one of them nearly
    in its plane (past the guard of h_m):
    its block and the corners, directors and normal sums of its cells."""
    mesh = Mesh.rectangle(40.0, 20.0, nx=nx, ny=ny)
    model = Model(mesh)
    model.add(FibrousShell(fabric, thickness_variation=variation, clamped=clamped))
    if clamped is not None:
        model.fix(mesh.nodes(clamped))
    compiled = model.compile()
    state = compiled.initial_state()
    rng = np.random.default_rng(seed)
    positions = state.positions + rng.normal(scale=0.7, size=state.positions.shape)
    turn = np.cross(state.directors, rng.normal(scale=0.3, size=state.positions.shape))
    directors = rotate_about(state.directors, turn)
    directors[7] = np.array([1.0, 0.2, 0.1]) / np.sqrt(1.05)  # V . N ~ 0.1 < the guard 0.2
    block = compiled.blocks[0]
    conn = block.connectivity
    sums = geometry.normal_sums(block, positions)[conn]
    return block, positions[conn], directors[conn], sums


@pytest.mark.parametrize("variation", [True, False])
@pytest.mark.parametrize("name", sorted(FABRICS))
def test_the_compiled_membrane_hessians_give_the_numpy_ones(name, variation):
    block, x, v, sums = _cells(FABRICS[name](), variation)
    geo = geometry.cell_geometry(block, x, v, True, sums)
    assert geo["guarded"].any()  # the guard's branch is exercised
    if name != "g986":  # the laws' branches: compressed tension-only fibres, beyond the tables
        eps = membrane.strains(block, geo)["eps1"]
        assert (eps < 0).any() and (eps > 0.05).any()
    expected, expected_sums = tangent.membrane_hessian(block, x, v, sums)
    got, got_sums = hessian_kernels.membrane_hessians(block, x, v, sums)
    assert np.abs(got - expected).max() <= 1e-12 * np.abs(expected).max()
    if variation:
        assert np.abs(got_sums - expected_sums).max() <= 1e-12 * np.abs(expected_sums).max()
    else:
        assert not got_sums.any() and not expected_sums.any()


def test_the_hessians_of_more_cells_than_two_chunks_are_the_numpy_ones_in_every_chunk():
    """140 cells: two full chunks of CELLS_PER_CHUNK (64) and a part one, so that a cell at
    a chunk's boundary (63, 64, 127, 128) or in the last part chunk that the loops skipped
    or wrote twice would show (the 48-cell sheets above fit in one chunk)."""
    block, x, v, sums = _cells(_table_fabric(), True, nx=14, ny=5)
    assert len(x) > 2 * hessian_kernels.CELLS_PER_CHUNK
    expected, expected_sums = tangent.membrane_hessian(block, x, v, sums)
    got, got_sums = hessian_kernels.membrane_hessians(block, x, v, sums)
    scale = np.abs(expected).max()
    assert np.abs(got - expected).max(axis=(1, 2)).max() <= 1e-12 * scale
    assert np.abs(got_sums - expected_sums).max() <= 1e-12 * np.abs(expected_sums).max()


def test_the_compiled_normal_share_jacobians_give_the_numpy_ones():
    # Random cells, obtuse and slender ones alike, and a random set of held corners.
    rng = np.random.default_rng(5)
    x = rng.normal(size=(400, 3, 3))
    held = rng.random((400, 3)) < 0.2
    _, expected = geometry.corner_normals(x, jacobian=True)
    expected = expected * ~held[:, :, None, None, None]
    got = hessian_kernels.normal_share_jacobians(x, held)
    assert np.abs(got - expected).max() <= 1e-12 * np.abs(expected).max()
    assert not got[held].any()


def test_the_compiled_pair_sums_are_the_bincounts_of_corner_pairs():
    block, x, v, sums = _cells(_table_fabric(), True)
    pairs = block.corner_pairs()
    hessian, _ = tangent.membrane_hessian(block, x, v, sums)
    expected = pairs.hessian(hessian).data
    assert np.array_equal(hessian_kernels.pair_sums(pairs.slot, hessian, pairs.n_pairs), expected)


def test_the_hessians_summed_a_chunk_of_cells_at_a_time_are_those_of_all_cells_at_once():
    # Chunks of 7 cells (the sheet has 48): the same additions in the same order.
    block, x, v, sums = _cells(_polynomial_fabric(), True)
    pairs = block.corner_pairs()
    hessian, d_sums = hessian_kernels.membrane_hessians(block, x, v, sums)
    h_blocks, chunked_sums = hessian_kernels.pair_hessians(block, x, v, sums, pairs, chunk=7)
    assert np.array_equal(h_blocks, pairs.hessian(hessian).data)
    assert np.array_equal(chunked_sums, d_sums)


def test_the_compiled_membrane_tangent_with_a_clamped_edge_is_the_numpy_one():
    # Wall nodes (the clamped edge's normal sums are the wall's and do not vary) through the
    # whole sparse membrane tangent, compiled against numpy.
    parts = {}
    for kernel in ("numpy", "compiled"):
        mesh = Mesh.rectangle(40.0, 20.0, nx=6, ny=4)
        model = Model(mesh)
        model.add(FibrousShell(_table_fabric(), clamped="left", kernel=kernel))
        model.fix(mesh.nodes("left"))
        compiled = model.compile()
        state = compiled.initial_state()
        rng = np.random.default_rng(8)
        state.positions = state.positions + rng.normal(scale=0.5, size=state.positions.shape)
        state.directors = rotate_about(
            state.directors, 0.2 * rng.normal(size=state.directors.shape)
        )
        block = compiled.blocks[0]
        assert block.wall_nodes.any()
        parts[kernel] = tangent.nodal_membrane_tangent(block, state)
    (expected, expected_second), (got, got_second) = parts["numpy"], parts["compiled"]
    expected_matrix, got_matrix = expected.matrix.toarray(), got.matrix.toarray()
    assert np.abs(got_matrix - expected_matrix).max() <= 1e-12 * np.abs(expected_matrix).max()
    assert np.abs(got_second - expected_second).max() <= 1e-12 * np.abs(expected_second).max()
