"""The one-ply hemisphere's results on finer meshes and their observed order
(validation/cases/hemisphere_forming.py ``run``, unscaled as the fine resolution).

Each run is the case's own (``run(cells, kinematics)``, the stroke in DURATION, no mass
scaling); its record holds the draw-in of the edge middle, averaged along the edges and of the
corners (mm), the punch force at the end and averaged over the last fifth of its travel (N),
the rms of shear - net over the compared cells (deg), the largest KE / W after the first tenth
and at the end, the steps, the CPU time and the load, and the centre line's state at the die's
round (``centre_line_state``): whether the edge middle's fibre lies on the round (taut) or
stands off it, cornered under the holder's plane. Each run writes its record as it ends
(``<out>/<kinematics>-<cells>.json``), so a stop keeps the runs done.

The observed order p and the Richardson value f0 of each quantity over the finest three
meshes (``validation.checks.observed_order``, h = 200 mm / cells), the orders of every
consecutive three (``validation.studies.grid_convergence.consecutive_orders``: they agree in
the asymptotic range) and Roache's grid convergence index of the finest: ``orders``. Run from
the project root, one run at a time, each as a command:

    python -m validation.studies.hemisphere_forming_order run fibrous 56 --out runs/order
    python -m validation.studies.hemisphere_forming_order orders runs/order

A variant of the case (``run --friction MU --fibre-bending B_IN``; one folder per variant,
``orders`` refuses records of different ones): Coulomb friction on the die and the holder,
the fibres' in-plane bending (elements.FibreBending; docs/hemisphere_forming.md "Friction on
the die and the holder: an observed order"). The figures below are the case's own
(frictionless, no in-plane bending).

Measured (docs/hemisphere_forming.md, "Observed orders on finer meshes"; fibrous, one thread,
nice 10, load 7-15): 14 / 20 / 28 / 40 / 56 cells, 19346 / 27677 / 38781 / 55443 / 77703 steps,
12 / 27 / 64 / 169 / 412 s of CPU, every run to the end, the holder down, KE / W at most
0.019. The edge middle's draw-in 23.41 / 28.65 / 27.96 / 29.13 / 26.76 mm, its fibre on the
die's round at 14 cells (0.00 mm over it), cornered under the holder at 20 to 40 (3.0-3.3 mm)
and part way at 56 (2.2 mm): a change of regime, no order. The edges' mean draw-in 12.15 /
13.19 / 13.10 / 13.60 / 13.75 mm (p = 3.30 on 28 / 40 / 56, f0 13.82, GCI 0.09 mm; none on
the other triples; least squares p = 1.88, f0 13.79), the corners' 5.54 / 7.39 / 7.09 / 8.45
/ 8.75 mm (p = 4.22, f0 8.84; none on the others), the punch force over the last fifth 43.25 /
48.39 / 53.27 / 54.85 / 54.07 N (no order on the finest three; least squares p = 1.93, f0
55.8), at the end 74.4 / 55.1 / 83.1 / 76.5 / 91.7 N (none), the per-cell rms of shear - net
2.439 / 2.162 / 1.527 / 1.854 / 2.888 deg (none). The shear field at fixed material points
within 60 deg of the pole: 0.62-0.82 deg from the net on every mesh, its change to the next
mesh 0.88 / 0.54 / 0.57 / 0.68 deg; 15 mm off the symmetry planes 0.72 / 0.53 / 0.33 / 0.44
deg (orders 0.72 and 1.57, then growing): at 56 cells the rows beside the held centre lines
shear alternately, row by row (up to +-10 deg off the net), a pattern of the mesh's width.
A 48-cell run (240 s of CPU) has the alternating rows too, the late force 54.45 N, the edges'
mean 13.62 mm. The Mindlin shell on 14 / 20 / 28 / 40 cells shows no order either (its rms
2.649 / 2.093 / 2.128 / 4.159 deg, its draw-ins' steps growing). So no quantity is in its
asymptotic range on these meshes; the orders the finest three give (3.3, 4.2) are above any
the discretisation has and the overlapping triples do not confirm them.
"""

from __future__ import annotations

import json
import math
import os
import sys
from pathlib import Path
from typing import Any

import numpy as np

from validation.checks import observed_order
from validation.studies.grid_convergence import (
    consecutive_orders,
    grid_convergence_index,
    power_fit,
)

__all__ = [
    "POLAR_DEG",
    "QUANTITIES",
    "SPACING",
    "centre_line_state",
    "field_orders",
    "measure",
    "orders",
    "read_records",
    "shear_field",
    "variant",
]

#: The quantities whose order is observed: the ``run`` record's key -> its label.
QUANTITIES = {
    "draw_in_mm": "draw-in of the edge middle (mm)",
    "edge_draw_in_mm": "draw-in averaged along the edges (mm)",
    "corner_draw_in_mm": "draw-in of the corners (mm)",
    "punch_force_N": "punch force at the end (N)",
    "late_punch_force_N": "punch force over the last fifth of the travel (N)",
    "rms_deg": "rms of shear - net in the die (deg)",
    "largest_kinetic_over_work": "largest KE / W after the first tenth",
}
#: mm: the material grid's spacing for the shear field, finer than the finest cell
SPACING = 2.0
#: deg: the field is compared within these polar angles of the pole on the net (the last the
#: case's COMPARED_POLAR, 71.1 deg: its cells' rms region; the die's round starts at 80 deg)
POLAR_DEG = (45.0, 60.0, 71.1)
#: mm: the regions again without the material points this near a symmetry plane (x = 0 or
#: y = 0): the rows of cells beside the held centre lines shear differently from mesh to
#: mesh (a band one cell wide at 20 and 40 cells, none at 28, rows alternating in sign at 48
#: and 56; docs/hemisphere_forming.md, "Observed orders on finer meshes"); 15 mm is one cell
#: of the coarsest mesh run (14 cells)
BAND_MM = 15.0


def shear_field(cells: int, positions: np.ndarray) -> np.ndarray:
    """(p,) the shear angle (rad) of the case's blank of ``cells`` cells a side at the points
    of one material grid (``material_grid(HALF, SPACING)``, whatever the mesh): each cell's
    shear (``hemisphere_forming.blank_shear``) averaged to the nodes by area and interpolated
    linearly in the flat blank (validation/studies/hemisphere_plies_fields.py: the value at a
    material point does not depend on which cell it falls in).

    Parameters
    ----------
    cells : int
        The blank's cells a side.
    positions : numpy.ndarray, shape (n, 3) or more rows
        The blank's nodes' positions at the end, mm (rows past n ignored).
    """
    from validation.cases import hemisphere_forming as case
    from validation.studies.hemisphere_plies_fields import field_at, material_grid, nodal_average

    mesh = case.model(cells, "fibrous", holder_force=0.0)[0]
    shear = case.blank_shear(mesh, positions[: mesh.n_nodes])
    nodal = nodal_average(mesh.points, mesh.triangles, shear)
    return field_at(mesh.points, mesh.triangles, nodal, material_grid(case.HALF, SPACING))


def field_orders(cells: list[int], fields: list[np.ndarray]) -> dict[str, dict[str, Any]]:
    """Per region (the material points within each ``POLAR_DEG`` of the pole on the net, and
    the same at least ``BAND_MM`` from both symmetry planes): the rms (deg) of each mesh's
    ``fields`` (``shear_field``, coarsest first, at ``cells``) less the net's shear
    (``against net``) with the orders of each consecutive three, and the rms of each field's
    change to the next finer mesh (``changes``) with the orders they give (``change_orders``:
    a discretisation order with no model error in it)."""
    from validation.cases import hemisphere_forming as case
    from validation.studies.grid_convergence import change_orders
    from validation.studies.hemisphere_plies_fields import material_grid, net_on_sphere

    grid = material_grid(case.HALF, SPACING)
    net = net_on_sphere(case.DIE - 0.5 * case.THICKNESS, case.NET_CELL, 0.0, grid)
    sizes = [200.0 / n for n in cells]
    out = {}
    off_planes = np.minimum(np.abs(grid[:, 0]), np.abs(grid[:, 1])) >= BAND_MM
    regions = [
        (f"within {limit:g} deg", net["polar"] <= math.radians(limit)) for limit in POLAR_DEG
    ]
    regions += [(f"{name}, {BAND_MM:g} mm off the planes", r & off_planes) for name, r in regions]
    for name, inside in regions:

        def rms(a: np.ndarray, b: np.ndarray) -> float:
            return float(np.degrees(np.sqrt(np.mean((a - b)[inside] ** 2))))  # noqa: B023

        against = [rms(f, net["shear"]) for f in fields]
        changes = [rms(a, b) for a, b in zip(fields[:-1], fields[1:])]
        out[name] = {
            "points": int(inside.sum()),
            "against net": against,
            "against net orders": consecutive_orders(sizes, against).tolist()
            if len(cells) > 2
            else [],
            "changes": changes,
            "change orders": change_orders(sizes, changes) if len(cells) > 2 else [],
        }
    return out


def centre_line_state(points: np.ndarray, positions: np.ndarray) -> dict[str, float]:
    """Where the edge middle's fibre (the centre line y = 0, x > 0) passes the die's round: its
    largest height above the die's surface over the round (mm; about 0 where it lies on the
    round, taut, some mm where it is cornered under the holder's plane over the die's
    opening), the flange's start (mm), and the fibre's mean strain from the pole to the
    flange's start (``strain_to_flange``: its chords over their flat lengths, less 1, over
    the segments whose outer node lies inside that radius; > 0 where the fibre is pulled
    taut, < 0 where it is pushed in and corners).

    Parameters
    ----------
    points : numpy.ndarray, shape (n, 3)
        The flat blank's nodes, mm.
    positions : numpy.ndarray, shape (n, 3) or more rows
        Their positions at the end, mm (rows past n ignored).
    """
    from validation.cases import hemisphere_forming as case
    from validation.references import centre_line_draw_in as draw_in

    line = np.flatnonzero(np.isclose(points[:, 1], 0.0) & (points[:, 0] >= 0.0))
    line = line[np.argsort(points[line, 0])]
    x = positions[line]
    radius = np.hypot(x[:, 0], x[:, 1])
    start = draw_in.flange_start(case.DIE, case.DIE_RIM)
    # The round's centre in the (r, z) plane (mm): the rim's radius below the flange's face
    # (z = 0) at the flange's start (validation.specimens.hemisphere_die); the blank's
    # mid-surface lies half a ply off the round.
    mid = 0.5 * case.THICKNESS
    centre_r, centre_z = start, -case.DIE_RIM
    on_round = (radius > start * case.DIE / (case.DIE + case.DIE_RIM)) & (radius < start)
    distance = np.hypot(radius - centre_r, x[:, 2] - centre_z)
    height = distance - (case.DIE_RIM + mid)
    chords = np.linalg.norm(np.diff(x, axis=0), axis=1)
    inside = radius[1:] <= start
    flat = np.diff(points[line, 0])[inside].sum()
    return {
        "height_over_round_mm": float(height[on_round].max(initial=0.0)),
        "flange_start_mm": float(start),
        "strain_to_flange": float(chords[inside].sum() / flat - 1.0) if flat > 0 else math.nan,
    }


def measure(
    cells: int,
    kinematics: str,
    positions: Path | None = None,
    friction: float = 0.0,
    fibre_bending: float = 0.0,
) -> dict[str, Any]:
    """One unscaled run of the case (``hemisphere_forming.run``) and its record: the
    ``QUANTITIES``, the end force and state, the centre line's state, converged, steps,
    end time (s), the holder's lift (mm), CPU and wall (s) and the load at start and end.
    ``positions``: a .npz file to keep the blank's points and end positions (mm) in. The
    case's variant (its ``model``; the case has neither, 0 and 0): Coulomb ``friction`` on
    the die and the holder, the fibres' in-plane bending ``fibre_bending`` (N mm); the record
    holds both (``variant``) and the share of the work the contacts dissipated by friction."""
    from validation.cases import hemisphere_forming as case

    record = case.run(cells, kinematics, friction=friction, fibre_bending=fibre_bending)
    result = record["result"]
    mesh = record["mesh"]
    if positions is not None:
        np.savez_compressed(positions, points=mesh.points, positions=result.positions)
    out: dict[str, Any] = {
        "cells": cells,
        "kinematics": kinematics,
        "variant": {"friction": float(friction), "fibre_bending_N_mm": float(fibre_bending)},
    }
    out.update({key: float(record[key]) for key in QUANTITIES})
    out.update(
        {
            "kinetic_over_work": float(record["kinetic_over_work"]),
            "kinetic_exceeded_share": float(record["kinetic_exceeded_share"]),
            "damping_over_work": float(record["damping_over_work"]),
            # no contact damping in the case: what the contacts dissipated is friction's
            "friction_over_work": float(record["contact_damping_over_work"]),
            "holder_lift_mm": record["holder_lift_mm"],
            "converged": bool(result.converged),
            "steps": int(result.steps),
            "end_time_s": float(record["end_time_s"]),
            "cost": record["cost"],
            "centre_line": centre_line_state(mesh.points, result.positions[: mesh.n_nodes]),
        }
    )
    return out


def variant(record: dict[str, Any]) -> dict[str, float]:
    """The case's variant a ``measure`` record ran: its friction on the die and the holder
    and the fibres' in-plane bending (N mm); the case's own (0, 0) for records written
    before the study had variants."""
    return record.get("variant", {"friction": 0.0, "fibre_bending_N_mm": 0.0})


def read_records(folder: Path, kinematics: str) -> list[dict[str, Any]]:
    """The records of ``kinematics`` in ``folder`` (``<kinematics>-<cells>.json``), coarsest
    first."""
    records = [json.loads(p.read_text()) for p in folder.glob(f"{kinematics}-*.json")]
    return sorted(records, key=lambda r: r["cells"])


def orders(records: list[dict[str, Any]]) -> dict[str, dict[str, Any]]:
    """Per quantity of ``QUANTITIES`` over ``records`` (three or more, coarsest first): the
    ``values``, the observed order ``p`` and Richardson value ``f0`` of the finest three, the
    orders of each consecutive three (``consecutive``) and the finest's grid convergence
    index (``gci``, in the quantity's unit; NaN without a positive order), and with four or
    more runs the least-squares power law through all of them (``fit``: ``power_fit``'s
    order, value at h = 0, residual and the change it explains; None with three)."""
    if len(records) < 3:
        raise ValueError(f"give three or more runs, got {len(records)}")
    variants = {json.dumps(variant(r), sort_keys=True) for r in records}
    if len(variants) > 1:
        raise ValueError(
            f"the runs are of different variants of the case ({', '.join(sorted(variants))}): "
            "an order needs one case on every mesh"
        )
    sizes = [200.0 / r["cells"] for r in records]
    table = {}
    for key, label in QUANTITIES.items():
        values = [float(r[key]) for r in records]
        p, f0 = observed_order(sizes[-3:], values[-3:])
        table[label] = {
            "values": values,
            "p": p,
            "f0": f0,
            "consecutive": consecutive_orders(sizes, values).tolist(),
            "gci": grid_convergence_index(sizes[-3:], values[-3:])["gci"],
            "fit": power_fit(sizes, values) if len(records) > 3 else None,
        }
    return table


def _main(argv: list[str]) -> None:
    import argparse

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    verbs = parser.add_subparsers(dest="verb", required=True)
    one = verbs.add_parser("run", help="one run, its record written as it ends")
    one.add_argument("kinematics", choices=("fibrous", "mindlin"))
    one.add_argument("cells", type=int)
    one.add_argument("--out", type=Path, required=True)
    one.add_argument("--friction", type=float, default=0.0, help="on the die and the holder")
    one.add_argument("--fibre-bending", type=float, default=0.0, help="B_in, N mm (0: none)")
    table = verbs.add_parser("orders", help="the observed orders of the recorded runs")
    table.add_argument("folder", type=Path)
    arguments = parser.parse_args(argv)
    if arguments.verb == "run":
        if arguments.cells < 2:
            parser.error(f"cells must be an integer of at least 2, got {arguments.cells}")
        arguments.out.mkdir(parents=True, exist_ok=True)
        path = arguments.out / f"{arguments.kinematics}-{arguments.cells}.json"
        record = measure(
            arguments.cells,
            arguments.kinematics,
            path.with_suffix(".npz"),
            arguments.friction,
            arguments.fibre_bending,
        )
        path.write_text(json.dumps(record, indent=1))
        print(json.dumps(record, indent=1), f"load now {os.getloadavg()[0]:.1f}")
        return
    for kinematics in ("fibrous", "mindlin"):
        records = read_records(arguments.folder, kinematics)
        if not records:
            continue
        cells = [r["cells"] for r in records]
        print(f"{kinematics}, cells {cells}, variant {variant(records[0])}:")
        fields = []
        for r in records:
            kept = np.load(arguments.folder / f"{kinematics}-{r['cells']}.npz")
            fields.append(shear_field(r["cells"], kept["positions"]))
            # the line's state again from the kept positions (records before its strain)
            line = centre_line_state(kept["points"], kept["positions"])
            print(
                f"  {r['cells']}: {r['steps']} steps, {r['cost']['cpu_s']:.0f} s CPU (load "
                f"{r['cost']['load'][0]:.1f} -> {r['cost']['load'][1]:.1f}), converged "
                f"{r['converged']}, reached {r['end_time_s']:.4f} s; centre line "
                f"{line['height_over_round_mm']:.2f} mm over the round, strained "
                f"{100 * line['strain_to_flange']:+.2f} % to the flange; friction took "
                f"{100 * r.get('friction_over_work', 0.0):.1f} % of the work, the holder "
                f"rose {r['holder_lift_mm']:.2f} mm"
            )
        for region, row in field_orders(cells, fields).items():
            print(
                f"  shear field {region} ({row['points']} points): against the net "
                + ", ".join(f"{v:.3f}" for v in row["against net"])
                + " deg, orders "
                + ", ".join(f"{v:.2f}" for v in row["against net orders"])
                + "; change to the next mesh "
                + ", ".join(f"{v:.3f}" for v in row["changes"])
                + " deg, orders "
                + ", ".join(f"{v:.2f}" for v in row["change orders"])
            )
        if len(records) < 3:
            continue
        for label, row in orders(records).items():
            values = ", ".join(f"{v:.4g}" for v in row["values"])
            steps = ", ".join(f"{q:.2f}" for q in row["consecutive"])
            print(
                f"  {label}: {values}; finest three p = {row['p']:.2f}, f0 = {row['f0']:.4g}, "
                f"GCI {row['gci']:.3g}; consecutive p: {steps}"
            )
            fit = row["fit"]
            if fit is not None:
                print(
                    f"    least squares over all: p = {fit['order']:.2f}, f0 = "
                    f"{fit['extrapolated']:.4g}, residual {fit['residual']:.3g} against a "
                    f"change of {fit['change']:.3g}{' (p at its bound)' if fit['bound'] else ''}"
                )


if __name__ == "__main__":
    _main(sys.argv[1:])
