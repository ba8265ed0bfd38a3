"""numba's two builds of a kernel (femcore/jit.py ``_Parallel``): a loop on one thread runs
the plain build of the kernel's parted copy and leaves the parallel one uncompiled; a loop on
more threads runs the parallel build, a loop over parts each run by the plain build on a
thread of its own; both give the same numbers to the last bit, and are cached apart."""

import numpy as np
import pytest

from femcore import jit

if jit.AVAILABLE:
    from numba import get_thread_id

pytestmark = pytest.mark.skipif(not jit.AVAILABLE, reason="numba is not installed")


def _scaled_sums(offsets, values, out):  # pragma: no cover - numba
    """out[i] = 0.1 * the sum of values[offsets[i]:offsets[i + 1]] in order (a loop whose
    rounding shows any change of the order of its sums)."""
    for i in jit.prange(out.shape[0]):
        total = 0.0
        for j in range(offsets[i], offsets[i + 1]):
            total += 0.1 * values[j]
        out[i] = total


def _kernel_and_arguments():
    rng = np.random.default_rng(7)
    values = rng.normal(size=4000) * 10.0 ** rng.integers(-8, 8, size=4000)
    offsets = np.sort(rng.integers(0, 4000, size=501))
    offsets[0], offsets[-1] = 0, 4000
    return jit.jit(_scaled_sums), offsets, values


def _python_sums(offsets, values) -> np.ndarray:
    """The loop run by Python itself (numba's ``prange`` is ``range`` there)."""
    out = np.empty(len(offsets) - 1)
    _scaled_sums(offsets, values, out)
    return out


def test_a_loop_on_one_thread_runs_the_plain_build_and_never_compiles_the_parallel_one():
    kernel, offsets, values = _kernel_and_arguments()
    out = np.empty(len(offsets) - 1)
    kernel(offsets, values, out)  # one numba thread (tests/conftest.py)
    assert kernel._parallel is None
    assert len(kernel.serial.signatures) == 1
    # the same sums in the same order as Python's loop, to the last bit
    np.testing.assert_array_equal(out, _python_sums(offsets, values))


@pytest.mark.parallel
def test_a_loop_on_more_threads_runs_the_plain_build_in_parts_with_the_same_numbers():
    """The parallel build is a loop over parts, one a thread, each part run by the plain
    build (its one int64 signature: prange's unsigned index is not passed on)."""
    import numba

    kernel, offsets, values = _kernel_and_arguments()
    out = np.empty(len(offsets) - 1)
    kernel(offsets, values, out)  # on numba's threads, every loop (the parallel mark)
    if numba.get_num_threads() > 1:
        assert kernel._parallel is not None and len(kernel.parallel.signatures) == 1
        # (the parts call the plain build's machine code: compiled, or loaded from numba's
        # cache, for the arguments' types)
        (signature,) = kernel.serial.signatures
        assert [str(t) for t in signature[-2:]] == ["int64", "int64"]
    np.testing.assert_array_equal(out, _python_sums(offsets, values))


@pytest.mark.parallel
def test_the_loop_over_the_parts_calls_the_plain_build_s_own_code_and_links_none_of_it():
    """The parallel build calls the plain build's machine code through its address
    (femcore/jit.py ``_over_parts``): nothing of the plain build is in the loop's module,
    where numba would optimise and compile it again (the fibrous force pass's loop over the
    parts took 27.2 s of CPU so, 1.2 s through the address: benchmarks/
    suite_parallel_build.py). The same numbers to the last bit."""
    import numba

    if numba.get_num_threads() < 2:
        pytest.skip("numba has one thread here")
    from numba.core.caching import NullCache

    kernel, offsets, values = _kernel_and_arguments()
    kernel.parallel._cache = NullCache()  # compiled here: a build from numba's cache has no IR
    out = np.empty(len(offsets) - 1)
    kernel(offsets, values, out)
    (loop,) = kernel.parallel.signatures
    plain = (*(numba.typeof(a) for a in (offsets, values, out)), numba.int64, numba.int64)
    kernel.serial.compile(plain)  # (compiled already, or loaded from numba's cache)
    name = kernel.serial.overloads[plain].fndesc.llvm_func_name
    assert name not in kernel.parallel.inspect_llvm(loop)
    np.testing.assert_array_equal(out, _python_sums(offsets, values))


def _thread_ids(out):  # pragma: no cover - numba
    """out[i] = the id of the thread that ran item i."""
    for i in jit.prange(out.shape[0]):
        out[i] = get_thread_id()


@pytest.mark.parallel
def test_the_parts_run_on_threads_of_their_own():
    """Part k of the loop's range, in order, on thread k: as many threads at work as numba's
    setting, each on one block of consecutive items."""
    import numba

    threads = numba.get_num_threads()
    if threads < 2:
        pytest.skip("numba has one thread here")
    kernel = jit.jit(_thread_ids)
    out = np.full(1000, -1, dtype=np.int64)
    kernel(out)
    assert kernel._parallel is not None
    bounds = [1000 * k // threads for k in range(threads + 1)]
    ids = [set(out[bounds[k] : bounds[k + 1]]) for k in range(threads)]
    assert all(len(i) == 1 for i in ids)
    assert len(set.union(*ids)) == threads


@pytest.mark.parametrize("length", [0, 1, 7, 500])
@pytest.mark.parametrize("parts", [1, 2, 3, 8])
def test_the_parts_cover_the_loop_once_in_order(length, parts):
    """The parted copy run by Python (``prange`` is numba's, a ``range`` there): parts 0 .. p - 1
    of a loop of ``length`` items write each item once, and the sums of the whole loop."""
    kernel, offsets, values = _kernel_and_arguments()
    offsets = offsets[: length + 1] if length else offsets[:1]
    whole = _python_sums(offsets, values)
    out = np.full(len(offsets) - 1, np.nan)
    for part in range(parts):
        before = np.isnan(out).sum()
        kernel.serial.py_func(offsets, values, out, part, parts)
        assert np.isnan(out).sum() == before - (
            length * (part + 1) // parts - length * part // parts
        )
    np.testing.assert_array_equal(out, whole)


def test_each_build_is_cached_under_a_name_of_its_own():
    """numba's cache index of a function does not tell its builds apart: the plain build
    compiles the parted copy ``_part``, the parallel one the loop over the parts
    ``_parallel``, both of the kernel's module and file."""
    kernel = jit.jit(_scaled_sums)
    assert kernel.parted
    assert kernel.serial.py_func.__qualname__.startswith("_scaled_sums_part_")
    loop = kernel.parallel.py_func
    assert loop.__qualname__.startswith("_scaled_sums_parallel_")
    for build in (kernel.serial.py_func, loop):
        assert build.__module__ == _scaled_sums.__module__
        assert build.__code__.co_filename == _scaled_sums.__code__.co_filename
    assert kernel.parallel.targetoptions.get("parallel") and not kernel.serial.targetoptions.get(
        "parallel"
    )


def test_a_kernel_is_parted_and_built_at_its_first_use_not_at_import():
    """Making a kernel reads no source and builds nothing (a process pays for the kernels it
    calls only); its first call makes the parted copy and the plain build."""
    kernel, offsets, values = _kernel_and_arguments()
    assert kernel._serial is None and kernel._part is None
    kernel(offsets, values, np.empty(len(offsets) - 1))
    assert kernel._serial is not None and kernel._part is not None


def _two_loops(out):  # pragma: no cover - numba
    for i in jit.prange(out.shape[0]):
        out[i] = i
    for i in jit.prange(out.shape[0]):
        out[i] += 1.0


def test_a_function_of_two_parallel_loops_keeps_numbas_parallel_build():
    kernel = jit.jit(_two_loops)
    assert not kernel.parted
    assert kernel.parallel.py_func.__code__ is _two_loops.__code__
    out = np.zeros(5)
    kernel(out)
    np.testing.assert_array_equal(out, np.arange(5) + 1.0)


def _reduction(values, out):  # pragma: no cover - numba
    total = 0.0
    for i in jit.prange(values.shape[0]):
        total += values[i]
    out[0] = total


def _zeroed_first(values, out):  # pragma: no cover - numba
    out[:] = 0.0
    for i in jit.prange(values.shape[0]):
        out[i] += values[i]


def _returned(values):  # pragma: no cover - numba
    total = 0.0
    for i in jit.prange(values.shape[0]):
        total += values[i]
    return total


@pytest.mark.parallel
@pytest.mark.parametrize("function", [_reduction, _zeroed_first, _returned])
def test_a_loop_whose_parts_are_not_independent_keeps_numbas_parallel_build(function):
    """A reduction across the loop, a write to an argument before it, a returned value: each
    part running the whole function would give a part's sum or undo another part's items, so
    such a function is not parted, and its answer on several threads is the whole loop's."""
    kernel = jit.jit(function)
    assert not kernel.parted
    values = np.arange(1.0, 5001.0)
    if function is _returned:
        assert kernel(values) == values.sum()
        return
    out = np.full(values.shape, np.nan)
    kernel(values, out)
    whole = values.sum() if function is _reduction else values
    np.testing.assert_array_equal(out[0] if function is _reduction else out, whole)


def test_a_change_of_the_rewrite_names_new_builds(monkeypatch):
    """numba serves a cached build by its name, its file's stamp and its bytecode, and the
    loop over the parts has the same bytecode for every kernel: the builds are named after
    the parted copy's source, so a rewrite that changes (here the parts' argument's name)
    never meets the builds of the old one."""
    stamp = jit._stamp(_scaled_sums)
    first = jit._parted(_scaled_sums, stamp)
    monkeypatch.setattr(jit, "_PARTS", "count__")
    second = jit._parted(_scaled_sums, stamp)
    assert first.__name__ != second.__name__
    assert first.__name__.startswith("_scaled_sums_part_")


def test_a_kernel_whose_file_changed_since_its_import_keeps_its_imported_code(tmp_path):
    """The parted copy is made from the source file at the kernel's first call: a file edited
    since the kernel was made would give code other than the imported function's, so then
    the kernel keeps numba's builds of the imported function."""
    import importlib.util
    import os

    path = tmp_path / "edited_kernel.py"
    source = (
        "from femcore import jit\n\n\n"
        "def add(out):\n"
        "    for i in jit.prange(out.shape[0]):\n"
        "        out[i] = out[i] + 1.0\n"
    )
    path.write_text(source)
    spec = importlib.util.spec_from_file_location("edited_kernel", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    kernel = jit.jit(module.add)
    path.write_text(source.replace("+ 1.0", "+ 5.0"))
    os.utime(path, ns=(1, 1))  # a stamp of its own, whatever the clock's resolution
    out = np.zeros(3)
    kernel(out)
    assert not kernel.parted
    np.testing.assert_array_equal(out, np.ones(3))


def test_the_fibrous_bind_gives_the_normals_and_bending_loops_the_states_array_type(monkeypatch):
    """numba compiles a kernel once for each array type it is given, read-only and writable
    apart: the bind's reference geometry (the mesh's read-only points) is computed from a
    writable copy, as the states' positions are, so that the normals and bending-side loops
    compile once. The copy changes no number: the reference sums and fold angles are those
    of the mesh's points themselves (numpy reference, to the last bit)."""
    from elements import FibrousShell
    from elements.fibrous import bending, geometry
    from elements.fibrous import geometry_kernels as fibrous_kernels
    from femcore import Mesh, Model
    from materials import Fabric

    seen: list[tuple[str, bool]] = []
    for name in ("_normals_pass", "_bending_sides"):
        original = getattr(fibrous_kernels, name)

        def recorded(*args, _name=name, _original=original):
            seen.append((_name, bool(args[1].flags.writeable)))
            return _original(*args)

        monkeypatch.setattr(fibrous_kernels, name, recorded)
    mesh = Mesh.rectangle(30.0, 20.0, nx=3, ny=2)
    model = Model(mesh)
    fabric = Fabric(thickness=1.0, areal_density=1e-9, tension=500.0, shear=0.5, bending=2.0)
    model.add(FibrousShell(fabric))
    compiled = model.compile()
    compiled.internal_force(compiled.initial_state())
    assert {name for name, _ in seen} == {"_normals_pass", "_bending_sides"}
    assert all(writable for _, writable in seen), seen
    block = compiled.blocks[0]
    assert not block.reference_points.flags.writeable  # the mesh's points, kept read-only
    block.compiled = False  # the numpy reference of the same geometry, from the points
    wall = block.wall_nodes
    block.wall_nodes = np.zeros_like(wall)
    np.testing.assert_array_equal(
        geometry.normal_sums(block, block.reference_points), block.reference_sums
    )
    block.wall_nodes = wall
    np.testing.assert_array_equal(
        bending.geometry(block, block.reference_points)["fold"], block.reference_fold
    )


def test_a_table_law_s_energy_in_the_loops_is_the_law_s_own_to_the_last_bit_without_a_call():
    """The fibrous kernels evaluate the packed laws' energy with constant indices (the shear
    law 2, the fabric section's module constants) inside their cell loops. A table law's
    energy is a search and a trapezoid on the integrals that ``pack_laws`` tabled, spliced
    into the caller: no compiled call (whose array arguments a loop reference-counts and
    around which it saves its registers), and materials.Law.energy's numbers (the numpy
    reference: the same trapezoids summed in the same order, y beyond the table on the line
    from the end knot as ``Law.value`` takes it) to the last bit, on, between and beyond the
    knots."""
    import numba

    from elements.fibrous.packed_laws import law_energy, pack_laws
    from materials import BendingLaw, ShearLaw

    @numba.njit
    def constant_indices(integers, reals, x):  # pragma: no cover - numba
        return (
            law_energy(integers, reals, 0, x),
            law_energy(integers, reals, 1, x),
            law_energy(integers, reals, 2, x),
        )

    laws = [
        BendingLaw.bilinear(7.5, 0.5, 1e-3),
        ShearLaw.table([-1.0, -0.5, 0.0, 0.5, 1.0], [-3.0, -1.0, 0.0, 1.0, 3.0]),
        BendingLaw.bilinear(2.0, 0.5, 2e-3),
    ]
    integers, reals = pack_laws(laws)
    grid = np.concatenate(
        [np.linspace(-3e-3, 3e-3, 61), np.linspace(-1.5, 1.5, 61), [-1e-3, 1e-3, 2e-3, 0.5]]
    )
    for x in grid:
        energies = constant_indices(integers, reals, x)
        for law, energy in zip(laws, energies, strict=True):
            assert energy == float(law.energy(x)), (law, x)
    (signature,) = constant_indices.signatures
    lines = constant_indices.inspect_llvm(signature).splitlines()
    assert not [line for line in lines if " call " in line and "packed_laws" in line]


def _reciprocals(values, out):  # pragma: no cover - numba
    """out[i] = 1 / values[i]."""
    for i in jit.prange(out.shape[0]):
        out[i] = 1.0 / values[i]


def test_a_lanes_kernel_is_parted_and_divides_by_zero_without_raising():
    """``jit_lanes``: the parted builds with numba's numpy error model (no zero test before a
    division, which keeps LLVM from vectorising a loop): 1 / 0 is inf there, where ``jit``'s
    build raises ZeroDivisionError as Python does."""
    values = np.array([2.0, 0.0, -0.0])
    out = np.empty(3)
    kernel = jit.jit_lanes(_reciprocals)
    kernel(values, out)
    assert kernel.parted
    assert out.tolist() == [0.5, np.inf, -np.inf]
    with pytest.raises(ZeroDivisionError):
        jit.jit(_reciprocals)(values, out)


def test_the_fibrous_loops_across_chunks_of_cells_are_parted():
    """The fibrous passes whose loop runs over chunks of cells or sides (geometry_kernels.py
    ``_normals_pass``, ``_side_folds``, kernels.py ``_cells_pass``) keep the parted builds'
    shape (one ``prange`` over the chunks, the last statement): their parts run on threads of
    their own (tests/test_threads.py holds their forces the same on one thread and on all)."""
    from elements.fibrous import geometry_kernels, kernels

    for kernel in (
        geometry_kernels._normals_pass,
        geometry_kernels._side_folds,
        kernels._cells_pass,
    ):
        assert kernel.parted, kernel.__name__


def test_two_numpy_scalars_of_one_class_but_two_units_are_two_argument_types():
    """The parts' address is looked up by the arguments' types: a timedelta64 in days and
    one in seconds (two numba types, two builds) must not share a key, or a later call in
    seconds would run the build in days; an array's key keeps its dtype and layout."""
    days, seconds = np.timedelta64(1, "D"), np.timedelta64(1, "s")
    assert jit._type_key(days) != jit._type_key(seconds)
    assert jit._type_key(np.float64(1.0)) == jit._type_key(np.float64(2.0))
    assert jit._type_key(np.zeros(3)) != jit._type_key(np.zeros(3, dtype=np.float32))
    assert jit._type_key(np.zeros((3, 2))) != jit._type_key(np.zeros((3, 2)).T)


def test_a_pickled_kernel_carries_no_machine_address_of_this_process():
    """A kernel sent to another process (pickled) looks its parts' addresses up again
    there: an address of this process called in another crashed it."""
    import pickle

    kernel, _, _ = _kernel_and_arguments()
    kernel._addresses[("a key",)] = 12345  # as a call on several threads leaves it
    restored = pickle.loads(pickle.dumps(kernel))
    assert restored._addresses == {}
    assert kernel._addresses == {("a key",): 12345}  # the sender's own kept


def _checked_roots(values, out):  # pragma: no cover - numba
    """out[i] = sqrt(values[i]); a negative value raises ValueError."""
    for i in jit.prange(out.shape[0]):
        if values[i] < 0.0:
            raise ValueError("a negative value")
        out[i] = np.sqrt(values[i])


@pytest.mark.parallel
def test_a_part_that_raises_raises_on_any_thread_count():
    """A loop one of whose parts raises: on several threads the part's exception stays on
    its thread and the rest of its part unwritten, so the whole loop runs again on this
    thread and raises it, as on one thread (before: the call returned with garbage left in
    the unwritten items); a loop that raises nowhere returns its numbers."""
    import numba

    if numba.get_num_threads() < 2:
        pytest.skip("numba has one thread here")
    kernel = jit.jit(_checked_roots)
    values = np.arange(4000.0)
    out = np.empty(4000)
    kernel(values, out)
    assert kernel._parallel is not None
    np.testing.assert_array_equal(out, np.sqrt(values))
    values[3999] = -1.0  # in the last part
    with pytest.raises(ValueError, match="a negative value"):
        kernel(values, np.empty(4000))


def test_the_fibrous_level_lanes_run_without_reference_counting():
    """The helpers that loop across a chunk's scratch rows (elements/fibrous/level_lanes.py)
    are built by ``lane_rows``: numba's reference counting off (each array argument's incref
    and decref at every call, atomic operations: 4 % of the fibrous force when they were
    spliced by ``inline``) and its numpy error model (no zero test before a division, which
    would keep their loops from vectorising); such a helper cannot make an array."""
    from numba.core.errors import TypingError

    from elements.fibrous import level_lanes

    for name in (
        "level_lanes",
        "law_lanes",
        "linear_lanes",
        "law_row",
        "load_lanes",
        "moment_lanes",
    ):
        options = getattr(level_lanes, name).targetoptions
        assert options["_nrt"] is False and options["error_model"] == "numpy", name
    made = jit.lane_rows(_fresh_array)
    with pytest.raises(TypingError):
        made(3)


def _fresh_array(n):  # pragma: no cover - numba
    """An array made inside the helper (what a build without reference counting refuses)."""
    return np.empty(n)
