"""The arc-length step length (solvers/arc_step.py, docs/theory.md §6.6 "Step length") beside
the solver before it, in one process: every step at most the first one's length
(``LONGEST_STEP = 1``, stretched to a load step of 1 / increments where the first step carried
less), Crisfield's rule counting every factorising iteration, and the corrector's strict
convergence test (no round-off floor): the reference pass. Per model and increments: the
increments taken, the Newton iterations, the tangents formed (failed attempts included), the
cuts, the CPU, and where it ended.

Lines:

1. the von Mises truss of tests/test_static.py (both limit points of its closed form), plain
   and with arc_chords 1e-2, increments 3-20;
2. the imperfect strip (MindlinShell and FibrousShell 100 x 5 mm, 20 x 1 cells, tip load 1.5
   Pcr with a side load of 1e-4 Pcr) at 3, 5 and 10 increments: the stiff-then-soft path;
3. the cantilever of tests/test_arc_chords.py (P L^2 / EI = 3, 4 increments) and the flat
   bias stack of tests/test_bias_extension.py (4 increments);
4. with ``--paper``: the paper cases' computations (validation.paper.case.compute_paper_case,
   the arc-length path with at_limit="jump"), each run's increments, iterations and tangents,
   and how far each check's value moved.

    python benchmarks/arc_step_length.py [--paper bai-5.1,bai-6.1.1] [--resolution default]

Measured (one numba thread, CPU, one process, 2 cores shared with other jobs, load 3.6-5):
  1. the truss's 36 runs 1733 -> 1700 increments (13 fewer, 21 the same, 2 with two more: 14
     and 16 increments without chords), 5037 -> 4985 iterations, 5632 -> 5683 tangents; every
     run passes both limit points (within 3.8 % of the closed form's loads either way).
  2. before, every strip stopped near load factor 0.65 (Pcr is 0.667) after its max_increments
     (80, 120, 220); now MindlinShell 27 / 28 / 31 increments at 3 / 5 / 10 (87-95 iterations,
     0.10-0.11 s), lateral tip 78.944 mm (the elastica's 78.858); FibrousShell 60 / 64 / 66
     (305-322 iterations, 0.72-0.77 s), 78.907 mm.
  3. the cantilever the same (4 increments, 23 iterations); the bias stack 5 increments, 24 ->
     25 iterations.
  4. (default resolution) bai-6.1.1, 6.1.2, 6.2.1, 6.2.2: the same increments, iterations and
     checks to the bit; bai-5.1: 973 -> 947 Newton iterations over its seven runs, the three
     kinematics 18 / 21 / 24 -> 20 / 20 / 21 increments (188 / 214 / 256 -> 216 / 216 / 234
     tangents), its checks within 2.5e-9 relative, 15/15 passed.
"""

from __future__ import annotations

import argparse
import importlib
import math
import os
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # this tree's packages

import numpy as np  # noqa: E402

import solvers.arc_length as arc_length  # noqa: E402
import solvers.round_off as round_off  # noqa: E402
from solvers import ConvergenceError, Static  # noqa: E402
from solvers.arc_step import ArcStep  # noqa: E402


class FirstStepCap(ArcStep):
    """The rule before solvers.arc_step (the reference pass): Crisfield's factor within [1/2,
    2], never above the first step's length stretched to a load step of 1 / increments."""

    def after(self, motion, spent, pushed=False):
        length = motion.length
        if self.first_longest is None:
            carried = max(motion.load, 1e-300)
            self.first_longest = length * max(1.0, 1.0 / (self.increments * carried))
        growth = float(np.clip(np.sqrt(self.aim / max(spent, 1)), 0.5, 2.0))
        return min(length * growth, self.first_longest)


def strict_test(*args, **kwargs) -> float:
    """The round-off probe of the reference pass: no floor (the corrector's strict test)."""
    return math.inf


def factorised(history, count, chord_steps, tol) -> int:
    """The iterations Crisfield's rule counted in the reference pass: all that factorised."""
    return count - chord_steps


RULES = (("first-step cap", FirstStepCap), ("arc_step", ArcStep))
PROBE = round_off.round_off_ratio
SPENT = arc_length.iterations_spent


def use(rule) -> None:
    """Static's arc length with ``rule``'s step control, and for ArcStep only with the
    corrector's round-off floor and Crisfield's count down to the settled ratio (the reference
    pass is the solver before the three)."""
    new = rule is ArcStep
    arc_length.ArcStep = rule  # type: ignore[misc]
    round_off.round_off_ratio = PROBE if new else strict_test  # type: ignore[assignment]
    arc_length.iterations_spent = SPENT if new else factorised  # type: ignore[assignment]


def run(model, rule, **options):
    """Static along the arc length with ``rule``'s step control: (result, stopped, CPU)."""
    use(rule)
    started = time.process_time()
    try:
        result = Static(path="arc_length", progress=False, **options).solve(model)
        stopped = ""
    except ConvergenceError as error:
        result = error.result
        stopped = f" STOPPED at {error.load_factor:.4g}"
    finally:
        use(ArcStep)
    return result, stopped, time.process_time() - started


def counts(result) -> str:
    info = result.info
    return (
        f"{len(result.frames) - 1:4d} increments, {sum(info['iterations_per_increment']):5d} "
        f"iterations, {info['evaluations']['tangent']:5d} tangents, {info['cuts']} cuts"
    )


def truss_lines() -> None:
    sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
    from tests.test_static import _von_mises_truss, truss_limit_loads

    model, _, _, travel = _von_mises_truss()
    compiled = model.compile()
    expected = truss_limit_loads(travel)
    print(f"1. von Mises truss, limit loads of the closed form {expected[0]:.4f} {expected[1]:.4f}")
    for chords in (0.0, 1e-2):
        for increments in range(3, 21):
            for name, rule in RULES:
                result, stopped, cpu = run(compiled, rule, increments=increments, arc_chords=chords)
                limits = " ".join(f"{value:.4f}" for value in result.info["limit_points"])
                print(
                    f"  chords {chords:g}, {increments:2d} increments, {name:14s}: "
                    f"{counts(result)}, limits {limits}, {cpu:.2f} s{stopped}"
                )


def imperfect_strip(kind: str):
    """(model, tip nodes, closed-form lateral tip) of the review's strip at 1.5 Pcr: the
    test's (tests/test_arc_step.py ``imperfect_column``) and the elastica of
    validation.references.elastica."""
    sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
    from tests.test_arc_step import LENGTH, imperfect_column
    from validation.references.elastica import buckled_cantilever_column

    model, tip, bending = imperfect_column(kind)
    load = 1.5 * math.pi**2 * bending / (4 * LENGTH**2)
    return model, tip, buckled_cantilever_column(LENGTH, load, bending)["lateral"]


def strip_lines() -> None:
    for kind in ("mindlin", "fibrous"):
        model, tip, lateral = imperfect_strip(kind)
        compiled = model.compile()
        print(f"2. imperfect {kind} strip at 1.5 Pcr, the elastica's lateral tip {lateral:.3f} mm")
        for increments in (3, 5, 10):
            for name, rule in RULES:
                result, stopped, cpu = run(compiled, rule, increments=increments)
                end = result.frames[-1]
                print(
                    f"  {increments:2d} increments, {name:14s}: {counts(result)}, load factor "
                    f"{end.load_factor:.4f}, tip lateral {end.positions[tip, 2].mean():.3f} mm, "
                    f"{cpu:.2f} s{stopped}"
                )


def other_lines() -> None:
    sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
    from tests.test_bias_extension import STACK, bias_specimen
    from validation.specimens import mindlin_strip

    mesh, model = mindlin_strip(100.0, 10.0, 1.0, 1e5, cells=20)
    tip = mesh.nodes("right")
    model.force(tip, (0.0, 0.0, -3.0 * (1e5 * 10.0 / 12) / 100.0**2 / len(tip)))
    _, bias = bias_specimen(STACK)
    for label, built in (("3. cantilever P L^2/EI = 3", model), ("3. flat bias stack", bias)):
        compiled = built.compile()
        for name, rule in RULES:
            result, stopped, cpu = run(compiled, rule, increments=4)
            print(f"  {label}, {name:14s}: {counts(result)}, {cpu:.2f} s{stopped}")


def paper_lines(names: list[str], resolution: str) -> None:
    from validation.paper.case import compute_paper_case

    for case in names:
        module = "validation.cases." + case.replace("-", "_").replace(".", "_")
        spec = importlib.import_module(module).SPEC
        outcomes = {}
        for name, rule in RULES:
            use(rule)
            started = time.process_time()
            try:
                outcomes[name] = compute_paper_case(spec, resolution)
            finally:
                use(ArcStep)
            cpu = time.process_time() - started
            outcome = outcomes[name]
            passed = sum(check.passed for check in outcome.checks)
            print(
                f"4. {case} {resolution}, {name:14s}: {cpu:6.2f} s CPU, {outcome.steps} Newton "
                f"iterations, {passed}/{len(outcome.checks)} checks passed (load "
                f"{os.getloadavg()[0]:.1f})\n    {outcome.solver}",
                flush=True,
            )
        old, new = (outcomes[name] for name, _ in RULES)
        moved = [
            abs(b.value - a.value) / abs(a.value)
            for a, b in zip(old.checks, new.checks)
            if abs(a.value) > 1e-10
        ]
        print(f"  the checks' values moved at most {max(moved, default=0.0):.2e} relative")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--paper", default="", help="comma-separated paper cases (line 4)")
    parser.add_argument("--resolution", default="default")
    parser.add_argument("--only-paper", action="store_true", help="line 4 alone")
    args = parser.parse_args()
    import numba

    numba.set_num_threads(1)
    os.environ.setdefault("FIBRESHELL_PROGRESS", "0")
    print(f"load {os.getloadavg()[0]:.1f}")
    if not args.only_paper:
        truss_lines()
        strip_lines()
        other_lines()
    if args.paper:
        paper_lines([name.strip() for name in args.paper.split(",")], args.resolution)


if __name__ == "__main__":
    main()
