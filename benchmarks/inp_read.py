"""Reading an Abaqus deck: ``Mesh.read`` (the deck's lines and its *INCLUDE files through
femcore/inp_include.py, its sets by femcore/inp_sets.py, meshio for the nodes and elements)
beside meshio's own reading of the same text (``meshio.read``, no sets of our rules, no
checks): a structured ``--n`` x ``--n`` mesh of S4R quadrilaterals with a GENERATE node set,
written once as one file and once as a main deck including the mesh file.

Printed: the seconds of each reading (best of ``--repeats``), their ratio, and /proc/loadavg
(what else the machine runs counts: this is a shared machine).

Run from the project root:

    python benchmarks/inp_read.py
    python benchmarks/inp_read.py --n 400 --repeats 5
"""

from __future__ import annotations

import argparse
import sys
import tempfile
import time
import warnings
from pathlib import Path

import meshio

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from femcore import Mesh  # noqa: E402


def deck_text(n: int) -> str:
    """An n x n S4R mesh of unit squares with the node set of its x = 0 edge."""
    lines = ["*NODE"]
    lines += [
        f"{j * (n + 1) + i + 1}, {float(i)}, {float(j)}, 0.0"
        for j in range(n + 1)
        for i in range(n + 1)
    ]
    lines.append("*ELEMENT, TYPE=S4R, ELSET=ALL")
    label = 1
    for j in range(n):
        for i in range(n):
            a = j * (n + 1) + i + 1
            lines.append(f"{label}, {a}, {a + 1}, {a + n + 2}, {a + n + 1}")
            label += 1
    lines.append(f"*NSET, NSET=LEFT, GENERATE\n1, {n * (n + 1) + 1}, {n + 1}")
    return "\n".join(lines) + "\n"


def best(read, repeats: int) -> float:
    times = []
    for _ in range(repeats):
        started = time.perf_counter()
        read()
        times.append(time.perf_counter() - started)
    return min(times)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--n", type=int, default=300, help="cells along each side")
    parser.add_argument("--repeats", type=int, default=3)
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as folder:
        mesh_file = Path(folder) / "mesh.inp"
        mesh_file.write_text(deck_text(args.n))
        main_deck = Path(folder) / "main.inp"
        main_deck.write_text("*HEADING\n*INCLUDE, INPUT=mesh.inp\n")
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            ours = best(lambda: Mesh.read(mesh_file), args.repeats)
            ours_included = best(lambda: Mesh.read(main_deck), args.repeats)
        reference = best(lambda: meshio.read(mesh_file), args.repeats)
        cells = Mesh.read(main_deck).n_triangles
    print(f"{args.n} x {args.n} S4R deck ({cells} triangles once split), best of {args.repeats}:")
    print(f"  Mesh.read, one file        {ours:7.3f} s  ({ours / reference:.2f} x meshio's)")
    print(f"  Mesh.read, *INCLUDE        {ours_included:7.3f} s  "
          f"({ours_included / reference:.2f} x meshio's)")  # fmt: skip
    print(f"  meshio.read, one file      {reference:7.3f} s  (the reference pass)")
    print(f"  load average: {Path('/proc/loadavg').read_text().strip()}")


if __name__ == "__main__":
    main()
