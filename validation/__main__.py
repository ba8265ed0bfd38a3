"""python -m validation: run the validation cases and write the report (see --help)."""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

from femcore.writable import check_folder
from fibreshell.folder_lock import FolderInUse
from validation.cases import CASES, RESOLUTIONS
from validation.report import default_jobs, run_cases

__all__ = ["main", "parse"]


def parse(argv: list[str], prog: str = "python -m validation") -> argparse.Namespace:
    """The command line: --list, --cases, --resolution, --out (names checked here); ``prog``
    the command's name in its help and errors (``fibreshell report`` runs it too)."""
    parser = argparse.ArgumentParser(
        prog=prog,
        description="Run the validation cases and write an HTML report with results.json.",
    )
    parser.add_argument("--list", action="store_true", help="list the case names and exit")
    parser.add_argument("--cases", default=None, help="comma-separated case names (default: all)")
    parser.add_argument("--resolution", default="default", help="|".join(RESOLUTIONS))
    parser.add_argument(
        "--out", default="report", help="report folder (default: report, inside the working folder)"
    )
    parser.add_argument(
        "--jobs",
        type=int,
        default=None,
        help="cases run at once in parallel processes, the longest first (default: one per "
        "core free, those the machine's load leaves)",
    )
    args = parser.parse_args(argv)
    if args.jobs is None:
        args.jobs = default_jobs()
    if args.jobs < 1:
        parser.error(f"--jobs must be a whole number >= 1, got {args.jobs}")
    try:  # a folder, writable, before any case runs
        if not args.list:
            check_folder(Path(args.out), "--out")
    except (ValueError, OSError) as error:
        parser.error(str(error))
    if args.resolution not in RESOLUTIONS:
        parser.error(
            f"unknown resolution {args.resolution!r}: expected one of {', '.join(RESOLUTIONS)}"
        )
    if args.cases is not None:
        names = [n.strip() for n in args.cases.split(",") if n.strip()]
        unknown = [n for n in names if n not in CASES]
        if unknown or not names:
            parser.error(
                f"unknown case name(s) {', '.join(unknown) or '(none given)'}: "
                f"expected some of {', '.join(CASES)} (see --list)"
            )
        repeated = sorted({n for n in names if names.count(n) > 1})
        if repeated:
            parser.error(
                f"case name(s) {', '.join(repeated)} given more than once in --cases: "
                "expected each case once"
            )
        args.cases = names
    else:
        args.cases = list(CASES)
    return args


def main(argv: list[str] | None = None, prog: str = "python -m validation") -> int:
    """Run the command line (``prog``: the command's name in messages); 0 when every check
    passed and no case raised, 1 when not, 2 when ``--out`` is held by another command (one
    line on stderr names it; nothing ran), 3 when the report could not be written (one line
    on stderr names the file and what was kept)."""
    args = parse(sys.argv[1:] if argv is None else argv, prog)
    if args.list:
        for name, case in CASES.items():
            print(f"{name:28s} {case.title}")
        return 0
    started = time.perf_counter()
    out = Path(args.out)
    try:
        report = run_cases(args.cases, args.resolution, out, jobs=args.jobs)
    except FolderInUse as error:  # another report or run writes there: nothing was touched
        print(f"{prog}: error: {error}", file=sys.stderr)
        return 2
    except OSError as error:  # a full or read-only disk under the report
        written = sorted(p.name for p in out.iterdir()) if out.is_dir() else []
        kept = f"{len(written)} file(s) in {str(out)!r}" if written else "nothing"
        print(f"{prog}: error: {_describe(error)}; stopped, kept: {kept}",
              file=sys.stderr)  # fmt: skip
        return 3
    results = report.cases.values()
    failed = sum(not c.passed for r in results for c in r.outcome.checks)
    errors = sum(r.outcome.error is not None for r in results)
    print(
        f"report written to {out / 'index.html'} in {time.perf_counter() - started:.1f} s: "
        f"{failed} failed check(s), {errors} case error(s)"
    )
    return 1 if failed or errors else 0


def _describe(error: OSError) -> str:
    """One line for a failed write: the file and the reason."""
    if error.filename is None:
        return str(error)
    return f"cannot write {str(error.filename)!r}: {error.strerror or error}"


if __name__ == "__main__":
    sys.exit(main())
