"""The ``fibreshell`` command: run a case file, compare the two kinematics on it, or write the
validation report.

    fibreshell run CASE.toml [--out DIR] [--resume] [--quiet]
    fibreshell compare CASE.toml [--out DIR] [--calibration laws|fit|initial-slope]
                     [--kinematics fibrous,mindlin,plies] [--plies N] [--shear-ratio R]
                     [--fit-path NAME] [--fit-evaluations N] [--scheduler ADDRESS]
                     [--workers N] [--quiet]
    fibreshell sweep CASE.toml --vary KEY=V1,V2 [--vary ...] [--zip] [--scheduler ADDRESS]
                     [--workers N] [--out DIR] [--quiet]
    fibreshell identify CASE.toml --data MEASURED.csv --fit KEY[=START][,KEY...] [--path NAME]
                     [--scheduler ADDRESS] [--workers N] [--out DIR] [--quiet]
    fibreshell report [--list] [--cases A,B] [--resolution ...] [--out DIR] [--jobs N]
    fibreshell --version

Every output folder defaults to one named after the case file in the working folder
(``CASE``, ``CASE-compare``, ``CASE-sweep``, ``CASE-identify``; the report's ``report``).

Exit status: 0 done, 1 the solver stopped (its last good state is written; for a sweep: a variant
failed, its row says why; for identify: a run failed, the fit did not converge, or the data do not
determine a fitted value), 2 a bad case file or command line (the message names the file, the table
and the key), or an output folder another command is writing in (fibreshell.folder_lock: the message
names it), 3 an output folder or file could not be written (one line on stderr names the path and
what was kept), 130 interrupted (SIGINT or SIGTERM: ``run`` finishes the step in progress, writes
its outputs, checkpoint and summary.json with status "interrupted" and says how to resume)."""

from __future__ import annotations

import argparse
import json
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
    parser.add_argument("--version", action="version", version=f"fibreshell {_version()}")
    commands = parser.add_subparsers(dest="command", required=True)
    for name, text in (
        ("run", "run one case: result.pvd, history.csv, summary.json in --out"),
        (
            "compare",
            "run a case in several kinematics: the fibrous shell, the Mindlin shell of a "
            "stated calibration, the stack as plies",
        ),
    ):
        command = commands.add_parser(name, help=text, description=text)
        command.add_argument("case", help="the case file (.toml)")
        command.add_argument("--out", default=None, help=_out_help("" if name == "run"
                                                                   else "-compare"))  # fmt: skip
        command.add_argument("--quiet", action="store_true", help="no progress line")
        if name == "run":
            command.add_argument(
                "--resume", action="store_true",
                help="continue from the checkpoint in --out (an explicit or relaxation run "
                "stopped by Ctrl-C, SIGTERM or a kill) to the same result as a run never "
                "stopped",
            )  # fmt: skip
        if name == "compare":
            command.add_argument(
                "--calibration", default="laws", choices=("laws", "fit", "initial-slope"),
                help="how the Mindlin shell is made of the fabric: laws (default: its own "
                "tension, shear and bending laws), fit (Bai's: bending and transverse shear "
                "fitted to the fibrous mid-surface along a path), initial-slope (E = 12 B0 / "
                "h^3, a homogeneous elastic section)",
            )  # fmt: skip
            command.add_argument(
                "--kinematics", default="fibrous,mindlin",
                help="comma-separated subset of fibrous, mindlin, plies (default "
                "fibrous,mindlin)",
            )  # fmt: skip
            command.add_argument(
                "--plies", type=int, default=None,
                help="plies of the plies kinematics (default: the fabric's ply count)",
            )  # fmt: skip
            command.add_argument(
                "--shear-ratio", type=float, default=None,
                help="G13 / E of --calibration initial-slope (default 0.5)",
            )  # fmt: skip
            command.add_argument(
                "--transverse-shear", type=float, default=None, metavar="S",
                help="transverse shear stiffness S (N/mm) of --calibration laws or fit (the "
                "fit's start; default 5 B0 / h^2)",
            )  # fmt: skip
            command.add_argument(
                "--twisting", type=float, default=None, metavar="D",
                help="twisting stiffness D_t (N mm) of --calibration laws or fit (default "
                "B0 / 2); a fabric whose bending law has a toe (B0 = 0) needs both",
            )  # fmt: skip
            command.add_argument(
                "--fit-path", default=None,
                help="the path --calibration fit matches (default: the first)",
            )  # fmt: skip
            command.add_argument(
                "--fit-evaluations", type=int, default=None, metavar="N",
                help="model evaluations --calibration fit may make in all, its Jacobians' "
                "included (default 34; at least 11)",
            )  # fmt: skip
            command.add_argument(
                "--scheduler", default=None, metavar="ADDRESS",
                help="a Dask scheduler (tcp://host:8786) for --calibration fit's runs; "
                "default: a local cluster",
            )  # fmt: skip
            command.add_argument(
                "--workers", type=int, default=None,
                help="worker processes of --calibration fit's local cluster (default: one "
                "per core)",
            )  # fmt: skip
    text = "run a case over values of its keys, every variant a Dask task: sweep.csv in --out"
    command = commands.add_parser("sweep", help=text, description=text)
    command.add_argument("case", help="the case file (.toml)")
    command.add_argument("--vary", action="append", required=True, metavar="KEY=V1,V2,...",
                         help="a dotted key of the case file (part.0.material.bending, "
                         "mesh.rectangle.lx, solver.increments) or kinematics / shear_ratio, "
                         "and its values (TOML values, or linspace(a, b, n), geomspace(a, b, "
                         "n)); several --vary make the full product")  # fmt: skip
    command.add_argument("--zip", action="store_true",
                         help="pair the i-th values of every --vary instead")  # fmt: skip
    command.add_argument("--max-variants", type=int, default=None, metavar="N",
                         help="the most variants the sweep may have (default 10000): more "
                         "is refused before anything runs")  # fmt: skip
    _cluster_options(command, "-sweep")
    text = "fit values of a case's keys to measured data (least squares on Dask)"
    command = commands.add_parser("identify", help=text, description=text)
    command.add_argument("case", help="the case file (.toml)")
    command.add_argument("--data", required=True, help="measured data (.csv): columns x, z "
                         "(a profile along --path) or summary columns (displacement_tip_z, "
                         "...), and dotted case keys for the conditions of each row")  # fmt: skip
    command.add_argument("--fit", required=True, metavar="KEY[=START],...",
                         help="the keys to fit, each with its starting value (default: the "
                         "case file's)")  # fmt: skip
    command.add_argument("--path", default=None, help="the case's path a profile is along")
    command.add_argument("--sigma", default=None, metavar="COLUMN=VALUE,...",
                         help="the measurement uncertainty of response columns (data units): "
                         "each residual is divided by it (default 1)")  # fmt: skip
    command.add_argument("--max-evaluations", type=int, default=34,
                         help="model evaluations the fit may make in all, its Jacobians' "
                         "included (default 34; at least 5 x the fitted keys + 1)")  # fmt: skip
    _cluster_options(command, "-identify")
    commands.add_parser("report", help="run the validation cases and write the report "
                        "(fibreshell report --help)", add_help=False)  # fmt: skip
    return parser


def _version() -> str:
    """The installed package's version (pyproject.toml), or a word saying it is not
    installed (the sources run from a checkout)."""
    from importlib.metadata import PackageNotFoundError, version

    try:
        return version("fibreshell")
    except PackageNotFoundError:
        return "(not installed: version unknown)"


def _out_help(suffix: str) -> str:
    """The --out help: where _out_folder puts the outputs by default."""
    return (f"output folder (default: the case file's name{suffix} inside the working folder, "
            f"e.g. g1151_strip{suffix}/ for cases/g1151_strip.toml)")  # fmt: skip


def _cluster_options(command: argparse.ArgumentParser, suffix: str) -> None:
    command.add_argument(
        "--scheduler", default=None, metavar="ADDRESS",
        help="a Dask scheduler (tcp://host:8786); default: a local cluster",
    )  # fmt: skip
    command.add_argument(
        "--workers", type=int, default=None,
        help="worker processes of the local cluster (default: one per core)",
    )  # fmt: skip
    command.add_argument("--out", default=None, help=_out_help(suffix))
    command.add_argument("--quiet", action="store_true", help="no progress bar")


def _key_numbers(text: str, option: str) -> dict[str, float | None]:
    """``KEY[=NUMBER],...`` (the text of ``option``) as {key: number or None}."""
    from fibreshell.sweep import read_value, split_values

    numbers: dict[str, float | None] = {}
    for item in split_values(text):
        key, sep, number = item.partition("=")
        if not key.strip():
            raise ValueError(f"{option} {text!r}: expected KEY[=NUMBER],KEY[=NUMBER],...")
        value = read_value(number.strip()) if sep else None
        if sep and (isinstance(value, bool) or not isinstance(value, int | float)):
            raise ValueError(f"{option} {item!r}: expected a number after =, got {number!r}")
        numbers[key.strip()] = value
    return numbers


def _sweep(args: argparse.Namespace, progress: bool | None) -> int:
    from fibreshell.sweep import MAX_VARIANTS, parse_vary, sweep

    cap = MAX_VARIANTS if args.max_variants is None else args.max_variants
    vary = dict(parse_vary(item, cap) for item in args.vary)
    if len(vary) != len(args.vary):
        raise ValueError("a key is given to --vary twice: give all its values in one --vary")
    out = _out_folder(args.out, args.case, "-sweep")
    table = sweep(args.case, vary, paired=args.zip, out=out, scheduler=args.scheduler,
                  workers=args.workers, progress=progress, max_variants=cap)  # fmt: skip
    failed = table.failed
    print(table.text())
    which = f" (variants {', '.join(map(str, failed))}: see the error column)" if failed else ""
    print(f"{len(table.rows)} variants, {len(failed)} failed{which}")
    print(f"results in {out / 'sweep.csv'}")
    return 1 if failed else 0


def _identify(args: argparse.Namespace, progress: bool | None) -> int:
    from fibreshell.identify import FitFailed, format_result, identify

    out = _out_folder(args.out, args.case, "-identify")
    try:
        given = _key_numbers(args.sigma, "--sigma") if args.sigma is not None else {}
        sigma = {column: value for column, value in given.items() if value is not None}
        if len(sigma) != len(given):
            raise ValueError(f"--sigma {args.sigma!r}: expected COLUMN=VALUE,...")
        fit = _key_numbers(args.fit, "--fit")
        result = identify(args.case, args.data, fit, path=args.path, out=out,
                          scheduler=args.scheduler, workers=args.workers, progress=progress,
                          max_evaluations=args.max_evaluations, sigma=sigma)  # fmt: skip
    except FitFailed as error:
        print(f"fibreshell identify: STOPPED: {error}")
        return 1
    print(format_result(result))
    print(f"results in {out}/ (identify.json, fit.png)")
    # A value the data do not determine is not a result: status 1, as a fit that failed.
    return 0 if result.success and result.all_determined else 1


def _out_folder(argument: str | None, case_path: str, suffix: str) -> Path:
    """The output folder, checked for writing (femcore.writable.check_folder): an existing
    one, or the nearest existing folder above a new one, which the command creates only once
    its options are checked (a refused command leaves nothing behind)."""
    from femcore.writable import check_folder

    out = Path(argument) if argument else Path(Path(case_path).stem + suffix)
    if out.exists():
        return check_folder(out, "--out", create=False)
    above = next(folder for folder in out.absolute().parents if folder.exists())
    if not above.is_dir():
        raise ValueError(f"--out {str(out)!r}: {str(above)!r} is a file, not a folder")
    check_folder(above, f"--out {str(out)!r}: the folder above it,", create=False)
    return out


def _interrupted_line(case, run, args: argparse.Namespace, out: Path) -> str:
    """The one line of a run stopped by a signal: what it kept, how to go on."""
    from fibreshell.run import kept

    last = run.result.frames[-1]
    where = (f"t = {last.time:.6g} s" if run.summary["solver"] == "explicit"
             else f"load factor {last.load_factor:.6g}")  # fmt: skip
    kind = case.solver["kind"]
    if run.checkpoint is not None and run.checkpoint.exists():
        then = f"resume with: fibreshell run {args.case} --out {out} --resume"
    elif kind == "static":
        then = "a static run keeps no checkpoint: run it again to go on"
    elif case.solver.get("checkpoint") is None:  # [solver] checkpoint = false
        then = "no checkpoint asked for ([solver] checkpoint = false): run it again to go on"
    elif kind == "relaxation":  # its checkpoint is written as an increment converges
        then = "no increment converged yet, so no checkpoint to resume from: run it again"
    else:
        then = "no checkpoint written: run it again"
    return (f"{case.title}: INTERRUPTED by {run.signal} after {run.result.steps} steps (last "
            f"frame at {where}); kept {kept(out, run.checkpoint)}; {then}")  # fmt: skip


def main(argv: list[str] | None = None) -> int:
    """Run the command line; returns the exit status."""
    try:
        return _main(sys.argv[1:] if argv is None else argv)
    except OSError as error:  # femcore.writable.OutputError: one line naming path and kept
        print(f"fibreshell: error: {error}", file=sys.stderr)
        return 3
    except KeyboardInterrupt:  # a second Ctrl-C, or one outside `fibreshell run`
        print("fibreshell: interrupted (outputs may be incomplete)", file=sys.stderr)
        return 130


def _main(argv: list[str]) -> int:
    if argv[:1] == ["report"]:
        from validation.__main__ import main as report

        return report(argv[1:], prog="fibreshell report")
    args = _parser().parse_args(argv)
    from fibreshell.case import load_case
    from fibreshell.compare import calibration_lines, compare_case, summary_lines
    from fibreshell.run import run_case

    started = time.perf_counter()
    progress = False if args.quiet else None  # None: solvers.progress.resolve_progress
    if args.command in ("sweep", "identify"):
        try:
            return (_sweep if args.command == "sweep" else _identify)(args, progress)
        except ValueError as error:
            print(f"fibreshell: error: {error}", file=sys.stderr)
            return 2
    try:
        case = load_case(args.case)
        if args.command == "run":
            from solvers import interruptible

            out = _out_folder(args.out, args.case, "")
            with interruptible():
                run = run_case(case, out, progress=progress, resume=args.resume)
            if run.status == "interrupted":
                print(_interrupted_line(case, run, args, out))
                return 130
            runs = {"": run}
        else:
            out = _out_folder(args.out, args.case, "-compare")
            if args.fit_evaluations is not None and args.calibration != "fit":
                raise ValueError(
                    f"--fit-evaluations {args.fit_evaluations} is the cap of --calibration fit; "
                    f"got --calibration {args.calibration}"
                )
            fitting = {} if args.fit_evaluations is None else {
                "fit_evaluations": args.fit_evaluations}  # fmt: skip
            # The calibration before the runs: a reader knows what is compared while waiting.
            stated = calibration_lines(case, args.calibration, args.shear_ratio, args.kinematics,
                                       args.transverse_shear, args.twisting)  # fmt: skip
            for line in stated:
                print(line, flush=True)
            runs = compare_case(
                case, out, progress, calibration=args.calibration, kinematics=args.kinematics,
                plies=args.plies, shear_ratio=args.shear_ratio, fit_path=args.fit_path,
                transverse_shear=args.transverse_shear, twisting=args.twisting,
                scheduler=args.scheduler, workers=args.workers, **fitting,
            )  # fmt: skip
            comparison = json.loads((out / "comparison.json").read_text())
            fitted = args.calibration == "fit"  # its values are known only now
            for line in summary_lines(comparison, calibration=fitted or not stated):
                print(line)
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
            before = getattr(run.result, "info", {}).get("wall_time_before_resume", 0.0)
            resumed = f" ({before:.1f} s of them before the resume)" if before > 0.0 else ""
            floor = getattr(run.result, "info", {}).get("round_off_accepted")
            told = (
                f" ({floor['count']} accepted at the round-off floor, residual ratios up to "
                f"{floor['largest_ratio']:.3g} against tol {floor['tol']:g})"
                if floor
                else ""
            )
            print(f"{case.title}{where}: done in {run.wall_time:.1f} s{resumed}, "
                  f"{run.result.steps} steps{told}")  # fmt: skip
    print(f"results in {out}/ ({time.perf_counter() - started:.1f} s in all)")
    return 1 if stopped else 0
