"""Peer comparison of MindlinShell with CalculiX on a cantilever strip under a tip load.

The same strip (clamped at x = 0, a vertical load P shared by the tip nodes) is written as a
CalculiX deck with S4 shells (expanded by ccx to C3D8I bricks with incompatible modes, good in
bending; its S3 triangles lock and are avoided) and solved linearly and with NLGEOM; the tip
deflection is read from the .dat file and set against MindlinShell solved with
``solvers.Static`` on the same grid split into triangles.

Run ``python -m validation.calculix``; without ``ccx`` on the PATH (Debian package
``calculix-ccx``) it says so and prints the MindlinShell side only.
"""

from __future__ import annotations

import argparse
import shutil
import subprocess
import tempfile
from dataclasses import dataclass
from pathlib import Path

import numpy as np

__all__ = ["Strip", "calculix_deck", "mindlin_tip", "parse_tip_displacement", "run_calculix"]


@dataclass(frozen=True)
class Strip:
    """Cantilever strip: length, width, thickness (mm), E (MPa), nu, cells along x and y."""

    length: float = 100.0
    width: float = 10.0
    thickness: float = 1.0
    young: float = 1e5
    poisson: float = 0.0
    nx: int = 20
    ny: int = 2

    @property
    def bending_stiffness(self) -> float:
        """E b h^3 / 12, N mm^2 (beam bending stiffness of the whole width)."""
        return self.young * self.width * self.thickness**3 / 12.0


def _grid(strip: Strip):
    x = np.linspace(0.0, strip.length, strip.nx + 1)
    y = np.linspace(0.0, strip.width, strip.ny + 1)
    xx, yy = np.meshgrid(x, y)
    return np.column_stack([xx.ravel(), yy.ravel(), np.zeros(xx.size)])


def calculix_deck(strip: Strip, load: float, nonlinear: bool) -> str:
    """The CalculiX input deck (text) of the strip under a total tip load ``load`` (N, -z)."""
    points = _grid(strip)
    nx, ny = strip.nx, strip.ny
    lines = ["*HEADING", "cantilever strip, MindlinShell peer comparison", "*NODE, NSET=NALL"]
    lines += [f"{i + 1}, {p[0]:.10g}, {p[1]:.10g}, {p[2]:.10g}" for i, p in enumerate(points)]
    lines.append("*ELEMENT, TYPE=S4, ELSET=EALL")
    element = 1
    for j in range(ny):
        for i in range(nx):
            a = j * (nx + 1) + i + 1
            lines.append(f"{element}, {a}, {a + 1}, {a + nx + 2}, {a + nx + 1}")
            element += 1
    clamp = [j * (nx + 1) + 1 for j in range(ny + 1)]
    tip = [j * (nx + 1) + nx + 1 for j in range(ny + 1)]
    lines += ["*NSET, NSET=CLAMP", ", ".join(map(str, clamp))]
    lines += ["*NSET, NSET=TIP", ", ".join(map(str, tip))]
    lines += [
        "*MATERIAL, NAME=ELASTIC",
        "*ELASTIC",
        f"{strip.young:.10g}, {strip.poisson:.10g}",
        "*SHELL SECTION, ELSET=EALL, MATERIAL=ELASTIC",
        f"{strip.thickness:.10g}",
        "*BOUNDARY",
        "CLAMP, 1, 6",
        "*STEP, NLGEOM, INC=200" if nonlinear else "*STEP",
        "*STATIC",
        "0.05, 1.0" if nonlinear else "",
        "*CLOAD",
    ]
    share = load / len(tip)
    # Trapezoidal share along the tip edge, as the consistent load of a line load.
    weights = np.full(len(tip), 1.0)
    weights[0] = weights[-1] = 0.5
    weights = weights / weights.sum() * len(tip)
    lines += [f"{node}, 3, {-share * w:.10g}" for node, w in zip(tip, weights)]
    lines += ["*NODE PRINT, NSET=TIP", "U", "*END STEP"]
    return "\n".join(line for line in lines if line != "") + "\n"


def parse_tip_displacement(dat_text: str) -> np.ndarray:
    """Mean (ux, uy, uz) of the last 'displacements' block of a CalculiX .dat file."""
    blocks, current = [], None
    for line in dat_text.splitlines():
        if "displacements" in line:
            current = []
            blocks.append(current)
            continue
        parts = line.split()
        if current is not None and len(parts) == 4:
            try:
                current.append([float(v) for v in parts[1:]])
            except ValueError:
                current = None
    filled = [b for b in blocks if b]
    if not filled:
        raise ValueError("no displacement block found in the CalculiX .dat output")
    return np.mean(np.array(filled[-1]), axis=0)


def run_calculix(strip: Strip, load: float, nonlinear: bool) -> np.ndarray | None:
    """Tip displacement from ccx, or None when ccx is not installed."""
    ccx = shutil.which("ccx")
    if ccx is None:
        return None
    with tempfile.TemporaryDirectory() as folder:
        deck = Path(folder) / "strip.inp"
        deck.write_text(calculix_deck(strip, load, nonlinear))
        subprocess.run(
            [ccx, "-i", "strip"], cwd=folder, check=True, capture_output=True, timeout=600
        )
        return parse_tip_displacement((Path(folder) / "strip.dat").read_text())


def mindlin_tip(strip: Strip, load: float, nonlinear: bool) -> np.ndarray:
    """Tip displacement of MindlinShell (Static) on the same grid split into triangles; the
    linear case is solved at 1e-4 of the load and scaled back."""
    from elements import MindlinShell
    from femcore import Mesh, Model
    from materials import ElasticShell
    from solvers import Static

    mesh = Mesh.rectangle(strip.length, strip.width, nx=strip.nx, ny=strip.ny)
    model = Model(mesh)
    model.add(MindlinShell(ElasticShell(strip.young, strip.poisson, strip.thickness, 1e-9)))
    model.fix("left")
    tip = mesh.nodes("right")
    scale = 1.0 if nonlinear else 1e-4
    weights = np.full(len(tip), 1.0)
    weights[0] = weights[-1] = 0.5
    weights = weights / weights.sum()
    for node, w in zip(tip, weights):
        model.force([node], (0.0, 0.0, -scale * load * w))
    result = Static(increments=5 if nonlinear else 1).solve(model)
    return result.displacements[tip].mean(axis=0) / scale


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument(
        "--load-parameter",
        type=float,
        default=3.0,
        help="P L^2 / EI of the nonlinear case (default 3)",
    )
    args = parser.parse_args(argv)
    strip = Strip()
    load = args.load_parameter * strip.bending_stiffness / strip.length**2
    have_ccx = shutil.which("ccx") is not None
    if not have_ccx:
        print(
            "CalculiX (ccx) is not installed: apt-get install calculix-ccx to compare; "
            "showing MindlinShell only."
        )
    print(
        f"strip {strip.length} x {strip.width} x {strip.thickness} mm, E = {strip.young:g}, "
        f"nu = {strip.poisson}, {strip.nx} x {strip.ny} cells; P L^2/EI = "
        f"{args.load_parameter:g}"
    )
    for nonlinear in (False, True):
        ours = mindlin_tip(strip, load, nonlinear)
        theirs = run_calculix(strip, load, nonlinear)
        label = "nonlinear" if nonlinear else "linear"
        line = f"{label:>9}: MindlinShell tip (ux, uz) = ({ours[0]:.4f}, {ours[2]:.4f}) mm"
        if theirs is not None:
            error = (ours[2] - theirs[2]) / abs(theirs[2])
            line += (
                f"; CalculiX S4 ({theirs[0]:.4f}, {theirs[2]:.4f}) mm; "
                f"difference in uz {100 * error:+.2f}%"
            )
        print(line)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
