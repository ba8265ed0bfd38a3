"""What parting the compiled kernels costs a process (femcore.jit): the check that a kernel's
``prange`` loop may be split into independent parts (``_parts_independent``), run on every
kernel of the library, beside a reference pass of the check as it was written before (kept
here: for each name stored in the loop it walked the whole loop again for augmented
assignments, quadratic in the loop's size). Both passes must agree on every kernel.

Each process that runs a kernel parts it at its first use: the report's workers, pytest's
workers and every process a test starts pay it once per kernel they meet.

Measured (one thread, CPU time, best of 5, 2 cores shared with other jobs, load 6.5-6.8): the
27 kernels (27 prange loops), the check alone 0.985 s before (the reference pass), 0.039 s
now; the whole of ``_parted`` on every kernel (reading the source, the check, the rewrite,
the compile of the copy) 1.36-1.82 s before (one pass each, load 6), 0.24 s now. The two
passes agree on all 27 loops (each parted).

Run: python benchmarks/kernel_parting.py [--repeats 5]
"""

from __future__ import annotations

import argparse
import ast
import importlib
import os
import pkgutil
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import elements  # noqa: E402
import femcore  # noqa: E402
import solvers  # noqa: E402
from femcore import jit  # noqa: E402


def reference_parts_independent(definition: ast.FunctionDef, call: ast.Call) -> bool:
    """``femcore.jit._parts_independent`` as it was written before (the reference pass)."""
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
    bound_inside = {
        node.id
        for node in ast.walk(loop)
        if isinstance(node, ast.Name) and isinstance(node.ctx, ast.Store)
        and not any(node is a.target for a in ast.walk(loop) if isinstance(a, ast.AugAssign))
    }  # fmt: skip
    return all(
        node.target.id in bound_inside
        for node in ast.walk(loop)
        if isinstance(node, ast.AugAssign) and isinstance(node.target, ast.Name)
    )


def kernels() -> list:
    """Every kernel (femcore.jit's wrapper) the library's modules define."""
    found: dict[int, object] = {}
    for package in (elements, femcore, solvers):
        for module in pkgutil.walk_packages(package.__path__, package.__name__ + "."):
            try:
                loaded = importlib.import_module(module.name)
            except ImportError:  # an optional dependency missing
                continue
            for value in vars(loaded).values():
                if isinstance(value, jit._Parallel):
                    found[id(value)] = value
    return list(found.values())


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--repeats", type=int, default=5)
    args = parser.parse_args()
    load = ", ".join(f"{x:.2f}" for x in os.getloadavg())
    every = kernels()
    loops = []
    for kernel in every:
        definition = jit._source_tree(kernel._function, kernel._stamp)
        if definition is None:
            continue
        calls = [
            node
            for node in ast.walk(definition)
            if isinstance(node, ast.Call) and jit._is_prange(node.func)
        ]
        loops += [(definition, call) for call in calls]
    agree = sum(jit._parts_independent(d, c) == reference_parts_independent(d, c) for d, c in loops)
    print(f"{len(every)} kernels, {len(loops)} prange loops; load before {load}")
    print(f"the two passes agree on {agree} of {len(loops)}")
    for label, check in (("reference", reference_parts_independent),
                         ("now", jit._parts_independent)):  # fmt: skip
        best = float("inf")
        for _ in range(args.repeats):
            start = time.process_time()
            for definition, call in loops:
                check(definition, call)
            best = min(best, time.process_time() - start)
        print(f"{label:10s} the check on every loop: {best:.3f} s CPU (best of {args.repeats})")
    best = float("inf")
    for _ in range(args.repeats):
        start = time.process_time()
        for kernel in every:
            jit._parted(kernel._function, kernel._stamp)
        best = min(best, time.process_time() - start)
    print(f"now        _parted on every kernel: {best:.3f} s CPU (best of {args.repeats})")
    print("load after " + ", ".join(f"{x:.2f}" for x in os.getloadavg()))


if __name__ == "__main__":
    main()
