"""numba's compilation for the element kernels, optional: without numba the decorators return
the plain Python function and ``prange`` is ``range``, so the numpy paths keep working.

``jit`` compiles a loop over cells or nodes (its one ``prange`` loop) as numba's plain build
of the function's parted copy, which runs part k of p equal parts of the loop's range, and
runs it whole for a loop on one thread, or on more threads (``threads_for``) from a small
parallel build that runs part k on thread k (``_Parallel``: a process whose loops all run on
one thread, a test session's, never compiles a parallel build, and the parallel build is a
loop of one call to the plain build's machine code through its address, cheap to compile);
``serial`` compiles a helper called from inside such loops.
Both cache the machine code next to the module (numba's disk cache, made by
femcore/kernel_cache.py to find a build stale when a project module the kernel's file imports
has changed, not only the file itself) and keep IEEE arithmetic (no fastmath), so that a
compiled loop gives the numbers of its numpy reference up to the order of its sums; the kernels
sum in the same order on any number of threads, so a run gives the same numbers to the last
bit whatever the thread count.

Threads, chosen here and only here:

* the threading layer is numba's OpenMP layer with a passive wait (``OMP_WAIT_POLICY=PASSIVE``,
  set before numba loads the layer unless the environment sets it): its threads sleep between
  two parallel loops. The default policy spins there, and on a machine where other processes
  are busy the spinning threads take the cores the working ones need: explicit steps of a
  9800-triangle blank on 2 threads took 4.7 times as long as on one (3.8 with one more busy
  process), 1.0 and 0.9 times with the passive wait (benchmarks/threads.py, 2 cores at a load
  of 13). The workqueue layer does not spin either, but aborts a process that launches
  parallel loops from two threads at once. ``NUMBA_THREADING_LAYER`` in the environment still
  chooses another layer;
* each parallel loop runs on ``threads_for(items)`` threads: one for a loop over fewer than
  ``SMALL_LOOP`` items (waking and joining a thread costs more than it saves), else the cores
  free for this process (``free_cores``), at most numba's setting (``numba.set_num_threads``,
  ``NUMBA_NUM_THREADS``: the caller's cap).
"""

from __future__ import annotations

import ast
import copy
import functools
import hashlib
import inspect
import os
import textwrap
import time
import types
from typing import Any, Literal

# Before numba loads its OpenMP layer (at the first parallel loop): a passive wait.
os.environ.setdefault("OMP_WAIT_POLICY", "PASSIVE")

try:  # numba is a dependency; the numpy paths keep the package usable without it
    import numba

    AVAILABLE = True
except ImportError:  # pragma: no cover - exercised only where numba is missing
    numba = None  # type: ignore[assignment]
    AVAILABLE = False

if AVAILABLE:
    from numba.np.ufunc import parallel as _layer

from femcore.kernel_cache import dependency_digest, njit  # noqa: E402 (after the wait policy)

if AVAILABLE and "NUMBA_THREADING_LAYER" not in os.environ:
    # OpenMP first (passive, above); workqueue where numba has no OpenMP (never spins either).
    numba.config.THREADING_LAYER_PRIORITY = ["omp", "workqueue", "tbb"]  # type: ignore[attr-defined]

if AVAILABLE:
    import numpy as np
    from numba.core import cgutils
    from numba.core import types as numba_types
    from numba.extending import intrinsic

    @intrinsic
    def _call_at(typingctx, address, arguments):
        """Inside compiled code: call the numba build whose machine code starts at
        ``address`` (int64, ``_Parallel._address``) with the items of the tuple
        ``arguments``, whose types are that build's signature (numba's calling convention;
        a kernel that returns nothing); True where the call raised (its exception is not
        carried across the threads: the caller runs the kernel again on one thread to raise
        it, ``_Parallel.__call__``). The call goes through the address: nothing of the
        called build is linked into the caller, which numba would otherwise optimise and
        compile again in the caller's module."""

        def codegen(context, builder, signature, values):
            argument_types = list(arguments.types)
            function = context.call_conv.get_function_type(numba_types.none, argument_types)
            pointer = builder.inttoptr(values[0], function.as_pointer())
            items = cgutils.unpack_tuple(builder, values[1], len(argument_types))
            status, _ = context.call_conv.call_function(
                builder, pointer, numba_types.none, argument_types, items
            )
            return status.is_error

        return numba_types.boolean(address, arguments), codegen


__all__ = [
    "AVAILABLE",
    "CHUNK",
    "FOLLOW_LOAD",
    "PLAIN_ON_ONE_THREAD",
    "SMALL_LOOP",
    "free_cores",
    "chunk_size",
    "chunk_sums",
    "chunks",
    "inline",
    "jit",
    "jit_lanes",
    "lane_rows",
    "lanes",
    "plain_part",
    "prange",
    "serial",
    "threads_for",
    "unsigned",
]

# A parallel loop over fewer items than this runs on one thread (measured at a load of 8 on
# 2 cores: the fibrous force of 800 triangles no faster on 2 threads, of 9800 1.2 times).
SMALL_LOOP = 2000
# Whether the threads follow the free cores (False: numba's setting alone, as in the tests
# that compare thread counts).
FOLLOW_LOAD = True
# Whether a loop on one thread runs the plain build of its kernel (False: the parallel build,
# on one thread; _Parallel).
PLAIN_ON_ONE_THREAD = True
# Seconds between two looks at the machine's load (free_cores).
LOAD_REFRESH = 2.0
# Nodes per chunk of a parallel loop that sums over its nodes (an energy): each chunk sums
# its own nodes in order, and the chunks' sums are added in chunk order (``chunk_sums``), so
# that the sum is the same to the last bit on any number of threads. Small enough that the
# chunks of the 20k-triangle blank (10k nodes) share out evenly on two threads.
CHUNK = 1024


# An array index as an unsigned integer inside compiled code (int without numba): numba
# tests a signed index for < 0 at every array access (to count from the end), unless it can
# tell the index is not negative, as it can for range(n) but not for a chunk's range of a
# loop's part (range(start, stop) with start computed from the part): a chunked loop over the
# nodes ran 1.3 times as long as the plain loop, as fast with its index unsigned.
unsigned = numba.uint64 if AVAILABLE else int


def chunk_size() -> int:
    """``CHUNK`` as it is at this call. A compiled loop takes its chunk size as an argument
    from here, never ``CHUNK`` itself: numba freezes a global into the machine code it builds
    (and caches), and the Python side sizing the chunks' sums would then disagree with the
    loop whenever the two saw different values."""
    return CHUNK


def chunks(items: int, size: int | None = None) -> int:
    """The number of ``size``-item chunks (default ``CHUNK``) that cover ``items`` items (at
    least 1)."""
    return max(1, -(-items // (CHUNK if size is None else size)))


def chunk_sums(partial):
    """(k,) the sums of the chunks' partial sums ``partial`` (chunks, k): numpy's sum along
    the chunks, one order whatever the threads that computed them."""
    return partial.sum(axis=0)


class _Load:
    """What ``free_cores`` last found: when, this process's CPU time then, the answer."""

    wall = -float("inf")
    cpu = 0.0
    free = 1


def _allowed_cores() -> int:
    """The cores this process may run on (its affinity mask; all of them where the system
    has no such mask)."""
    try:
        return len(os.sched_getaffinity(0))
    except (AttributeError, OSError):  # pragma: no cover - macOS and Windows
        return os.cpu_count() or 1


def free_cores() -> int:
    """The cores free for this process's threads (at least 1): those it may run on less
    those other processes keep busy, the 1-minute load average less this process's own
    share of it (its CPU time over the time since the last look), the load spread over the
    machine's cores when the affinity mask allows only some of them. Looked at every
    ``LOAD_REFRESH`` seconds at most, so a loop pays a clock read."""
    now = time.monotonic()
    if now - _Load.wall < LOAD_REFRESH:
        return _Load.free
    cpu = time.process_time()
    allowed = _allowed_cores()
    try:
        load = os.getloadavg()[0] * allowed / max(os.cpu_count() or allowed, allowed)
    except (AttributeError, OSError):  # pragma: no cover - Windows
        load = 0.0
    own = 0.0 if _Load.wall == -float("inf") else (cpu - _Load.cpu) / (now - _Load.wall)
    others = max(0.0, load - own)
    _Load.wall, _Load.cpu = now, cpu
    _Load.free = max(1, min(allowed, int(round(allowed - others))))
    return _Load.free


def threads_for(items: int) -> int:
    """The threads a parallel loop over ``items`` cells or nodes runs on: 1 below
    ``SMALL_LOOP``, else the free cores (``free_cores``; numba's setting when ``FOLLOW_LOAD`` is
    False), at most numba's current setting."""
    if not AVAILABLE:
        return 1
    return _threads(items, numba.get_num_threads())


def _threads(items: int, cap: int) -> int:
    """``threads_for`` with numba's setting ``cap`` read."""
    if items < SMALL_LOOP or cap == 1:
        return 1
    return min(cap, free_cores()) if FOLLOW_LOAD else cap


def _setting() -> int:
    """numba's thread setting of the calling thread: read from its threading layer directly
    once the layer is loaded (numba.get_num_threads takes two locks first, several
    microseconds a loop), through numba before."""
    try:
        if _layer._is_initialized:
            return _layer._get_num_threads()  # type: ignore[attr-defined]
    except AttributeError:  # pragma: no cover - another numba's internals
        pass
    return numba.get_num_threads()


class _Parallel:
    """A compiled loop called on ``threads_for`` threads of the length of its first argument
    (the cells or the nodes it loops over), from two builds:

    * ``serial``, numba's plain build of the function's parted copy (``_parted``: its one
      ``prange`` loop runs over part ``part`` of ``parts`` equal parts of its range), called
      with part 0 of 1 for a loop on one thread (a loop shorter than ``SMALL_LOOP``, or any
      loop where numba's setting or the free cores give one thread);
    * ``parallel``, numba's parallel build of a small loop over the parts (``_over_parts``:
      part k of as many parts as threads on thread k), each part run by the plain build,
      for a loop on more threads, made at its first call.

    Every cell (or node) is thus computed by the one plain build's code whatever the
    threads, so the same numbers to the last bit on any thread count
    (tests/test_threads.py, tests/test_kernel_builds.py), and numba's parallel passes
    (alias analysis, hoisting, the outlining of the loop body into a gufunc) see a loop of
    one call instead of the whole cell loop. They cost more than the plain build itself on
    the large loops: the fibrous force pass's parallel build took 23.9 s of CPU to compile
    against 6.5 s plain, 31 s against 11 s for all the fibrous force's loops, and built the
    helpers it calls again for its unsigned loop index (load 2-3,
    benchmarks/suite_kernels.py). numba's own parallel build splits a ``prange`` loop into
    equal static chunks, one a thread, as the parts do. On one thread the plain build runs
    as fast per cell as numba's parallel build did (benchmarks/suite_builds.py).
    ``PLAIN_ON_ONE_THREAD = False`` runs the parallel build on every loop.

    A function whose source cannot be read, or that has no ``prange`` call or more than
    one, keeps numba's parallel build of the whole function (``_renamed``), beside its
    plain build. Each build is cached under a name of its own (``_part_<digest>`` and
    ``_parallel_<digest>`` appended, the digest of the parted copy's source): numba's cache
    index of a function does not tell its builds apart, nor a change of the rewrite here.
    The loop over the parts calls the plain build's own machine code through its address
    (``_address``, ``_over_parts``): nothing of it is linked into the loop's build, which
    numba would optimise and compile again there (the fibrous force pass's loop over the
    parts took 27.2 s of CPU so, 1.2 s through the address)."""

    def __init__(self, function, error_model: Literal["python", "numpy"] = "python"):
        self._function = function
        self._error_model = error_model
        # The source file as imported: a file edited since is not read for the parted copy.
        self._stamp = _stamp(function)
        # The project modules as imported (the cache's stamp, femcore/kernel_cache.py), taken
        # now: the builds are made at the first call, maybe after some file was edited.
        self._digest = dependency_digest(function.__code__.co_filename)
        self._part = None  # the parted copy (None: the whole function, or not made yet)
        self._arguments: list[str] = []
        self._serial: Any = None
        self._parallel: Any = None
        # the plain build's machine code by the arguments' types (``_address``)
        self._addresses: dict[tuple, int] = {}
        self._native = True  # whether numba compiles the builds (not NUMBA_DISABLE_JIT)
        functools.update_wrapper(self, function)

    def __getstate__(self) -> dict:
        """Pickled without the plain build's addresses: machine addresses of this process,
        which another process (a kernel sent to a worker) would call into at random; it
        looks them up again at its first call on several threads."""
        state = self.__dict__.copy()
        state["_addresses"] = {}
        return state

    @property
    def serial(self):
        """The plain build (numba's dispatcher) of the parted copy, made at its first use
        (the kernel's source read then, not when its module is imported: 27 kernels took
        0.27 s of CPU to part at a load of 9, and a process uses a few of them)."""
        if self._serial is None:
            self._part = _parted(self._function, self._stamp, self._error_model)
            if self._part is not None:
                self._arguments = _arguments(self._function)
            self._serial = njit(
                self._function if self._part is None else self._part,
                self._digest,
                fastmath=False,
                error_model=self._error_model,
            )
            self._native = hasattr(self._serial, "overloads")  # a numba dispatcher
        return self._serial

    @property
    def parted(self) -> bool:
        """Whether the plain build runs the parted copy (else the whole function, beside
        numba's parallel build of the whole function)."""
        return self.serial is not None and self._part is not None

    @property
    def parallel(self):
        """The parallel build (numba's dispatcher), made at its first use."""
        if self._parallel is None:
            if self.parted:
                body = _over_parts(self._function, self._arguments, self.serial)
            else:
                body = _renamed(self._function, "_parallel")
            self._parallel = njit(
                body, self._digest, parallel=True, fastmath=False, error_model=self._error_model
            )
        return self._parallel

    def _address(self, args) -> int:
        """Where the plain build's machine code for the types of ``args`` starts (compiled
        or loaded from numba's cache at the first call with these types): the parallel
        build calls it there. Looked up by ``_type_key``, a few hundred nanoseconds an
        argument (numba's typeof took several microseconds)."""
        key = tuple([_type_key(a) for a in args])
        address = self._addresses.get(key)
        if address is None:
            signature = (*(numba.typeof(a) for a in args), numba.int64, numba.int64)
            self.serial.compile(signature)
            build = self.serial.overloads[signature]
            address = build.library.get_pointer_to_function(build.fndesc.llvm_func_name)
            self._addresses[key] = address
        return address

    def __call__(self, *args):
        serial = self._serial
        if serial is None:
            serial = self.serial
        parted = self._part is not None
        items = len(args[0])
        # (numba's jit disabled: the Python function, the whole loop as part 0 of 1 here; a
        # loop below SMALL_LOOP runs on one thread whatever numba's setting, which is then
        # not read: the two-ply step makes some fifty such calls)
        if items < SMALL_LOOP and PLAIN_ON_ONE_THREAD or not self._native:
            if parted:
                return serial(*args, 0, 1)
            return serial(*args)
        cap = _setting()
        threads = _threads(items, cap)
        if threads == 1 and PLAIN_ON_ONE_THREAD:
            if parted:
                return serial(*args, 0, 1)
            return serial(*args)
        if not parted:
            return self._on_threads(threads, cap, args)
        # each part's flag: whether it raised (its exception stays on its thread, and the
        # rest of its part unwritten): the whole loop again on this thread raises it, as
        # the kernel does on one thread
        raised = np.zeros(threads, dtype=np.bool_)
        self._on_threads(threads, cap, (*args, threads, self._address(args), raised))
        if raised.any():
            return serial(*args, 0, 1)
        return None

    def _on_threads(self, threads: int, cap: int, args):
        """The parallel build called with ``args`` on ``threads`` of numba's ``cap``."""
        if threads == cap:
            return self.parallel(*args)
        numba.set_num_threads(threads)
        try:
            return self.parallel(*args)
        finally:
            numba.set_num_threads(cap)


def _type_key(value) -> Any:
    """A key of ``value``'s numba type as an argument: an array's dtype, dimensions and
    flags (numpy's bitmask: the layout, whether it is writeable and aligned, and more, so
    that two keys may name one type but one key never two), a numpy scalar's dtype (its
    unit or record layout with it: timedelta64's days and seconds are two types), a float's,
    a bool's or an int64's Python type, else numba's type itself."""
    kind = type(value)
    if kind is np.ndarray:
        return value.dtype, value.ndim, value.flags.num
    if isinstance(value, np.generic):
        return kind, value.dtype
    if kind is float or kind is bool:
        return kind
    if kind is int and -(2**63) <= value < 2**63:
        return kind
    return numba.typeof(value)


# The names the parted copies and the loops over the parts take for their own (a kernel's
# arguments never end in two underscores).
_PART, _PARTS, _ADDRESS, _RAISED = "part__", "parts__", "address__", "raised__"


def _stamp(function) -> tuple[int, int] | None:
    """The modification time (ns) and size of ``function``'s source file (None: no file)."""
    try:
        found = os.stat(function.__code__.co_filename)
    except (OSError, AttributeError):
        return None
    return found.st_mtime_ns, found.st_size


def _source_tree(function, stamp: tuple[int, int] | None) -> ast.FunctionDef | None:
    """The definition of ``function`` as parsed from its module's source, undecorated, its
    lines numbered as in the file; None where the source cannot be read or its file is no
    longer the one of ``stamp`` (``_stamp`` when the function was wrapped: a file edited
    since its import would give code other than the function's)."""
    if stamp is None or _stamp(function) != stamp:
        return None
    try:
        source = textwrap.dedent(inspect.getsource(function))
    except (OSError, TypeError):
        return None
    tree = ast.parse(source)
    if len(tree.body) != 1 or not isinstance(tree.body[0], ast.FunctionDef):
        return None
    # the function itself (its file may have changed since it was imported: then the whole
    # function's builds, from its code as imported)
    definition = tree.body[0]
    names = [a.arg for a in definition.args.args]
    if definition.name != function.__name__ or names != _arguments(function):
        return None
    ast.increment_lineno(tree, function.__code__.co_firstlineno - 1)
    definition = tree.body[0]
    definition.decorator_list = []
    return definition


def _define(definition: ast.FunctionDef, function, namespace: dict | None):
    """The function of ``definition``, compiled under ``function``'s file (numba caches a
    function beside the file it reads its source stamp from), its globals ``namespace``, or
    the module's own (None: the helpers the module defines after the kernel are found when
    numba types it, at its first call)."""
    module = ast.Module(body=[definition], type_ignores=[])
    ast.fix_missing_locations(module)
    code = compile(module, function.__code__.co_filename, "exec")
    made_here: dict = {}
    exec(code, function.__globals__ if namespace is None else namespace, made_here)
    made = made_here[definition.name]
    made.__qualname__ = function.__qualname__ + definition.name[len(function.__name__) :]
    made.__module__ = function.__module__
    made.__doc__ = function.__doc__
    return made


def _is_prange(node: ast.AST) -> bool:
    """Whether ``node`` names ``prange`` (``prange`` or ``<module>.prange``)."""
    if isinstance(node, ast.Name):
        return node.id == "prange"
    return isinstance(node, ast.Attribute) and node.attr == "prange"


def _parted(function, stamp: tuple[int, int] | None, error_model: str = "python"):
    """A copy of ``function`` with two more arguments, ``part`` and ``parts``, whose one
    ``prange(n)`` loop runs over ``range(n * part // parts, n * (part + 1) // parts)``: part
    0 of 1 is the whole loop. None where the source cannot be read, the function has a
    closure or defaults, it has no ``prange`` call or more than one, or its parts would not
    be independent (``_parts_independent``); ``error_model`` (numba's) other than "python"
    is part of the name's digest."""
    if function.__closure__ or function.__defaults__ or function.__kwdefaults__:
        return None
    definition = _source_tree(function, stamp)
    if definition is None:
        return None
    if any(
        isinstance(node, ast.Name) and node.id in (_PART, _PARTS, _ADDRESS, _RAISED)
        for node in ast.walk(definition)
    ):
        return None  # the parted copy's own names taken
    named = [node for node in ast.walk(definition) if _is_prange(node)]
    calls = [
        node
        for node in ast.walk(definition)
        if isinstance(node, ast.Call)
        and _is_prange(node.func)
        and len(node.args) == 1
        and not node.keywords
    ]
    if len(calls) != 1 or len(named) != 1 or not _parts_independent(definition, calls[0]):
        return None
    call = calls[0]

    def bound(k: ast.expr) -> ast.expr:  # n * k // parts
        product = ast.BinOp(left=copy.deepcopy(call.args[0]), op=ast.Mult(), right=k)
        return ast.BinOp(left=product, op=ast.FloorDiv(), right=ast.Name(_PARTS, ast.Load()))

    part = ast.Name(_PART, ast.Load())
    following = ast.BinOp(left=ast.Name(_PART, ast.Load()), op=ast.Add(), right=ast.Constant(1))
    call.func = ast.Name("range", ast.Load())
    call.args = [bound(part), bound(following)]
    definition.args.args += [ast.arg(_PART), ast.arg(_PARTS)]
    # numba finds a cached build by its name, its file's stamp (with the texts of the project
    # modules the file imports: femcore/kernel_cache.py) and its bytecode: the
    # rewritten source's digest in the name, so that a change in the rewrite here (which
    # leaves the kernel's file as it was) is not served the build of the old rewrite, nor is
    # the loop over the parts, whose bytecode is the same for every kernel.
    rewritten = ast.unparse(definition) + ("" if error_model == "python" else error_model)
    digest = hashlib.sha1(rewritten.encode()).hexdigest()[:10]
    definition.name = f"{function.__name__}_part_{digest}"
    return _define(definition, function, None)


def _parts_independent(definition: ast.FunctionDef, call: ast.Call) -> bool:
    """Whether the parts of ``definition``'s loop over ``call`` (its ``prange``) may each run
    the whole function: the loop is the function's last statement, the statements before it
    bind local names only (each part runs them: a write to an argument there, such as
    zeroing an output, would undo another part's items), nothing is returned, and the loop
    body accumulates into no name bound outside it (a reduction numba's parallel build
    combines across threads, which the parts would not). Otherwise the function keeps
    numba's parallel build."""
    body = [
        statement
        for statement in definition.body
        if not (isinstance(statement, ast.Expr) and isinstance(statement.value, ast.Constant))
    ]
    if not body or not isinstance(body[-1], ast.For) or body[-1].iter is not call:
        return False
    loop = body[-1]
    for statement in body[:-1]:
        if not isinstance(statement, ast.Assign):
            return False
        # each part runs these: a call (other than len) may write to its arguments
        if any(
            isinstance(node, ast.Call)
            and not (isinstance(node.func, ast.Name) and node.func.id == "len")
            for node in ast.walk(statement)
        ):
            return False
        for target in statement.targets:
            names = target.elts if isinstance(target, ast.Tuple) else [target]
            if not all(isinstance(name, ast.Name) for name in names):
                return False
    if any(
        isinstance(node, ast.Return) and node.value is not None for node in ast.walk(definition)
    ):
        return False
    # the augmented assignments' targets found once (asked of each name in the loop, the walk
    # was quadratic in the loop's size: 1.6 s of CPU for the 27 kernels of a process)
    augmented = [node for node in ast.walk(loop) if isinstance(node, ast.AugAssign)]
    targets = {id(node.target) for node in augmented}
    bound_inside = {
        node.id
        for node in ast.walk(loop)
        if isinstance(node, ast.Name) and isinstance(node.ctx, ast.Store)
        and id(node) not in targets
    }  # fmt: skip
    return all(
        node.target.id in bound_inside for node in augmented if isinstance(node.target, ast.Name)
    )


def _arguments(function) -> list[str]:
    """The names of ``function``'s positional arguments."""
    code = function.__code__
    return list(code.co_varnames[: code.co_argcount])


def _over_parts(function, arguments: list[str], part_build):
    """A function of ``function``'s ``arguments``, ``parts`` (int64, the threads),
    ``address`` (int64: where the machine code of ``part_build``, the plain build of
    ``_parted(function)``, starts for these arguments' types, ``_Parallel._address``) and
    ``raised`` ((parts,) bool, written) whose ``prange`` loop calls that code on part k of
    ``parts``, on thread k (numba's parallel loop splits its range into one chunk a thread),
    and sets ``raised[k]`` where that part raised.

    The call goes through the address (``_call_at``), not to ``part_build`` by name: numba
    links a build called by name into its caller and optimises and compiles it again there,
    which cost the fibrous force pass's parallel build 27.2 s of CPU against 1.2 s through
    the address, the same numbers to the last bit (benchmarks/suite_parallel_build.py). The
    parts thus run the plain build's own machine code on any thread count."""
    names = ", ".join(arguments)
    digest = part_build.py_func.__name__.rsplit("_", 1)[-1]  # the parted copy's
    # the part as int64 (prange's index is unsigned): the plain build's one signature
    source = (
        f"def {function.__name__}_parallel_{digest}({names}, {_PARTS}, {_ADDRESS}, {_RAISED}):\n"
        f"    for {_PART} in prange({_PARTS}):\n"
        f"        {_RAISED}[{_PART}] = call_at({_ADDRESS}, ({names}, int64({_PART}), {_PARTS}))\n"
    )
    tree = ast.parse(source)
    ast.increment_lineno(tree, function.__code__.co_firstlineno - 1)
    definition = tree.body[0]
    assert isinstance(definition, ast.FunctionDef)
    namespace = {
        "__builtins__": __builtins__,
        "call_at": _call_at,
        "prange": numba.prange,
        "int64": numba.int64,
    }
    return _define(definition, function, namespace)


def _renamed(function, suffix: str):
    """A copy of ``function`` (the same code, globals, defaults and closure) whose name and
    qualified name end in ``suffix``: numba caches it in files of its own."""
    copy = types.FunctionType(
        function.__code__,
        function.__globals__,
        function.__name__ + suffix,
        function.__defaults__,
        function.__closure__,
    )
    copy.__qualname__ = function.__qualname__ + suffix
    copy.__module__ = function.__module__
    copy.__doc__ = function.__doc__
    return copy


def jit(function):
    """``function`` compiled with its ``prange`` loops in parallel, on ``threads_for`` threads
    of its first argument's length, and compiled plain for a loop on one thread
    (``_Parallel``; as is without numba)."""
    if not AVAILABLE:
        return function
    return _Parallel(function)


def jit_lanes(function):
    """``jit`` with numba's numpy error model: a division by zero gives inf or nan and is not
    tested before each division, a test and branch that keeps LLVM from vectorising a loop
    (``lanes``). For the kernels whose inner loops run across cells (elements/fibrous/
    kernels.py ``_cells_pass``), which test their own divisors where a zero can occur."""
    if not AVAILABLE:
        return function
    return _Parallel(function, "numpy")


def plain_part(kernel):
    """The plain build of the ``jit`` (or ``jit_lanes``) ``kernel`` as a helper of compiled
    code that runs the kernel's loop on its own thread (a fused pass): called with the
    kernel's arguments and two more, the part and the parts (``np.int64(0), np.int64(1)``:
    the whole loop; int64, not the literals 0 and 1, for which numba would build it again),
    it is the very build the kernel runs on one thread, compiled once for both callers. A
    helper compiled apart from the same source (``lanes(function)``) was a second build of
    the loop, the same machine code: 8.5 s of CPU for the ply contact's eight fused stages
    on a fresh cache (benchmarks/suite_kernels.py). Where the kernel keeps its whole build
    (its source unreadable, ``_parted``) or without numba: the kernel's function as such a
    helper, the part and the parts ignored."""
    if isinstance(kernel, _Parallel) and kernel.parted:
        return kernel.serial
    function = getattr(kernel, "_function", kernel)
    if not AVAILABLE or isinstance(kernel, _Parallel) and not kernel._native:
        return lambda *args: function(*args[:-2])
    names = ", ".join(_arguments(function))
    whole = njit(function, error_model=getattr(kernel, "_error_model", "python"))
    namespace: dict = {"whole": whole}
    exec(f"def whole_loop({names}, {_PART}, {_PARTS}):\n    whole({names})\n", namespace)
    return numba.njit(namespace["whole_loop"])


def serial(function):
    """``function`` compiled to run on the calling thread (as is without numba): a kernel, or
    a helper called from compiled loops.

    A helper is compiled once per signature and linked into each compiled caller, whose
    module LLVM optimises with it: LLVM inlines the small ones (the fibrous cells' geometry)
    and calls the larger ones. numba's ``inline="always"`` (``inline``: the helper's IR
    copied into every call site before the caller is typed) compiles each copy again: with
    every fibrous helper spliced, the three modules tests/test_fibrous.py,
    test_bias_extension.py and test_fabric_section_kernels.py took 136.6 s of CPU compiling,
    with only the laws' value, slope and energy and a level's strains spliced 66.2 s (the
    fibrous force pass 39.6 -> 8.1 s, its Hessian 35.8 -> 11.1 s, the fabric section 25.5 ->
    9.8 s), the explicit step as fast (benchmarks/suite_kernels.py). The same numbers to the
    last bit either way (IEEE, no fastmath: the same operations in the same order)."""
    if not AVAILABLE:
        return function
    return njit(function)


def lanes(function):
    """``serial`` with numba's numpy error model: a division by zero gives inf or nan instead
    of raising ZeroDivisionError, so that the division has no test and branch, which would
    keep LLVM from vectorising a loop of the helper (elements/lane_maths.py: helpers whose
    divisors are never zero)."""
    if not AVAILABLE:
        return function
    return njit(function, error_model="numpy")


def lane_rows(function):
    """``lanes`` without numba's reference counting (its ``_nrt=False``): for the helpers
    that run loops across the rows of a chunk's scratch array, called a few times a chunk
    with arrays they only read and write (elements/fibrous/level_lanes.py). numba increfs
    and decrefs every array argument of a function at each call, and a helper spliced by
    ``inline`` takes its arguments as new names, increfed and decrefed the same way: atomic
    operations that LLVM keeps around loops and branches, 26 a fibre level of a chunk of 32
    cells, about 4 % of the fibrous force (benchmarks/kernel_pairs.py). Such a helper cannot
    make an array (numba refuses np.empty there when it compiles it), and must never return
    one of its array arguments: its caller would take the return as a reference it was
    given, and free the array while it is still in use (a crash, not an error). The
    helpers return a number or nothing. The same numbers to the last bit."""
    if not AVAILABLE:
        return function
    return njit(function, error_model="numpy", _nrt=False)


def inline(function):
    """``function`` spliced into each compiled caller (numba's ``inline="always"``: its IR
    copied into every call site before the caller is typed), as is without numba. For the
    few helpers of the explicit force pass that LLVM would leave as calls (the packed laws,
    a level's strains): a call with array arguments costs their reference counting, which
    made the fibrous explicit step about twice as slow per cell with them called
    (benchmarks/suite_kernels.py). Each copy is compiled again in each caller: every other
    helper is ``serial``."""
    if not AVAILABLE:
        return function
    return njit(function, inline="always")


def _prange(n):  # pragma: no cover - replaced by numba.prange inside compiled code
    return range(n)


prange = numba.prange if AVAILABLE else _prange
