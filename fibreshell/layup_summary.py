"""The per-ply numbers of a ``[layup]`` run for summary.json (fibreshell/case_layup.py): each
ply's angle, shear and mean displacement, and the slip of each ply over the one below, as a
Python run of ``elements.layup.Layup`` measures them (``Layup.shear``, the ply contacts'
``ply_slip`` field, elements/ply_slip.py)."""

from __future__ import annotations

import re
from typing import Any

import numpy as np

from elements.layup import Layup
from elements.ply_crossing import crossed_nodes
from elements.ply_slip import slip_summary
from femcore.results import Frame
from solvers.tool_penetration import PENALTY_MARGIN, PENETRATION_SHARE

__all__ = [
    "PENETRATION_SHARE",
    "layup_summary",
    "ply_crossings",
    "ply_penetrations",
    "ply_slip_fields",
]

_SLIP = re.compile(r"ply_slip(?:_(\d+))?")
_GAP = re.compile(r"ply_gap(?:_(\d+))?")
# PENETRATION_SHARE, a quarter of the ply thickness, and PENALTY_MARGIN are the tools' too:
# one share for every contact (solvers/tool_penetration.py says why).


def ply_slip_fields(point_fields: dict[str, np.ndarray]) -> list[str]:
    """The names of the ``ply_slip`` node fields of a frame, one per ply contact in the order
    of the contacts ("ply_slip", "ply_slip_2", ...: ply 2 on ply 1 first; femcore.compiled
    ``fields`` numbers a name the second part gives again)."""
    found = [(int(m.group(1) or 1), name) for name in point_fields
             if (m := _SLIP.fullmatch(name))]  # fmt: skip
    return [name for _, name in sorted(found)]


def layup_summary(layup: Layup, reference: np.ndarray, frame: Frame) -> dict[str, Any]:
    """The layup's numbers at ``frame``.

    Parameters
    ----------
    layup : Layup
    reference : (n, 3) float
        The layup's reference positions, mm.
    frame : femcore.results.Frame
        With its node fields (the ply contacts' ``ply_slip``).

    Returns
    -------
    dict
        ``angles_deg``; ``friction`` (ply on ply); ``plies``: per "ply_k" (1 = bottom) its
        ``angle_deg``, ``warp`` (3,), ``shear_deg`` {min, max, rms} of its fibre-aligned
        triangles (``Layup.shear``: 90 deg less the angle between the deformed warp and weft,
        the pin-jointed net's sign), ``mean_displacement`` (3,) mm; ``slip``: per upper ply
        "ply_k" (k >= 2) the ``ply_slip`` over ply k - 1 since the start {max_mm, rms_mm,
        nodes} (``elements.ply_slip.slip_summary``; nodes with no ply below left out);
        ``crossed``: ``ply_crossings``; ``penetration``: ``ply_penetrations``.
    """
    shear = layup.shear(frame.positions)
    plies = {}
    for k, (angle, warp, nodes, gamma) in enumerate(
        zip(layup.angles, layup.warps, layup.ply_nodes, shear), start=1
    ):
        degrees = np.degrees(gamma)
        plies[f"ply_{k}"] = {
            "angle_deg": float(angle),
            "warp": warp,
            "shear_deg": {
                "min": float(np.min(degrees)),
                "max": float(np.max(degrees)),
                "rms": float(np.sqrt(np.mean(degrees**2))),
            },
            "mean_displacement": (frame.positions[nodes] - reference[nodes]).mean(axis=0),
        }
    point = frame.fields.get("point", {})
    names = ply_slip_fields(point)
    slip = {
        f"ply_{k}": slip_summary(point[name][layup.ply_nodes[k - 1]])
        for k, name in zip(range(2, layup.count + 1), names)
    }
    return {
        "angles_deg": layup.angles,
        "friction": layup.friction,
        "plies": plies,
        "slip": slip,
        "crossed": ply_crossings(layup, reference, frame.positions),
        "penetration": ply_penetrations(layup, point),
    }


def ply_crossings(
    layup: Layup, reference: np.ndarray, positions: np.ndarray
) -> dict[str, dict[str, Any]]:
    """Per pair of plies, the nodes of the upper ply past the lower ply's mid-surface and those
    of the lower ply past the upper ply's at ``positions`` (elements/ply_crossing.py), {lower:
    the lower ply's name, nodes: how many, deepest_mm: the deepest past it, 0 for none, first:
    up to ten node ids}: where the plies have passed through each other, which the contact's
    fields do not show. Every pair is judged, as every ply touches every ply below it
    (elements/ply_contact.py ``join_plies``): a neighbour pair under the upper ply's name
    "ply_k" (k >= 2, on ply k - 1), the others as "ply_k_on_ply_j" (j < k - 1), where a ply
    drawn out from between them left them facing each other."""
    triangles = layup.mesh.triangles
    out = {}
    pairs = [(k, k - 1) for k in range(2, layup.count + 1)]
    pairs += [(k, j) for k in range(3, layup.count + 1) for j in range(k - 2, 0, -1)]
    for k, j in pairs:
        lower, upper = layup.ply_nodes[j - 1], layup.ply_nodes[k - 1]
        down, down_depth = crossed_nodes(
            reference, positions, upper, triangles[layup.ply_cells[j - 1]], 1.0
        )
        up, up_depth = crossed_nodes(
            reference, positions, lower, triangles[layup.ply_cells[k - 1]], -1.0
        )
        ids = np.concatenate([down, up])
        depth = np.concatenate([down_depth, up_depth])
        out[f"ply_{k}" if j == k - 1 else f"ply_{k}_on_ply_{j}"] = {
            "lower": f"ply_{j}",
            "nodes": int(ids.size),
            "deepest_mm": float(depth.max(initial=0.0)),
            "first": [int(i) for i in ids[np.argsort(-depth)][:10]],
        }
    return out


def _contact_pairs(layup: Layup) -> list[tuple[int, int]]:
    """(upper, lower) of each ply contact that writes node fields, in the model's order
    (elements/ply_contact.py ``join_plies``: the neighbours, then with ``pairs="all"`` the
    others; a mirrored pass writes none)."""
    pairs = [(k, k - 1) for k in range(2, layup.count + 1)]
    if getattr(layup, "pairs", "neighbours") == "all":
        pairs += [(k, j) for k in range(3, layup.count + 1) for j in range(k - 2, 0, -1)]
    return pairs


def ply_penetrations(
    layup: Layup, point_fields: dict[str, np.ndarray], share: float = PENETRATION_SHARE
) -> dict[str, dict[str, Any]]:
    """Per ply contact whose penetration passes ``share`` of the ply thickness h at a frame
    (its ``ply_gap`` node fields, the mean gap of the points around each upper node, < 0 a
    penetration; ``ply_contact_force`` their pressing force, N): {upper, lower: the plies'
    names, deepest_mm, share_of_thickness, nodes: how many upper nodes are past share h,
    penalty: a penalty per upper node, N/mm, that keeps the deepest within share h under the
    same load (the give is the load over the springs, docs/theory.md §9.3a: the pressed
    nodes' force F over their count n and share h, times the deepest's depth over their mean
    and ``PENALTY_MARGIN``)}, keyed as ``ply_crossings`` keys its pairs. Empty where no
    contact passes it."""
    limit = share * layup.fabric.thickness
    gaps = sorted(
        (int(m.group(1) or 1), name) for name in point_fields if (m := _GAP.fullmatch(name))
    )
    out = {}
    for (k, j), (_, name) in zip(_contact_pairs(layup), gaps):
        gap = np.asarray(point_fields[name], dtype=float)
        forces = np.asarray(point_fields[name.replace("ply_gap", "ply_contact_force")])
        # a node pressed by the contact: its gap is a penetration (beside the lower ply's
        # outline a gap is the distance to its edge, with no force)
        depth = np.where(np.isfinite(gap) & (forces > 0.0), -gap, 0.0)
        over = np.flatnonzero(depth > limit)
        if over.size == 0:
            continue
        deepest = over[np.argmax(depth[over])]
        pressed = np.flatnonzero(depth > 0.0)
        force = float(np.sum(forces[pressed]))
        # a uniform penalty k per upper node gives the pressed nodes a mean depth F / (n k);
        # the deepest lies deeper than the mean by their ratio here, and by more as the
        # plies' bending shares the load out unevenly: PENALTY_MARGIN
        unevenness = max(1.0, float(depth[deepest] / np.mean(depth[pressed])))
        penalty = PENALTY_MARGIN * unevenness * force / (pressed.size * limit)
        out[f"ply_{k}" if j == k - 1 else f"ply_{k}_on_ply_{j}"] = {
            "upper": f"ply_{k}",
            "lower": f"ply_{j}",
            "deepest_mm": float(depth[deepest]),
            "share_of_thickness": float(depth[deepest] / layup.fabric.thickness),
            "nodes": int(over.size),
            "penalty": penalty,
        }
    return out
