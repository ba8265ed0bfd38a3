"""The alternating rows beside the one-ply hemisphere's held centre lines (48 cells and more,
docs/hemisphere_forming.md "Observed orders on finer meshes"): the same run of the case
(``hemisphere_forming.run``, unscaled) on blanks whose grid squares are cut along other
diagonals, the rows' alternation per frame, and a flat patch of the same ply whose weft is
compressed (``compressed_patch``), against the threshold a sliding of the warp fibres has
(``patch_threshold``).

Splits (``SPLITS``): "rectangle" the case's own (``Mesh.rectangle``: every square cut from
(i+1, j) to (i, j+1), so the mesh is not mirror-symmetric about the held planes x = 0, y = 0),
"flipped" every square cut the other way, "radial" each square cut along the diagonal that
points away from the blank's centre and "crosswise" along the other one (both mirror-symmetric
about the two held planes). Run from the project root, one run per command:

    python -m validation.studies.hemisphere_rows_diagonal run radial 48 --out runs/rows
    python -m validation.studies.hemisphere_rows_diagonal rows runs/rows/radial-48.npz
    python -m validation.studies.hemisphere_rows_diagonal patch 20 -0.0045 -0.005

Measured (one thread, nice 5, load 3-5): at 48 cells the rows alternate on all three splits
run (rectangle, flipped, radial: up to 7.2, 5.6, 4.7 deg in an octant at the end, 0.1-2.5 deg
at 40 cells), each in other octants, also on the mirror-symmetric radial mesh and not alike
in octants the mesh maps onto each other: an instability, not the diagonal's bias. They set
in at 84-90 % of the stroke. The flat patch (20 mm, no contact, flat, the bending idle) loses
its uniform state to the same rows past the weft compression ``patch_threshold`` gives:
10 / 20 / 40 cells stable at -0.80 / -0.45 / -0.35 %, rows at -1.10 / -0.50 / -0.40 %
(threshold -0.95 / -0.49 / -0.37 %), the shear law twice as stiff stable at -0.75 % and rows
at -0.90 % (threshold -0.82 %), the same on the three splits. On the hemisphere the shear
law's slope halved brings the rows to 40 cells (up to 4.7-5.5 deg, the warp fibres -1.0, 0,
-0.6 % by turns) and doubled takes them from the rows beside the x axis at 48 cells (0.3-1.0
deg, the shear monotone across the rows; 1.5-3.8 deg beside the y axis), ``run --shear-scale``.

With the fibres' in-plane bending (``run --fibre-bending``, ``patch --fibre-bending``: B_in in
N mm, elements.FibreBending, docs/theory.md §4.7; docs/hemisphere_forming.md "In-plane fibre
bending and the rows"), one thread, nice 5, load 5-13: at 48 cells and B_in = 0.5 the rows'
alternation at the end 1.1 / 0.6 / 0.8 / 1.3 / 0.9 / 0.5 / 0.6 / 1.1 deg per octant (without:
7.2 / 0.6 / 3.3 / 5.2 / 0.6 / 0.1 / 4.1 / 4.3), per-cell rms 1.575 deg (2.710); at 40 cells 0.7 /
1.2 / 1.3 / 0.1 / 0.3 / 1.4 / 1.0 / 0.5 (0.2 / 1.3 / 0.3 / 1.6 / 0.2 / 2.5 / 0.6 / 2.0), 1.624
deg (1.854); at 40 cells and B_in = 2, 1.0 / 1.1 / 1.1 / 0.1 / 0.1 / 0.9 / 1.1 / 0.2, 1.492 deg.
The flat patch's rows need more compression (20 cells: uniform at -0.60 % with
B_in = 0.05, at -0.70 % with 0.5), and its first mode is then at its loaded edges, where the
weft ends free to turn (``edge_rows_deg``), below the inner rows' threshold.
"""

from __future__ import annotations

import json
import os
import sys
from contextlib import contextmanager
from pathlib import Path
from typing import Any

import numpy as np

from femcore import Mesh
from femcore.mesh_generators import grid_quads

__all__ = [
    "OCTANTS",
    "SPLITS",
    "alternation",
    "compressed_patch",
    "grid_measures",
    "patch_threshold",
    "patched_case",
    "split_mesh",
]

SPLITS = ("rectangle", "flipped", "radial", "crosswise")


def split_mesh(lx: float, ly: float, nx: int, ny: int, origin: Any, split: str) -> Mesh:
    """``Mesh.rectangle``'s nodes, numbering and node sets with each grid square (a, b, c, d)
    cut along ``split`` (``SPLITS``): b-d gives (a, b, d), (c, d, b) as ``Mesh.rectangle``;
    a-c gives (b, c, a), (d, a, c), both counter-clockwise with their legs along the fibres."""
    if split not in SPLITS:
        raise ValueError(f"split must be one of {SPLITS}, got {split!r}")
    base = Mesh.rectangle(lx, ly, nx, ny, origin)
    quads = grid_quads(nx, ny)
    centre = base.points[quads].mean(axis=1)
    middle = base.points.mean(axis=0)
    same_sign = (centre[:, 0] - middle[0]) * (centre[:, 1] - middle[1]) > 0.0
    along_ac = {
        "rectangle": np.zeros(len(quads), bool),
        "flipped": np.ones(len(quads), bool),
        "radial": same_sign,  # a-c points along (1, 1), away from the centre where x y > 0
        "crosswise": ~same_sign,
    }[split]
    bd = np.stack((quads[:, [0, 1, 3]], quads[:, [2, 3, 1]]), axis=1)
    ac = np.stack((quads[:, [1, 2, 0]], quads[:, [3, 0, 2]]), axis=1)
    triangles = np.where(along_ac[:, None, None], ac, bd).reshape(-1, 3)
    return Mesh(
        base.points,
        triangles,
        node_sets={name: base.node_sets[name] for name in base.node_sets},
        element_sets={"all": np.arange(len(triangles))},
    )


def scaled_ply(shear_scale: float):
    """The case's ply (``hemisphere_forming.fabric``) with its shear law's slope at zero shear
    times ``shear_scale`` (its locking term kept)."""
    from materials import Fabric, ShearLaw
    from validation.cases import hemisphere_forming as case

    own = case.fabric()
    return Fabric(
        thickness=own.thickness,
        areal_density=own.areal_density,
        tension=own.tension,
        shear=ShearLaw.polynomial(0.2 * shear_scale, 0.0, case.SHEAR_LOCKING_K5),
        bending=own.bending,
    )


@contextmanager
def patched_case(split: str, shear_scale: float = 1.0, fibre_bending: float = 0.0):
    """The case module with its blank cut along ``split``, its shear law's slope at zero
    shear times ``shear_scale`` and, for ``fibre_bending`` > 0, the fibres' in-plane bending
    of that stiffness (N mm, ``elements.fibre_bending.FibreBending``) added to its model,
    for the ``with`` block: the module's ``model``, ``fabric`` and ``Mesh`` are restored on
    leaving it, so that a later run (or another study in the same process) gets the case
    as it is."""
    from validation.cases import hemisphere_forming as case

    saved = {name: getattr(case, name) for name in ("model", "fabric", "Mesh")}
    try:
        if fibre_bending > 0.0:
            from elements.fibre_bending import FibreBending

            plain = case.model

            def bent(*args, **kwargs):
                mesh, built = plain(*args, **kwargs)
                built.interact(FibreBending(fibre_bending))
                return mesh, built

            case.model = bent
        if shear_scale != 1.0:
            ply = scaled_ply(shear_scale)
            case.fabric = lambda: ply

        class Split(Mesh):
            @classmethod
            def rectangle(cls, lx, ly, nx, ny, origin=(0.0, 0.0, 0.0)):
                return split_mesh(lx, ly, nx, ny, origin, split)

        case.Mesh = Split  # type: ignore[misc]
        yield case
    finally:
        for name, value in saved.items():
            setattr(case, name, value)


def run(
    split: str, cells: int, out: Path, shear_scale: float = 1.0, fibre_bending: float = 0.0
) -> dict[str, Any]:
    """One unscaled run (the shear law's slope times ``shear_scale``, the fibres' in-plane
    bending ``fibre_bending`` N mm, none at 0); its frames' positions and cell fields in
    ``out`` (.npz) and its record beside it (.json)."""
    with patched_case(split, shear_scale, fibre_bending) as case:
        record = case.run(cells, "fibrous")
        net_shear = case.net_shear_at(record["mesh"])
    result, mesh = record["result"], record["mesh"]
    frames = result.frames
    tri = [f.fields["triangle"] for f in frames]
    np.savez_compressed(
        out,
        points=mesh.points,
        triangles=mesh.triangles,
        times=np.array([f.time for f in frames]),
        positions=np.array([f.positions for f in frames]),
        warp_strain=np.array([t["warp_strain"].mean(axis=1) for t in tri]),
        weft_strain=np.array([t["weft_strain"].mean(axis=1) for t in tri]),
        shear_deg=np.array([t["shear_angle_deg"].mean(axis=1) for t in tri]),
        warp_curvature=np.array([t["warp_curvature"] for t in tri]),
        weft_curvature=np.array([t["weft_curvature"] for t in tri]),
        tool_forces=np.array([f.tool_forces for f in frames]),
        net_shear=net_shear,
    )
    keys = ["rms_deg", "draw_in_mm", "edge_draw_in_mm", "late_punch_force_N"]
    keys += ["largest_kinetic_over_work", "holder_lift_mm", "end_time_s"]
    summary = {k: record[k] for k in keys}
    summary.update(
        split=split,
        cells=cells,
        shear_scale=shear_scale,
        fibre_bending=fibre_bending,
        steps=int(result.steps),
        cost=record["cost"],
    )
    out.with_suffix(".json").write_text(json.dumps(summary, indent=1))
    return summary


def grid_measures(data: Any, frame: int) -> dict[str, np.ndarray]:
    """The blank's fibre segments at one frame on the grid (j, i) of node (i, j): ``warp``
    (n+1, n) and ``weft`` (n, n+1) strains (chord over reference length - 1), ``gap`` (n+1,
    n+1) the nodes' distance from the die's bowl's sphere of the mid-surface (mm; 0 on the
    die, -0.3 on the punch), and ``off`` (n, n) the squares' shear (deg, the two triangles'
    mean; ``hemisphere_forming.blank_shear``)."""
    from elements.layup import ply_shear
    from validation.cases import hemisphere_forming as case

    points, triangles = data["points"], data["triangles"]
    n = int(round(np.sqrt(len(points)))) - 1
    h = (points[:, 0].max() - points[:, 0].min()) / n
    x = data["positions"][frame][: len(points)]
    grid = x.reshape(n + 1, n + 1, 3)
    shear = ply_shear(points, x, triangles, np.array([1.0, 0.0, 0.0]))
    centre = points[triangles].mean(axis=1)
    i = np.floor((centre[:, 0] - points[:, 0].min()) / h).astype(int)
    j = np.floor((centre[:, 1] - points[:, 1].min()) / h).astype(int)
    squares = np.zeros((n, n))
    np.add.at(squares, (j, i), 0.5 * np.degrees(shear))
    return {
        "warp": np.linalg.norm(grid[:, 1:] - grid[:, :-1], axis=2) / h - 1.0,
        "weft": np.linalg.norm(grid[1:] - grid[:-1], axis=2) / h - 1.0,
        "gap": np.linalg.norm(grid, axis=2) - (case.DIE - 0.5 * case.THICKNESS),
        "off": squares,
    }


#: The octants beside the held centre lines: (rows beside the x axis (y = 0) or the y axis,
#: the side of the line, the sign of the coordinate along it)
OCTANTS = [(line, side, along) for line in "xy" for side in (1, -1) for along in (1, -1)]


def alternation(
    squares: np.ndarray, lo: float = 30.0, hi: float = 62.0, half: float = 100.0
) -> dict[str, float]:
    """Per octant (``OCTANTS``): the rms (deg) over the squares whose centre lies lo-hi mm
    along the held line of the alternating part of the first four rows' shear,
    (s_0 - 3 s_1 + 3 s_2 - s_3) / 8 (a row-by-row pattern of amplitude a gives a; a field
    quadratic across the rows, the net's near the line, none)."""
    n = len(squares)
    h = 2.0 * half / n
    centres = -half + (np.arange(n) + 0.5) * h
    out = {}
    for line, side, along in OCTANTS:
        m = squares if line == "x" else squares.T  # m[across, along]
        idx = [n // 2 + r if side > 0 else n // 2 - 1 - r for r in range(4)]
        alt = (m[idx[0]] - 3.0 * m[idx[1]] + 3.0 * m[idx[2]] - m[idx[3]]) / 8.0
        chosen = (np.abs(centres) >= lo) & (np.abs(centres) <= hi) & (np.sign(centres) == along)
        name = (
            f"{line} axis, {'+-'[side < 0]}{'y' if line == 'x' else 'x'}, {'+-'[along < 0]}{line}"
        )
        out[name] = float(np.sqrt(np.mean(alt[chosen] ** 2)))
    return out


def patch_threshold(
    cells: int, side: float, shear_scale: float = 1.0, fibre_bending: float = 0.0
) -> float:
    """The weft strain (compression, > 0) past which the flat patch of ``compressed_patch``
    loses its uniform state to rows shearing alternately: the warp fibres sliding by
    u = A (-1)^k sin(pi x / 2 side) (k the row, the edge x = 0 held, x = side free) turn the
    weft segments by 2 A / h, which costs the shear law's tangent G (0.2 shear_scale N/mm at
    zero shear) and frees the compressed weft's T2 = TENSION eps2, and stretch the warp by
    A pi / 2 side (TENSION): unstable where -eps2 > G / TENSION + (pi h / 4 side)^2, h =
    side / cells. The first term is the continuum's (no wavelength of its own: the mesh's
    shortest, two rows, is the first to go), the second the mesh's.

    With the fibres' in-plane bending B_in = ``fibre_bending`` (N mm, docs/theory.md §4.7)
    the rows of a wave q across them (u = A cos(q y) sin(pi x / 2 side)) turn the weft by
    d = 2 sin(q h / 2) / h times A between the rows and bend it by d^2 A: unstable where
    T2 - G > B_in d^2 + TENSION (pi / 2 side)^2 / d^2 for some d <= 2 / h. Its least is
    pi sqrt(TENSION B_in) / side at d^2 = sqrt(TENSION / B_in) pi / (2 side), a wave of the
    fabric's own (2 pi / q), when that d is within the mesh's reach; else the mesh's
    shortest wave, 4 B_in / h^2 + TENSION (pi h / 4 side)^2."""
    from validation.cases import hemisphere_forming as case

    h = side / cells
    shear = 0.2 * shear_scale / case.TENSION
    if fibre_bending <= 0.0:
        return shear + (np.pi * h / (4.0 * side)) ** 2
    best_d2 = np.sqrt(case.TENSION / fibre_bending) * np.pi / (2.0 * side)
    d2 = min(best_d2, 4.0 / h**2)
    bend = fibre_bending * d2 + case.TENSION * (np.pi / (2.0 * side)) ** 2 / d2
    return float(shear + bend / case.TENSION)


def compressed_patch(
    weft_strain: float,
    cells: int = 20,
    side: float = 20.0,
    shear_scale: float = 1.0,
    split: str = "rectangle",
    fibre_bending: float = 0.0,
) -> dict[str, float]:
    """A flat square patch of the case's ply (``hemisphere_forming.fabric``, its shear law's
    slope times ``shear_scale``), ``side`` mm, ``cells`` a side cut along ``split``, held flat
    (uz = 0 everywhere), its bottom edge at uy = 0 and left edge at ux = 0, its top edge moved
    by ``weft_strain`` x side along y (compression < 0) over 5 ms (explicit, damping 2000/s),
    thirty nodes pushed along x by 1e-5 N to break the symmetry, with the fibres' in-plane
    bending ``fibre_bending`` (N mm; none at 0): the largest alternation of
    the rows' shear (deg; half the mean |s_j - s_j+1| of neighbouring rows of squares over
    the right half), the same over the rows a quarter of the side or more from the top and
    bottom edges (``inner_alternation_deg``), the largest |shear| of the three rows beside
    either edge (``edge_rows_deg``: with the in-plane bending the weft's free ends there buckle
    first, a mode of the edge that decays inward over the fabric's own wavelength), the rms
    shear (deg) and the weft's mean strain at the end."""
    from elements import FibrousShell
    from elements.layup import ply_shear
    from femcore import Model
    from solvers import CentralDifference

    mesh = split_mesh(side, side, cells, cells, (0.0, 0.0, 0.0), split)
    ply = scaled_ply(shear_scale)
    built = Model(mesh)
    built.add(FibrousShell(ply))
    built.fix(lambda x, y, z: np.ones_like(x, bool), ["uz"])
    built.fix("bottom", ["uy"])
    built.fix("left", ["ux"])
    built.displace("top", uy=weft_strain * side, amplitude="smooth")
    if fibre_bending > 0.0:
        from elements.fibre_bending import FibreBending

        built.interact(FibreBending(fibre_bending))
    rng = np.random.default_rng(1)
    for node in rng.choice(mesh.n_nodes, 30, replace=False):
        built.force(np.array([node]), (1e-5 * rng.normal(), 0.0, 0.0))
    result = CentralDifference(duration=5e-3, damping=2000.0, progress=False).solve(built)
    x = result.positions[: mesh.n_nodes]
    shear = np.degrees(ply_shear(mesh.points, x, mesh.triangles, np.array([1.0, 0.0, 0.0])))
    squares = shear.reshape(cells, cells, 2).mean(axis=2)  # [j, i]: split_mesh's order
    right = squares[:, cells // 2 :]
    grid = x.reshape(cells + 1, cells + 1, 3)
    weft = np.linalg.norm(grid[1:] - grid[:-1], axis=2) / (side / cells) - 1.0
    inner = right[cells // 4 : cells - cells // 4]  # a quarter of the side from either edge
    return {
        "alternation_deg": float(0.5 * np.abs(right[1:] - right[:-1]).mean(axis=1).max()),
        "inner_alternation_deg": float(0.5 * np.abs(inner[1:] - inner[:-1]).mean(axis=1).max()),
        "edge_rows_deg": float(np.abs(np.r_[right[:3], right[-3:]]).max()),
        "rms_shear_deg": float(np.sqrt(np.mean(shear**2))),
        "weft_strain": float(weft.mean()),
    }


def _main(argv: list[str]) -> None:
    import argparse

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    verbs = parser.add_subparsers(dest="verb", required=True)
    one = verbs.add_parser("run")
    one.add_argument("split", choices=SPLITS)
    one.add_argument("cells", type=int)
    one.add_argument("--out", type=Path, required=True)
    one.add_argument("--shear-scale", type=float, default=1.0)
    one.add_argument("--fibre-bending", type=float, default=0.0, help="B_in, N mm")
    patch = verbs.add_parser("patch", help="the flat patch's rows under weft compression")
    patch.add_argument("cells", type=int)
    patch.add_argument("strains", type=float, nargs="+", help="weft strains (< 0)")
    patch.add_argument("--shear-scale", type=float, default=1.0)
    patch.add_argument("--split", choices=SPLITS, default="rectangle")
    patch.add_argument("--fibre-bending", type=float, default=0.0, help="B_in, N mm")
    rows = verbs.add_parser("rows", help="per frame: the pattern's amplitude and the strains")
    rows.add_argument("npz", type=Path, nargs="+")
    arguments = parser.parse_args(argv)
    if arguments.verb == "run":
        arguments.out.mkdir(parents=True, exist_ok=True)
        scaled = "" if arguments.shear_scale == 1.0 else f"-shear{arguments.shear_scale:g}"
        if arguments.fibre_bending > 0.0:
            scaled += f"-bent{arguments.fibre_bending:g}"
        path = arguments.out / f"{arguments.split}-{arguments.cells}{scaled}.npz"
        record = run(
            arguments.split, arguments.cells, path, arguments.shear_scale, arguments.fibre_bending
        )
        print(json.dumps(record), os.getloadavg()[0])
        return
    if arguments.verb == "patch":
        bending = arguments.fibre_bending
        limit = patch_threshold(arguments.cells, 20.0, arguments.shear_scale, bending)
        print(
            f"{arguments.cells} cells, shear x {arguments.shear_scale}, {arguments.split}, "
            f"in-plane bending {bending:g} N mm: "
            f"unstable past a weft strain of {-100 * limit:.3f} %"
        )
        for strain in arguments.strains:
            got = compressed_patch(strain, arguments.cells, 20.0, arguments.shear_scale,
                                   arguments.split, bending)  # fmt: skip
            print(
                f"  weft {100 * strain:+.3f} %: rows alternate {got['alternation_deg']:.2f} "
                f"deg ({got['inner_alternation_deg']:.2f} away from the edges, the edge rows "
                f"up to {got['edge_rows_deg']:.2f}), rms shear {got['rms_shear_deg']:.3f} "
                f"deg, mean weft {100 * got['weft_strain']:+.3f} %"
            )
        return
    from femcore.loads import smooth_step

    for npz in arguments.npz:
        data = np.load(npz)
        n = int(round(np.sqrt(len(data["points"])))) - 1
        h = 200.0 / n
        middle = n // 2
        # columns (nodes) 40-62 mm from the centre along +x and -x, rows 0-3 beside y = 0
        xs = -100.0 + h * np.arange(n + 1)
        near = np.flatnonzero((np.abs(xs) >= 40.0) & (np.abs(xs) <= 62.0))
        print(
            f"{npz}: alternation (deg) per octant, rows 0-3, 30-62 mm along the line; "
            "beside y = 0: the weft's mean strain 50-62 mm and its least column mean 20-66 "
            "mm (%), 40-62 mm: the warp's of the four fibres y = -h, 0, h, 2h (%), the nodes "
            "on the die / the punch"
        )
        for frame, time in enumerate(data["times"]):
            g = grid_measures(data, frame)
            alt = alternation(g["off"])
            rim = near[np.abs(xs[near]) >= 50.0]
            weft = g["weft"][middle - 4 : middle + 4][:, rim].mean()
            band = np.flatnonzero((np.abs(xs) >= 20.0) & (np.abs(xs) <= 66.0))
            columns = g["weft"][middle - 4 : middle + 4][:, band].mean(axis=0)
            least = int(np.argmin(columns))
            warp = [g["warp"][middle + k][near[:-1]].mean() for k in (-1, 0, 1, 2)]
            gap = g["gap"][middle - 4 : middle + 5][:, near]
            stroke = smooth_step(time / 0.3)
            print(
                f"  t {time:.3f} s stroke {stroke:.2f}: alt "
                + " ".join(f"{v:4.1f}" for v in alt.values())
                + f" | weft {100 * weft:+.2f}, least {100 * columns[least]:+.2f} at x "
                + f"{xs[band][least]:+.0f} | warp "
                + " ".join(f"{100 * w:+.2f}" for w in warp)
                + f" | on die {int((gap > -0.1).sum())} punch {int((gap < -0.2).sum())}"
            )


if __name__ == "__main__":
    _main(sys.argv[1:])
