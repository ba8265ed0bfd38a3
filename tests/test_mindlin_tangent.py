"""elements/mindlin_tangent.py: the compiled tangent of the elastic Mindlin triangle gives the
numbers of the numpy reference (MindlinShellBlock._cell_tangent, itself checked against
central differences in tests/test_mindlin.py); a fabric section's compiled tangent is
tests/test_mindlin_fabric_tangent.py's."""

import numpy as np
import pytest

from elements import MindlinShell, mindlin_tangent
from femcore import Model
from materials import ElasticShell
from tests.test_mindlin import CYLINDER, MESH, ORTHOTROPIC, _deformed_state


@pytest.mark.parametrize("thickness_points", [2, 3, 5])
@pytest.mark.parametrize("mesh", [MESH, CYLINDER], ids=["flat", "cylinder"])
@pytest.mark.parametrize("material", [None, ORTHOTROPIC], ids=["isotropic", "orthotropic"])
def test_the_compiled_tangent_gives_the_numpy_blocks_to_1e_12(thickness_points, mesh, material):
    # The same sums in another order: agreement to round-off of the largest entry, on the
    # reference state and on stretched, sheared states with large director rotations.
    model = Model(mesh)
    section = material or ElasticShell(1000.0, 0.3, 2.0, 1e-9)
    model.add(MindlinShell(section, thickness_points=thickness_points))
    compiled = model.compile()
    block = compiled.blocks[0]
    assert block.kernel == "compiled"
    rng = np.random.default_rng(thickness_points)
    states = [compiled.initial_state(), _deformed_state(compiled, rng)]
    for state in states:
        fast = block.tangent(state)[0]
        block.kernel = "numpy"
        try:
            reference = block.tangent(state)[0]
        finally:
            block.kernel = "compiled"
        assert np.array_equal(fast.nodes, reference.nodes)
        scale = np.abs(reference.blocks).max()
        assert np.abs(fast.blocks - reference.blocks).max() <= 1e-12 * scale


def test_the_elastic_tangent_loop_is_parted_so_no_thread_shares_a_chunks_scratch():
    # Allocated before the prange, the scratch would keep numba's parallel build, whose
    # threads would share it; allocated a chunk, the loop runs as parts of the plain build.
    assert mindlin_tangent._tangent_cells.parted
