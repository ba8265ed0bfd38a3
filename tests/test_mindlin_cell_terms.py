"""elements/mindlin_cell_terms.py: the per-cell pieces spliced into the Mindlin triangle's
compiled loops (the elastic tangent, the fabric section's tangent, loads and section measures)
leave each loop's numbers as they were when it spelled the pieces out: the same bits as the
loops of revision BEFORE (their files taken from git and imported beside this tree's,
tests/revision_modules.py), on the tests' meshes, at the reference state and far from it, on
one thread and on all. The elastic tangent's loop runs in chunks of cells since then: the
same bits on one thread and on all, and parted like the fabric loops (elements/jit.py).

The comparisons are marked slow: numba builds the four loops of BEFORE too, 7-8 s of CPU on
an empty cache (benchmarks/mindlin_kernel_pairs.py --compile), kept from run to run in
pytest's cache folder."""

from __future__ import annotations

import importlib

import numpy as np
import pytest

from elements import MindlinShell, mindlin_tangent
from elements.fabric_section import response
from elements.jit import AVAILABLE
from elements.mindlin_tables import _TYING_N
from femcore import Model
from materials import ElasticShell, presets
from tests.revision_modules import revision_for_tests
from tests.test_fabric_section_kernels import FABRICS
from tests.test_mindlin import CYLINDER, MESH, ORTHOTROPIC, _deformed_state
from tests.test_mindlin_fabric_tangent import _bent_state

pytestmark = pytest.mark.skipif(not AVAILABLE, reason="numba missing")

# The last revision whose loops spelled out the pieces they now share.
BEFORE = "14e312d"
MODULES = {
    "elements/mindlin_tangent.py": "elements.mindlin_tangent",
    "elements/mindlin_fabric_tangent.py": "elements.mindlin_fabric_tangent",
    "elements/mindlin_fabric_loads.py": "elements.mindlin_fabric_loads",
    "elements/mindlin_fabric_measures.py": "elements.mindlin_fabric_measures",
}
ELASTIC = {"isotropic": ElasticShell(1000.0, 0.3, 2.0, 1e-9), "orthotropic": ORTHOTROPIC}
SECTIONS = {"g986": presets.g986_stack(), "non-linear": FABRICS["non-linear"]}
MESHES = {"flat": MESH, "cylinder": CYLINDER}


@pytest.fixture(scope="module")
def before(request):
    """The four loops' modules of BEFORE, by their file names (without .py)."""
    return revision_for_tests(request, BEFORE, MODULES)


def _now():
    names = [name.rsplit(".", 1)[1] for name in MODULES.values()]
    return {name: importlib.import_module(f"elements.{name}") for name in names}


def _states(model, seed: int):
    """The reference state and one far from it (tests/test_mindlin.py ``_deformed_state``)."""
    return [model.initial_state(), _deformed_state(model, np.random.default_rng(seed))]


def _elastic_tangents(modules, block, state):
    x, v = state.positions[block.connectivity], state.directors[block.connectivity]
    return modules["mindlin_tangent"].mindlin_tangent_blocks(
        block, x, v, block._level_stiffness(), *block._products()
    )


def _fabric_results(modules, block, state) -> list[np.ndarray]:
    """The fabric loops' outputs: section measures, tangent blocks, forces, moments (the
    section's response to this tree's measures, the same for both sides)."""
    x, v = state.positions[block.connectivity], state.directors[block.connectivity]
    common = (x, v, block.zeta, block.h, _TYING_N)
    y = modules["mindlin_fabric_measures"].fabric_section_measures(*common, block.reference_metric)
    answer = response(block.section, block._measures(x, v), hessian=True)
    tangent = modules["mindlin_fabric_tangent"].fabric_tangent_blocks(
        *common, block.reference_metric, answer.gradient, answer.hessian, *block._products()
    )
    force, moment = modules["mindlin_fabric_loads"].fabric_cell_loads(
        *common, answer.gradient, block._products()[0]
    )
    return [y, tangent, force, moment]


@pytest.mark.slow
@pytest.mark.parametrize("levels", [2, 3])
@pytest.mark.parametrize("material", ELASTIC)
@pytest.mark.parametrize("mesh", MESHES)
def test_the_elastic_tangent_is_the_bits_of_the_loop_before(before, levels, material, mesh):
    model = Model(MESHES[mesh])
    model.add(MindlinShell(ELASTIC[material], thickness_points=levels))
    compiled = model.compile()
    block = compiled.blocks[0]
    for state in _states(compiled, levels):
        now = _elastic_tangents(_now(), block, state)
        assert np.abs(now).max() > 0.0
        np.testing.assert_array_equal(now, _elastic_tangents(before, block, state))


@pytest.mark.slow
@pytest.mark.parametrize("section", SECTIONS)
@pytest.mark.parametrize("mesh", MESHES)
def test_the_fabric_loops_are_the_bits_of_the_loops_before(before, section, mesh):
    model = Model(MESHES[mesh])
    model.add(MindlinShell(SECTIONS[section], warp=(1.0, 0.3, 0.0)))
    compiled = model.compile()
    block = compiled.blocks[0]
    for state in (compiled.initial_state(), _bent_state(compiled, np.random.default_rng(4))):
        now = _fabric_results(_now(), block, state)
        then = _fabric_results(before, block, state)
        assert np.abs(now[1]).max() > 0.0
        for a, b in zip(now, then):
            np.testing.assert_array_equal(a, b)


@pytest.mark.slow
@pytest.mark.parallel
def test_the_loops_on_all_threads_are_the_bits_of_the_loops_before_on_one(before, monkeypatch):
    from tests.thread_runs import on_one_thread_and_on_all

    for module in _now().values():  # 5 cells a chunk: several chunks to share out
        if hasattr(module, "CELLS_PER_CHUNK"):
            monkeypatch.setattr(module, "CELLS_PER_CHUNK", 5)
    model = Model(CYLINDER)
    model.add(MindlinShell(ORTHOTROPIC, thickness_points=3))
    elastic = model.compile()
    model = Model(CYLINDER)
    model.add(MindlinShell(SECTIONS["non-linear"], warp=(1.0, 0.3, 0.0)))
    fabric = model.compile()
    elastic_state = _deformed_state(elastic, np.random.default_rng(7))
    fabric_state = _bent_state(fabric, np.random.default_rng(8))

    def run(modules):
        return [
            _elastic_tangents(modules, elastic.blocks[0], elastic_state),
            *_fabric_results(modules, fabric.blocks[0], fabric_state),
        ]

    one, every = on_one_thread_and_on_all(lambda: run(_now()))
    then, _ = on_one_thread_and_on_all(lambda: run(before))
    for a, b, c in zip(one, every, then):
        np.testing.assert_array_equal(a, c)
        np.testing.assert_array_equal(b, c)


def test_the_elastic_tangent_loop_is_parted_so_no_thread_shares_a_chunks_scratch():
    # Allocated before the prange, the scratch would keep numba's parallel build, whose
    # threads would share it; allocated a chunk, the loop runs as parts of the plain build.
    assert mindlin_tangent._tangent_cells.parted
