"""The ``fibreshell`` command: run a case file, compare the two kinematics on it, or write the
validation report.

    fibreshell run CASE.toml [--out DIR] [--quiet]
    fibreshell compare CASE.toml [--out DIR] [--shear-ratio R] [--quiet]
    fibreshell report [--cases ...] [--resolution ...] [--out DIR]

Exit status: 0 done, 1 the solver stopped (its last good state is written), 2 a bad case
file or command line (the message names the file, the table and the key).
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

__all__ = ["main"]


def _parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="fibreshell",
        description="Shells under large deformation: run a case file, compare the fibrous "
        "and the Mindlin kinematics on it, or write the validation report.",
    )
    commands = parser.add_subparsers(dest="command", required=True)
    for name, text in (
        ("run", "run one case: result.pvd, history.csv, summary.json in --out"),
        ("compare", "run a case with the fibrous shell and with the calibrated Mindlin shell"),
    ):
        command = commands.add_parser(name, help=text, description=text)
        command.add_argument("case", help="the case file (.toml)")
        command.add_argument("--out", default=None, help="output folder (default: next to "
                             "the working folder, named after the case)")  # fmt: skip
        command.add_argument("--quiet", action="store_true", help="no progress line")
        if name == "compare":
            command.add_argument("--shear-ratio", type=float, default=0.5,
                                 help="Mindlin G13 / E (default 0.5)")  # fmt: skip
    commands.add_parser("report", help="the validation report (python -m validation --help)",
                        add_help=False)  # fmt: skip
    return parser


def _out_folder(argument: str | None, case_path: str, suffix: str) -> Path:
    out = Path(argument) if argument else Path(Path(case_path).stem + suffix)
    if out.exists() and not out.is_dir():
        raise ValueError(f"--out {str(out)!r} is a file: give a folder")
    return out


def main(argv: list[str] | None = None) -> int:
    """Run the command line; returns the exit status."""
    argv = sys.argv[1:] if argv is None else argv
    if argv[:1] == ["report"]:
        from validation.__main__ import main as report

        return report(argv[1:])
    args = _parser().parse_args(argv)
    from fibreshell.case import load_case
    from fibreshell.compare import compare_case
    from fibreshell.run import run_case

    started = time.perf_counter()
    progress = False if args.quiet else True
    try:
        case = load_case(args.case)
        if args.command == "run":
            out = _out_folder(args.out, args.case, "")
            runs = {"": run_case(case, out, progress=progress)}
        else:
            out = _out_folder(args.out, args.case, "-compare")
            runs = compare_case(case, out, progress, args.shear_ratio)
    except ValueError as error:
        print(f"fibreshell: error: {error}", file=sys.stderr)
        return 2
    stopped = False
    for label, run in runs.items():
        where = f" ({label})" if label else ""
        if run.error:
            stopped = True
            print(f"{case.title}{where}: STOPPED after {run.wall_time:.1f} s: {run.error}")
        else:
            print(f"{case.title}{where}: done in {run.wall_time:.1f} s, {run.result.steps} steps")
    print(f"results in {out}/ ({time.perf_counter() - started:.1f} s in all)")
    return 1 if stopped else 0
