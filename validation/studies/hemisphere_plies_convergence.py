"""The two-ply hemisphere's discretisation error from records of its runs at several
resolutions (validation/studies/hemisphere_plies_record.py): per ply the shear field against
the pin-jointed net at fixed material points on the punch, the field's change between
consecutive meshes, the edges' mean draw-in and the corners', the punch's force at fixed
strokes, and the flange's wrinkles, with the observed order over every three consecutive
resolutions, Roache's grid convergence index and a least-squares power law over all of them
(validation/studies/grid_convergence.py). The measures are
validation/studies/hemisphere_plies_fields.py's; what they gave, docs/hemisphere_plies.md
"Converged results".

Run it with ``python -m validation.studies.hemisphere_plies_convergence folder`` after
``hemisphere_plies_record`` has written the runs' records into ``folder``; a run that stopped
before the end of the stroke is named and left out.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import numpy as np

from elements.layup import ply_shear
from validation.forming_measures import corner_draw_in, edge_draw_in
from validation.studies.grid_convergence import (
    change_orders,
    consecutive_orders,
    grid_convergence_index,
    power_fit,
)
from validation.studies.hemisphere_plies_fields import (
    centre_lines,
    field_at,
    groups_round,
    line_strain,
    material_grid,
    net_on_sphere,
    nodal_average,
)
from validation.studies.hemisphere_plies_setup import (
    DIE,
    HALF,
    NET_CELL,
    PLIES,
    PUNCH,
    THICKNESS,
    TRAVEL,
)

__all__ = ["GAP_DEG", "LIFT", "POLAR_DEG", "SPACING", "STROKES", "measure", "table"]

#: deg: the material points compared with the net lie within this polar angle of the pole on
#: it; the die's entry round starts at 90 deg, the flange beyond
POLAR_DEG = (45.0, 60.0, 75.0)
#: mm: the material grid's spacing, finer than the finest cell (10 mm at 20 cells)
SPACING = 2.0
#: the shares of the punch's travel at which its force is read (averaged over +-2 % of it;
#: at the end over its last 2 %) and its work up to them
STROKES = (0.25, 0.5, 0.75, 0.9, 1.0)
#: mm: a node is lifted when it stands this far above its ply's flat level past the die's
#: opening (one ply thickness); the lying ones stay within 0.3 mm of it
LIFT = THICKNESS
#: deg: lifted nodes further apart round the axis than this are separate places
GAP_DEG = 20.0


def _sphere(k: int) -> float:
    """Ply k's mid-surface sphere radius over the punch, mm (ply 1 the outer one)."""
    return PUNCH + (PLIES - k - 0.5) * THICKNESS


def measure(record: dict[str, Any]) -> dict[str, Any]:
    """The measures of one run's ``record`` (``hemisphere_plies_record.load``): {label:
    value} for the scalars, and each ply's shear field at the material grid (rad) under
    ``"fields"`` for the differences between meshes."""
    reference, triangles = record["reference"], record["triangles"]
    final = record["positions"][-1]
    history = record["history"]
    travel = -history["tool2_displacement_z"]
    grid = material_grid(HALF, SPACING)
    values: dict[str, float] = {}
    fields = []
    for k, (cells, nodes) in enumerate(zip(record["ply_cells"], record["ply_nodes"])):
        ply = f"ply {k + 1} ({record['angles'][k]:g} deg)"
        shear = ply_shear(reference, final, triangles[cells], record["warps"][k])
        field = field_at(
            reference, triangles[cells], nodal_average(reference, triangles[cells], shear), grid
        )
        fields.append(field)
        net = net_on_sphere(_sphere(k), NET_CELL, record["angles"][k], grid)
        # the nodes in each region that lie on their sphere at the end (0.5 mm, as the run's
        # cells in the die): the net is the reference where the ply lies on the punch
        node_polar = net_on_sphere(_sphere(k), NET_CELL, record["angles"][k], reference[nodes])[
            "polar"
        ]
        on_sphere = np.abs(np.linalg.norm(final[nodes], axis=1) - _sphere(k)) < 0.5
        for polar in POLAR_DEG:
            inside = net["polar"] <= math.radians(polar)
            error = np.degrees(field[inside] - net["shear"][inside])
            values[f"{ply} rms of shear - net within {polar:g} deg, deg"] = float(
                np.sqrt(np.mean(error**2))
            )
            held = node_polar <= math.radians(polar)
            values[f"{ply} share on the sphere within {polar:g} deg"] = float(
                on_sphere[held].mean()
            )
        run = record["parameters"]
        (cell_rms,) = [
            v
            for n, v in run.items()
            if n.endswith(f"ply{k + 1}_{record['angles'][k]:g}deg_rms_shear_error_deg")
        ]
        values[f"{ply} rms of shear - net over the cells in the die (the run's), deg"] = float(
            cell_rms
        )
        points = reference[nodes]
        values[f"{ply} edges' mean draw-in, mm"] = edge_draw_in(points, final[nodes], HALF)
        values[f"{ply} corners' mean draw-in, mm"] = corner_draw_in(points, final[nodes], HALF)
        middle = nodes[np.argmin(np.linalg.norm(points[:, :2] - [HALF, 0.0], axis=1))]
        values[f"{ply} draw-in of the edge middle (+x), mm"] = float(
            HALF - np.linalg.norm(final[middle, :2])
        )
        lines = centre_lines(points, HALF)
        strains = [line_strain(points, final[nodes], line) for line in lines]
        values[f"{ply} centre lines' mean strain (+x, +y, -x, -y)"] = float(np.mean(strains))
        values[f"{ply} centre line's strain (+x)"] = strains[0]
        middles = [HALF - float(np.linalg.norm(final[nodes[line[-1]], :2])) for line in lines]
        values[f"{ply} edge middles' draw-in, least, mm"] = min(middles)
        values[f"{ply} edge middles' draw-in, largest, mm"] = max(middles)
        flat = record["heights"][k]
        # a centre line lifts between the die's round and the holder's ring, or lies on them
        rise = [float(np.max(final[nodes[line], 2]) - flat) for line in lines]
        lifted = [r > LIFT for r in rise]
        values[f"{ply} centre lines lifted (of 4)"] = int(np.sum(lifted))
        for state, chosen in (("lifted", lifted), ("lying", [not x for x in lifted])):
            picked = [m for m, c in zip(middles, chosen) if c]
            values[f"{ply} edge middles' draw-in, {state} lines' mean, mm"] = (
                float(np.mean(picked)) if picked else math.nan
            )
        # the places where the ply stands off the die and the flange: its nodes past the die's
        # opening risen above the flange's level by more than LIFT
        past = np.linalg.norm(record["positions"][:, nodes, :2], axis=2) >= DIE
        height = np.where(past, record["positions"][:, nodes, 2] - flat, -np.inf).max(axis=1)
        values[f"{ply} largest rise past the die's opening, mm"] = float(height[-1])
        values[f"{ply} largest rise past the die's opening over the run, mm"] = float(height.max())
        up = past[-1] & (final[nodes, 2] - flat > LIFT)
        values[f"{ply} lifted places"] = groups_round(
            np.arctan2(final[nodes[up], 1], final[nodes[up], 0]), math.radians(GAP_DEG)
        )
        risen = np.flatnonzero(height > LIFT)
        values[f"{ply} lifted from (share of the travel)"] = (
            float(np.interp(record["times"][risen[0]], history["time"], travel) / TRAVEL)
            if risen.size
            else math.nan
        )
    force = history["tool2_force_z"]
    for share in STROKES:
        window = np.abs(travel - share * TRAVEL) <= 0.02 * TRAVEL
        values[f"punch force at {share:g} of the travel, N"] = (
            float(np.mean(force[window])) if window.any() else math.nan  # not reached
        )
    values["punch force at the end, N"] = float(record["tool_forces"][-1, 1, 2])
    # the punch's work (its force integrated over its travel, trapezoids over the history
    # records): the force's ringing averaged out
    work = np.concatenate([[0.0], np.cumsum(0.5 * (force[1:] + force[:-1]) * np.diff(travel))])
    for share in STROKES:
        values[f"punch work to {share:g} of the travel, N mm"] = float(
            np.interp(share * TRAVEL, travel, work)
        )
    return {
        "values": values,
        "fields": fields,
        "cells": record["cells"],
        "angles": [float(a) for a in record["angles"]],
        "stopped": [str(v) for n, v in record["parameters"].items() if n.endswith("stopped")],
        "failed": [name for name, passed in record["checks"] if not passed],
    }


def field_changes(runs: list[dict[str, Any]]) -> dict[str, dict[str, list[float]]]:
    """{label: {"changes": (m - 1), "to finest": (m)}}: each ply's rms over the material
    points within each ``POLAR_DEG`` of the change of its shear field (deg) from each run to
    the next finer, and from each run to the finest (0 for the finest: for f = f0 + C(X) h^p
    it is rms(C) (h^p - h_m^p), a power law in h whose p ``power_fit`` finds from all the
    runs at once)."""
    grid = material_grid(HALF, SPACING)
    out: dict[str, dict[str, list[float]]] = {}

    def rms(a: np.ndarray, b: np.ndarray, inside: np.ndarray) -> float:
        return float(np.degrees(np.sqrt(np.mean((a - b)[inside] ** 2))))

    for k, angle in enumerate(runs[0]["angles"]):
        polar = net_on_sphere(_sphere(k), NET_CELL, angle, grid)["polar"]
        for limit in POLAR_DEG:
            inside = polar <= math.radians(limit)
            label = f"ply {k + 1} shear field within {limit:g} deg, deg"
            finest = runs[-1]["fields"][k]
            out[label] = {
                "changes": [
                    rms(a["fields"][k], b["fields"][k], inside) for a, b in zip(runs[:-1], runs[1:])
                ],
                "to finest": [rms(r["fields"][k], finest, inside) for r in runs],
            }
    return out


def table(runs: list[dict[str, Any]]) -> list[str]:
    """Lines of text: each quantity's values over the runs (coarse to fine), the observed
    order of each three consecutive ones, the finest three's GCI and Richardson value, and
    the power law fitted to all."""
    cells = [r["cells"] for r in runs]
    sizes = [2.0 * HALF / c for c in cells]
    lines = [f"cells: {cells}; h = {', '.join(f'{h:.2f}' for h in sizes)} mm"]
    for label in runs[0]["values"]:
        values = [r["values"][label] for r in runs]
        lines.append(f"{label}: {', '.join(f'{v:.4g}' for v in values)}")
        counted = "share" in label or "lifted" in label or "places" in label
        if len(runs) < 3 or counted or not np.all(np.isfinite(values)):
            continue
        orders = consecutive_orders(sizes, values)
        index = grid_convergence_index(sizes[-3:], values[-3:])
        fit = power_fit(sizes, values)
        lines.append(
            f"    p by threes {', '.join(f'{p:.2f}' for p in orders)}; finest three: "
            f"f0 {index['extrapolated']:.4g}, GCI {index['gci']:.3g}; fit p {fit['order']:.2f}, "
            f"f0 {fit['extrapolated']:.4g}, residual {fit['residual']:.3g} of "
            f"{fit['change']:.3g}" + (" (p at its bound)" if fit["bound"] else "")
        )
    for label, field in field_changes(runs).items():
        changes, distance = field["changes"], field["to finest"]
        lines.append(f"{label}: rms changes {', '.join(f'{v:.4g}' for v in changes)}")
        lines.append(f"    rms to the finest {', '.join(f'{v:.4g}' for v in distance)}")
        if len(changes) >= 2:
            lines.append(
                "    order of the changes "
                + ", ".join(f"{p:.2f}" for p in change_orders(sizes, changes))
            )
        if len(runs) >= 4:
            fit = power_fit(sizes, distance)
            lines.append(
                f"    power law to the finest: p {fit['order']:.2f}, the finest's distance to "
                f"the limit {-fit['extrapolated']:.3g}, residual {fit['residual']:.3g} of "
                f"{fit['change']:.3g}" + (" (p at its bound)" if fit["bound"] else "")
            )
    return lines


if __name__ == "__main__":
    import sys

    from validation.studies.hemisphere_plies_record import load

    folder = Path(sys.argv[1])
    paths = sorted(folder.glob("*.npz"), key=lambda p: int(p.stem.rsplit("_", 1)[1]))
    measured = [measure(load(p)) for p in paths]
    for out in measured:
        for name in out["failed"]:
            print(f"{out['cells']} cells: FAIL {name}")
        for text in out["stopped"]:
            print(f"{out['cells']} cells stopped, left out of the orders: {text}")
    print("\n".join(table([out for out in measured if not out["stopped"]])))
