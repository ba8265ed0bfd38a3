"""The observed order of convergence of what a paper case reports, on three meshes.

Each paper case reports, per kinematics, where its sides end up and how thick the fibrous
stack becomes along its directors. ``order_quantities`` takes from a run's side profiles the
numbers whose convergence the report shows: the deflection (z) at the middle of each filmed
side, and for the fibrous shell the thickness along the director there (/ h; the Mindlin
section keeps h). Values at a fixed material point, not the largest over the nodes: the
largest samples a smooth peak at whichever node is nearest, which moves from mesh to mesh and
blurs the order (bai-6.2.1's largest thickness: order 1.2 on 10-20-40 cells, none on
20-40-60). ``mesh_size`` is the mesh's h, ``observed_orders`` turns the values on three meshes
into ``ObservedOrder`` records (Richardson: validation.checks.observed_order) and
``order_checks`` checks them where the case states a tolerance: the order is positive and the
extrapolated value within that fraction of the finest mesh's (or, without a positive order,
the three values already agree to that fraction). The runs themselves are made by
validation.paper.case.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import replace
from typing import TYPE_CHECKING

import numpy as np

from validation import specimens
from validation.checks import check, observed_order
from validation.paper.kinematics import CHECK_NAMES, ELEMENT, PAPER, Kinematics
from validation.records import Check, ObservedOrder, SideProfile

if TYPE_CHECKING:
    from validation.paper.case import PaperCase

__all__ = [
    "ORDER_KINEMATICS",
    "deflection_name",
    "mesh_size",
    "order_kind",
    "observed_orders",
    "order_checks",
    "order_quantities",
    "thickness_name",
]

# The kinematics whose orders the report shows: the default fibrous shell and the Mindlin
# shell (the Eq. 15 variant would cost a third set of runs and adds no new question).
ORDER_KINEMATICS: tuple[Kinematics, ...] = ("fibrous", "mindlin")


def deflection_name(side: str) -> str:
    """The name of the mid-side deflection of ``side`` ("side_1") in the report."""
    return f"deflection z at the middle of {side.replace('_', ' ')} (mm)"


def thickness_name(side: str) -> str:
    """The name of the fibrous thickness at the middle of ``side`` ("side_1") in the report."""
    return f"thickness along the director at the middle of {side.replace('_', ' ')} / h"


def order_kind(record: ObservedOrder) -> str:
    """The key of ``record`` in a case's ``order_tolerance``: "<kinematics> deflection" or
    "<kinematics> thickness" (e.g. "mindlin deflection": both sides' mid-side deflections)."""
    kind = "thickness" if record.quantity.startswith("thickness") else "deflection"
    return f"{record.kinematics} {kind}"


def order_quantities(
    sides: dict[str, SideProfile], kinematics: Kinematics, h: float
) -> dict[str, float]:
    """From a run's side profiles, at the middle of each side (s = half the side's length,
    interpolated linearly between its nodes, so that the same material point is measured on
    every mesh, with or without a node there): the mid-surface z, and for the fibrous shell
    the thickness along the director divided by h."""
    out = {}
    for side, data in sides.items():
        s = np.asarray(data.s)
        middle = 0.5 * s.max()
        out[deflection_name(side)] = float(np.interp(middle, s, np.asarray(data.midsurface)[:, 2]))
        if ELEMENT[kinematics] == "fibrous":
            out[thickness_name(side)] = float(np.interp(middle, s, data.thickness)) / h
    return out


def mesh_size(specimen: specimens.Specimen) -> float:
    """The mesh size h (mm): the largest node spacing along side 1, the direction every paper
    specimen is refined in (the strip keeps its cells across; a gripped corner specimen's
    graded grid has its largest cells between the patch and the clamp)."""
    _, s = specimen.sides["side_1"]
    return float(np.diff(np.sort(s)).max())


def observed_orders(
    measured: dict[str, Sequence[tuple[int, float, dict[str, float], bool]]],
) -> list[ObservedOrder]:
    """One record per kinematics and quantity from ``measured``: kinematics -> the three runs,
    coarsest first, each (cells, mesh size h, {quantity: value}, converged). A quantity not
    finite on every mesh (a run that stopped before it could be measured) has NaN order and
    extrapolated value."""
    out = []
    for kinematics, runs in measured.items():
        cells = tuple(run[0] for run in runs)
        sizes = tuple(run[1] for run in runs)
        for quantity in runs[0][2]:
            values = tuple(run[2][quantity] for run in runs)
            if all(math.isfinite(v) for v in values):
                order, extrapolated = observed_order(sizes, values)
            else:
                order, extrapolated = math.nan, math.nan
            out.append(
                ObservedOrder(
                    kinematics=kinematics,
                    quantity=quantity,
                    cells=cells,
                    sizes=sizes,
                    values=values,
                    order=order,
                    extrapolated=extrapolated,
                    converged=all(run[3] for run in runs),
                )
            )
    return out


def order_checks(case: PaperCase, orders: list[ObservedOrder], resolution: str) -> list[Check]:
    """One check per record for which the case states a tolerance ``tol`` at ``resolution``
    (``PaperCase.order_tolerance[resolution][order_kind(record)]``); the others are reported
    only.

    A record with a positive observed order (the differences shrink) passes when its
    Richardson value lies within ``tol`` of the finest mesh's (relative). One without (the
    differences change sign, vanish or grow) passes only when its three values all lie within
    ``tol`` of the finest mesh's: it has converged to that tolerance on the coarsest of its
    meshes, and the order of differences that small is noise. Both need the three runs
    converged.
    """
    tolerances = (case.order_tolerance or {}).get(resolution, {})
    checks = []
    source = (
        f"the same model on three meshes (Richardson extrapolation); set-up: {PAPER}, {case.source}"
    )
    for record in orders:
        tolerance = tolerances.get(order_kind(record))
        if tolerance is None:
            continue
        finest = record.values[-1]
        cells = ", ".join(str(n) for n in record.cells)
        name = f"{CHECK_NAMES[record.kinematics]}: {record.quantity}, n = {cells}"
        if math.isfinite(record.order) and record.order > 0.0:
            verdict = check(
                f"{name}: extrapolated (observed order {record.order:.2f}) vs the finest mesh "
                f"(relative, < {tolerance:g})",
                finest,
                record.extrapolated,
                tolerance,
                source=source,
            )
        else:
            farthest = max(record.values, key=lambda value: abs(value - finest))
            verdict = check(
                f"{name}: no positive order (observed {record.order:.2f}); converged if the "
                f"values lie within {tolerance:g} of the finest (relative)",
                finest,
                farthest,
                tolerance,
                source=source,
            )
        checks.append(replace(verdict, passed=verdict.passed and record.converged))
    return checks
