"""What the validation report spends beside its solves: each case's figures (per figure: the
layout passes, the text measurement, the 3D projection, the drawing, the PNG encoding), its
result files (VTU, XDMF/HDF5), the HTML page and the imports of a worker process, largest
first.

Three steps:

``save``: compute the cases once (``Case.compute``, in worker processes, one numba thread
each) and pickle each outcome's figure data into a folder, with the case's compute CPU.

``render``: draw every saved case's figures and files again (``Case.render``), in fresh
processes with the code found on each ``--code`` folder (a checkout of the code before, and
this one, side by side in the same run, alternating), and print per case, per figure and per
part the CPU seconds (``time.process_time``) as a table, largest first. The parts are
inclusive and nest: "draw" (the canvas's draw, layout included), "layout" (the constrained
layout engine), "tight bbox" (``bbox_inches="tight"``: a further draw to measure the box),
"text" (the Agg renderer's text measurement), "3D axes" (their draw and projection), "png"
(PIL's encoding and write), "vtu" / "xdmf" (the result files).

``imports``: each of the worker's heavy imports in a fresh process (CPU), and the HTML page
rendered from a report's results.json.

Usage::

    python benchmarks/report_overhead.py save --resolution default --out /tmp/fig-data
    python benchmarks/report_overhead.py render --data /tmp/fig-data --code /tmp/main --code .
    python benchmarks/report_overhead.py imports --results /tmp/report/results.json

Measured (2 cores shared with other jobs, load 9-15; one numba thread; CPU, the least of 2
rounds, the code before (main 97cc118, from git archive) and this one alternating in fresh
processes on the same pickled default results of the 23 cases):

The default report's cases computed (``save``, 2 workers, load 9-15, a cold numba cache
compiled by the first cases): 476 s CPU of solves. Their figures and files (``render``):
17.70 -> 14.83 s CPU in all, about 3 % of the report. Per case: the five paper cases 2.2-2.6
-> 1.7-2.1 s each (bai-6.2.1 2.55 -> 1.95, bai-6.1.1 2.37 -> 1.90, bai-6.2.2 2.25 -> 1.69,
bai-6.1.2 2.24 -> 1.86, bai-5.1 2.31 -> 2.12), hemisphere-plies 1.26 -> 1.10,
hemisphere-forming 0.93 -> 0.84, fibrous-deck-of-cards 0.53 -> 0.35, the 15 others
0.1-0.6 s each, about as before. By part, before -> after (inclusive, they nest): savefig
12.83 -> 6.28 (the layout now runs before it), the constrained layout 5.30 -> 4.69, the
drawing to the file 4.29 -> 4.34, the XDMF/HDF5 series 2.64 -> 2.60 (femcore.xdmf: h5py's
dataset per field and frame; not changed here), PNG encoding 0.96 -> 0.67, the 3D axes'
drawing 0.77 -> 0.58, text measurement 0.65 -> 0.66, tight boxes 0.42 -> 0.36, VTU 0.37.
Per figure the largest after: fibreshell.compare's path figures of the ply cases 0.40-0.42
(savefig with constrained layout, in fibreshell: not changed here), the paper cases' 3D
views 0.26-0.37 (a tight box around 3D axes still needs savefig's two draws), their side
elevations 0.17-0.32 (0.26-0.60 before), sides 0.18-0.20 (0.47-0.64), laws 0.10 (0.23-0.26),
the 2000-px hemisphere-plies maps 0.16-0.17 (0.46-0.55), every one-axes figure 0.03-0.05
(0.07-0.20).

What changed (validation.plots): ``save`` lays a constrained figure out once at its dpi and
saves it without its engine, with its tight box measured from that layout for a 2D figure
(savefig drew the figure once without output to lay it out, then to the file); the same
pixels, 0 of 255 on every such figure. PNGs at zlib level 3: 34 -> 21 ms per 990 x 847
figure, the report's PNGs 4.65 MB either way. A line per node (the directors of the side
elevations, the 3D views, fibrous-heavy-cantilever and fibrous-deck-of-cards, the
hemisphere's fibres) drawn as one line broken by NaN (``segments``): the 3D views' pixels
the same; the side elevations differ in 80-1647 pixels, at most 238 of 255, where the
vertical segment at the clamp was snapped to the pixel grid as a line of its own (half a
pixel); the deck of cards' dotted closed form in 293 px (109 of 255, the dots' phase), the
heavy cantilever in 47 px (94), the hemisphere's fibres in 8789 px (189 of 255) where warp
and weft cross (the weft is now drawn over every warp fibre, before alternately).

Imports (``imports``, each in a fresh process, CPU, load 11): validation.report 1.5 s in
all (validation.cases 1.6 alone, fibreshell 0.8, solvers 0.8, elements 0.7, femcore 0.55,
matplotlib.pyplot 0.5, mpl_toolkits.mplot3d 0.45, dask.distributed 0.4 (not imported by a
report worker), numba 0.3, scipy.sparse 0.2, meshio 0.16, h5py 0.12, gmsh 0.11): about 1.5 s
per worker process and the report's own. index.html (render_html) from the 23 cases'
results.json: 2 ms.
"""

from __future__ import annotations

import argparse
import json
import os
import pickle
import subprocess
import sys
import time
from collections import defaultdict
from pathlib import Path
from typing import Any

import numpy as np

if "_child" not in sys.argv:  # a _child: the tree its parent named (PYTHONPATH)
    sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # this tree's packages


# The parts timed inside a render: label -> (module, attribute path of the callable).
PARTS = {
    "savefig": ("matplotlib.figure", "Figure.savefig"),
    "draw": ("matplotlib.backends.backend_agg", "FigureCanvasAgg.draw"),
    "layout": ("matplotlib.layout_engine", "ConstrainedLayoutEngine.execute"),
    "tight bbox": ("matplotlib.figure", "Figure.get_tightbbox"),
    "text": ("matplotlib.backends.backend_agg", "RendererAgg.get_text_width_height_descent"),
    "3D axes": ("mpl_toolkits.mplot3d.axes3d", "Axes3D.draw"),
    "png": ("PIL.Image", "Image.save"),
    "vtu": ("femcore.results", "write_vtu"),
    "xdmf": ("femcore.xdmf", "write_xdmf"),
}
IMPORTS = (
    "numpy",
    "scipy.sparse",
    "numba",
    "matplotlib.pyplot",
    "mpl_toolkits.mplot3d",
    "meshio",
    "h5py",
    "gmsh",
    "dask.distributed",
    "femcore",
    "elements",
    "solvers",
    "fibreshell",
    "validation.cases",
)


def _load() -> str:
    """The machine's load averages, for the record."""
    return " ".join(f"{value:.1f}" for value in os.getloadavg())


# --- save -----------------------------------------------------------------------------------


def _compute(name: str, resolution: str, folder: str) -> tuple[str, float]:
    """Compute case ``name`` and pickle its figure data into ``folder``: (name, CPU s)."""
    import numba

    from validation.cases import CASES

    numba.set_num_threads(1)
    os.environ["FIBRESHELL_PROGRESS"] = "0"
    cpu = time.process_time()
    outcome = CASES[name].compute(resolution)
    cpu = time.process_time() - cpu
    with open(Path(folder) / f"{name}.pkl", "wb") as file:
        pickle.dump(outcome.data, file, protocol=pickle.HIGHEST_PROTOCOL)
    return name, cpu


def save(args: argparse.Namespace) -> None:
    """The ``save`` step."""
    import multiprocessing
    from concurrent.futures import ProcessPoolExecutor, as_completed

    from validation.cases import CASES
    from validation.report import schedule

    names = args.cases.split(",") if args.cases else list(CASES)
    folder = Path(args.out)
    folder.mkdir(parents=True, exist_ok=True)
    print(f"load {_load()}", flush=True)
    costs = {}
    context = multiprocessing.get_context("spawn")
    with ProcessPoolExecutor(args.jobs, mp_context=context) as pool:
        futures = [
            pool.submit(_compute, name, args.resolution, str(folder))
            for name in schedule(names, args.resolution)
        ]
        for future in as_completed(futures):
            name, cpu = future.result()
            costs[name] = cpu
            print(f"{name:28s} compute {cpu:7.1f} s CPU", flush=True)
    (folder / "compute.json").write_text(
        json.dumps({"resolution": args.resolution, "compute_cpu_s": costs}, indent=1)
    )
    print(f"load {_load()}")


# --- render ---------------------------------------------------------------------------------


def _instrument(times: dict[str, float]) -> None:
    """Wrap each of ``PARTS`` so that its CPU time adds to ``times[label]`` (outermost calls
    only: a part that calls itself is counted once)."""
    import importlib

    for label, (module_name, path) in PARTS.items():
        module = importlib.import_module(module_name)
        owner: Any = module
        *outer, attribute = path.split(".")
        for part in outer:
            owner = getattr(owner, part)
        original = getattr(owner, attribute)
        depth = [0]

        def wrapped(*a, __original=original, __label=label, __depth=depth, **k):
            __depth[0] += 1
            start = time.process_time()
            try:
                return __original(*a, **k)
            finally:
                __depth[0] -= 1
                if __depth[0] == 0:
                    times[__label] += time.process_time() - start

        setattr(owner, attribute, wrapped)
        if owner is module:  # the callers that imported the name itself
            for other in list(sys.modules.values()):
                if getattr(other, attribute, None) is original:
                    setattr(other, attribute, wrapped)


def _render_all(folder: str, names: list[str], out: str, repeats: int) -> dict[str, Any]:
    """In this process: render each saved case ``repeats`` times into ``out``; per case and
    per figure file the least CPU of the repeats, by part."""
    import numba

    import validation.plots  # noqa: F401  (matplotlib's Agg backend)
    from validation.cases import CASES

    numba.set_num_threads(1)
    times: dict[str, float] = defaultdict(float)
    _instrument(times)
    # A figure's parts are attributed to its file: savefig's first argument.
    import matplotlib.figure

    savefig = matplotlib.figure.Figure.savefig
    per_file: dict[str, dict[str, float]] = {}

    def by_file(self, fname, *a, **k):
        before = dict(times)
        try:
            return savefig(self, fname, *a, **k)
        finally:
            key = Path(str(fname)).name
            per_file[key] = {label: times[label] - before.get(label, 0.0) for label in PARTS}

    matplotlib.figure.Figure.savefig = by_file  # type: ignore[method-assign]
    result: dict[str, Any] = {}
    for name in names:
        with open(Path(folder) / f"{name}.pkl", "rb") as file:
            data = pickle.load(file)
        best: dict[str, Any] | None = None
        for _ in range(repeats):
            times.clear()
            per_file.clear()
            cpu = time.process_time()
            CASES[name].render(data, Path(out))
            cpu = time.process_time() - cpu
            run = {"cpu": cpu, "parts": dict(times), "files": dict(per_file)}
            if best is None or cpu < best["cpu"]:
                best = run
        result[name] = best
    return result


def _child(args: argparse.Namespace) -> None:
    """The ``_child`` step: ``_render_all`` with its answer as JSON on stdout's last line."""
    result = _render_all(args.data, args.cases.split(","), args.out, args.repeats)
    print(json.dumps(result))


def render(args: argparse.Namespace) -> None:
    """The ``render`` step: each ``--code`` folder's render of every saved case, in fresh
    processes, alternating between the folders, the least CPU of ``--rounds`` rounds."""
    folder = Path(args.data)
    names = (
        args.cases.split(",") if args.cases else sorted(path.stem for path in folder.glob("*.pkl"))
    )
    codes = [str(Path(code).resolve()) for code in args.code]
    print(f"load {_load()}", flush=True)
    runs: dict[str, dict[str, Any]] = {code: {} for code in codes}
    for _ in range(args.rounds):
        for code in codes:
            out = Path(args.out) / Path(code).name
            out.mkdir(parents=True, exist_ok=True)
            env = dict(os.environ, PYTHONPATH=code, NUMBA_NUM_THREADS="1")
            command = [sys.executable, __file__, "_child", "--data", str(folder), "--out",
                       str(out), "--cases", ",".join(names),
                       "--repeats", str(args.repeats)]  # fmt: skip
            answer = subprocess.run(command, env=env, capture_output=True, text=True, cwd=code)
            if answer.returncode != 0:
                raise RuntimeError(f"render with {code} failed:\n{answer.stderr[-3000:]}")
            result = json.loads(answer.stdout.strip().splitlines()[-1])
            for name, run in result.items():
                if name not in runs[code] or run["cpu"] < runs[code][name]["cpu"]:
                    runs[code][name] = run
    print(f"load {_load()}")
    _table(names, codes, runs)
    if len(codes) > 1:
        _pixels([Path(args.out) / Path(code).name for code in codes])


def _pixels(folders: list[Path]) -> None:
    """Each PNG drawn by the first code and by the last compared: its size in pixels and the
    largest difference of a channel (0-255), the pixels that differ, the files' sizes."""
    from matplotlib.image import imread

    first, last = folders[0], folders[-1]
    print(f"\nthe PNGs of {first.name} and {last.name}: largest channel difference (of 255), "
          "pixels that differ, kB")  # fmt: skip
    for path in sorted(first.glob("*.png")):
        other = last / path.name
        if not other.exists():
            print(f"{path.name[:44]:44s} missing in {last.name}")
            continue
        a, b = imread(path), imread(other)
        if a.shape != b.shape:
            print(f"{path.name[:44]:44s} shape {a.shape} -> {b.shape}")
            continue
        difference = np.abs(a.astype(float) - b.astype(float)) * 255
        differ = int((difference.max(axis=-1) > 0.5).sum())
        sizes = f"{path.stat().st_size / 1e3:7.1f} -> {other.stat().st_size / 1e3:7.1f}"
        print(f"{path.name[:44]:44s} {a.shape[1]}x{a.shape[0]} {difference.max():5.0f} "
              f"{differ:8d} px  {sizes}")  # fmt: skip


def _table(names: list[str], codes: list[str], runs: dict[str, dict[str, Any]]) -> None:
    """Print per case and per figure the CPU of each code, largest first, and the parts."""
    last = codes[-1]
    heads = " ".join(f"{Path(code).name[:10]:>10s}" for code in codes)
    print(f"\nper case, render CPU (s), largest first\n{'case':36s} {heads}")
    for name in sorted(names, key=lambda n: -runs[last][n]["cpu"]):
        cells = " ".join(f"{runs[code][name]['cpu']:10.2f}" for code in codes)
        print(f"{name:36s} {cells}")
    total = " ".join(f"{sum(runs[code][n]['cpu'] for n in names):10.2f}" for code in codes)
    print(f"{'all cases':36s} {total}")
    print(f"\nper part, summed over the cases (s; inclusive, they nest)\n{'part':36s} {heads}")
    for label in sorted(PARTS, key=lambda p: -sum(runs[last][n]["parts"].get(p, 0) for n in names)):
        cells = " ".join(
            f"{sum(runs[code][n]['parts'].get(label, 0.0) for n in names):10.2f}" for code in codes
        )
        print(f"{label:36s} {cells}")
    print(
        f"\nper figure file, savefig CPU (s), largest first\n{'file':36s} {heads}  "
        f"parts ({Path(last).name})"
    )
    files = {f: n for n in names for f in runs[last][n]["files"]}
    for file in sorted(files, key=lambda f: -runs[last][files[f]]["files"][f]["savefig"]):
        name = files[file]
        cells = " ".join(
            f"{runs[code][name]['files'].get(file, {}).get('savefig', float('nan')):10.2f}"
            for code in codes
        )
        parts = runs[last][name]["files"][file]
        shown = ", ".join(
            f"{label} {parts[label]:.2f}"
            for label in PARTS
            if label != "savefig" and parts[label] > 0.005
        )
        print(f"{file[:36]:36s} {cells}  {shown}")


# --- imports --------------------------------------------------------------------------------


def imports(args: argparse.Namespace) -> None:
    """The ``imports`` step: each module's import CPU in a fresh process (best of
    ``--rounds``), and the HTML page's rendering."""
    print(f"load {_load()}", flush=True)
    code = str(Path(args.code[0] if args.code else ".").resolve())
    env = dict(os.environ, PYTHONPATH=code, NUMBA_NUM_THREADS="1")
    probe = (
        "import time, importlib, sys; c = time.process_time(); "
        "importlib.import_module(sys.argv[1]); print(time.process_time() - c)"
    )
    base = "import time; print(time.process_time())"
    start = min(float(subprocess.run([sys.executable, "-c", base], env=env, capture_output=True,
                                     text=True).stdout) for _ in range(args.rounds))  # fmt: skip
    rows = []
    for module in IMPORTS:
        best = float("inf")
        for _ in range(args.rounds):
            answer = subprocess.run([sys.executable, "-c", probe, module], env=env,
                                    capture_output=True, text=True, cwd=code)  # fmt: skip
            if answer.returncode == 0:
                best = min(best, float(answer.stdout.strip().splitlines()[-1]))
        rows.append((module, best))
    print(f"\nthe interpreter's start {start:.2f} s CPU; each import alone in a fresh process:")
    for module, best in sorted(rows, key=lambda row: -row[1]):
        print(f"{module:36s} {best:10.2f}")
    if args.results:
        sys.path.insert(0, code)
        from validation.report_html import render_html

        content = json.loads(Path(args.results).read_text())
        best = float("inf")
        for _ in range(max(3, args.rounds)):
            cpu = time.process_time()
            render_html(content)
            best = min(best, time.process_time() - cpu)
        print(f"{'index.html (render_html)':36s} {best:10.3f}")


def main(argv: list[str] | None = None) -> None:
    """The command line."""
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("step", choices=("save", "render", "imports", "_child"))
    parser.add_argument("--resolution", default="default")
    parser.add_argument("--cases", default=None, help="comma-separated case names (default: all)")
    parser.add_argument("--jobs", type=int, default=2)
    parser.add_argument("--out", default="/tmp/report-overhead")
    parser.add_argument("--data", default="/tmp/report-overhead-data")
    parser.add_argument("--code", action="append", default=None, help="a code folder (repeat)")
    parser.add_argument("--rounds", type=int, default=2)
    parser.add_argument("--repeats", type=int, default=1)
    parser.add_argument("--results", default=None, help="a results.json for the HTML page")
    args = parser.parse_args(argv)
    if args.step == "save":
        if args.out == parser.get_default("out"):
            args.out = args.data
        save(args)
    elif args.step == "render":
        args.code = args.code or ["."]
        render(args)
    elif args.step == "imports":
        imports(args)
    else:
        _child(args)


if __name__ == "__main__":
    main()
