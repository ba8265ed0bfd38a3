"""How deep a run's body ended inside its rigid tools: ``result.info["tool_penetration"]``
and a warning past a stated share of the body's thickness.

A penalty contact holds a node off its tool by a spring, so a pressed node always sits a
little inside it: the depth is the load over the springs (docs/theory.md §9.3). Where the
load is large against the penalty (a holder pressed hard, a coarse mesh under a punch) the
depth becomes a visible share of the thickness, the stack's thickness and the tool's stroke
are off by it, and nothing else in the results says so: each solver measures it at its last
frame through the interaction protocol (``InteractionBlock.tool_penetrations``) and warns
past ``PENETRATION_SHARE`` of h, the share the ply contacts warn at too
(fibreshell/layup_summary.py)."""

from __future__ import annotations

import warnings
from typing import Any

import numpy as np

from femcore.model import CompiledModel
from femcore.results import Frame
from femcore.state import State
from solvers.common import outside_stacklevel

__all__ = [
    "PENALTY_MARGIN",
    "PENETRATION_SHARE",
    "record_tool_penetration",
    "tool_penetration_report",
    "warn_tool_penetrations",
]

#: The penetration of a contact past which a run warns, a share of the body's thickness h
#: (for the plies, the thinner ply's; a layup's plies are one fabric): a quarter of h, past
#: which the plies' order and the stack's thickness are visibly off (0.1 MPa on a [0/90]
#: fibrous pair of 0.3 mm plies at the automatic penalty overlaps them by 0.251 mm, 0.84 h;
#: 0.2 MPa turns their order), above the shipped forming case's coarse pair, 0.10-0.12 h at
#: the punch's pole, whose checks accept it (tests/test_case_layup.py).
PENETRATION_SHARE = 0.25
#: The penalty said to keep a contact within the share is this many times the one that would
#: keep the mean of its pressed nodes' depths at the deepest's share: the load is shared out
#: unevenly as the plies bend (the deepest node of a [0/90] pair pressed at 0.1 MPa, 2 cells a
#: side, 1.28 times the mean under a uniform penalty, where the automatic one had pressed
#: every node alike through the ply).
PENALTY_MARGIN = 1.5


def tool_penetration_report(
    model: CompiledModel, frame: Frame, share: float = PENETRATION_SHARE
) -> dict[str, dict[str, Any]]:
    """Per rigid tool its body's deepest penetration at ``frame`` (a run's last).

    Parameters
    ----------
    model : CompiledModel
    frame : femcore.results.Frame
        The positions (n, 3), mm, and load factor the tools are placed at.
    share : float
        The share of the thickness h past which a node counts as too deep.

    Returns
    -------
    dict
        {"tool<k>" (k in ``tool_forces``' order, from 1): {deepest_mm, node, at (3,) mm,
        thickness_mm, share_of_thickness (deepest over the thickness there, None for a
        body without thickness), pressed, past_share (nodes deeper than ``share`` h),
        force_N, penalty (a penalty per node, N/mm, that keeps the deepest within ``share``
        h under the same load, None where it is within: the pressed nodes' force over their
        count and share h, times the deepest's depth over their mean and
        ``PENALTY_MARGIN``)}}; a tool no interaction measures is left out.
    """
    n = frame.positions.shape[0]
    state = State(
        positions=frame.positions,
        directors=frame.directors,
        velocities=frame.velocities,
        angular_velocities=np.zeros((n, 3)),
        time=frame.time,
        load_factor=frame.load_factor,
    )
    out: dict[str, dict[str, Any]] = {}
    for k, found in enumerate(model.tool_penetrations(state, share), start=1):
        if found is None:
            continue
        h = found["thickness_mm"]
        entry = dict(found)
        entry["share_of_thickness"] = found["deepest_mm"] / h if h > 0.0 else None
        entry["penalty"] = None
        if found["past_share"] and found["mean_mm"] > 0.0 and h > 0.0:
            # a uniform penalty k per node gives the pressed nodes a mean depth F / (n k);
            # the deepest lies deeper than the mean by their ratio, more as the body bends
            unevenness = max(1.0, found["deepest_mm"] / found["mean_mm"])
            entry["penalty"] = (
                PENALTY_MARGIN * unevenness * found["force_N"] / (found["pressed"] * share * h)
            )
        del entry["mean_mm"]
        out[f"tool{k}"] = entry
    return out


def warn_tool_penetrations(
    report: dict[str, dict[str, Any]], solver: str, share: float = PENETRATION_SHARE
) -> None:
    """A UserWarning, once, naming each tool of ``report`` (``tool_penetration_report``) whose
    body went deeper than ``share`` of its thickness, with the remedies the contact supports
    under ``solver`` ("Static", "CentralDifference", "DynamicRelaxation"): a larger penalty
    (the one said keeps it within the share), ``augmented`` under Static, a finer mesh."""
    deep = {
        tool: entry
        for tool, entry in report.items()
        if entry["share_of_thickness"] is not None and entry["share_of_thickness"] > share
    }
    if not deep:
        return
    said = "; ".join(
        f"{tool} by {e['deepest_mm']:.3g} mm ({e['share_of_thickness']:.2g} of the "
        f"{e['thickness_mm']:.3g} mm thickness) at node {e['node']} "
        f"({', '.join(f'{c:.4g}' for c in e['at'])}), {e['past_share']} of its "
        f"{e['pressed']} pressed nodes past {share:g} h, under {e['force_N']:.3g} N"
        + ("" if e["penalty"] is None else f": penalty = {e['penalty']:.3g} N/mm or more")
        for tool, e in deep.items()
    )
    remedies = [
        "a larger penalty per node (model.contact(..., penalty=k); [[contact]] penalty = k)"
        + (", which shortens the explicit step" if solver == "CentralDifference" else "")
    ]
    if solver == "Static":
        remedies.append(
            "augmented=True (augmented = true), which holds the penetration within its "
            "augmented_tolerance whatever the penalty"
        )
    remedies.append(
        "a finer mesh where the tool presses (its load shared over more nodes' springs)"
    )
    warnings.warn(
        f"the body went into its rigid tools: {said} (result.info['tool_penetration'], "
        f"summary.json tool_penetration; more than {share:g} of the body's thickness). "
        f"Try {'; or '.join(remedies)}",
        UserWarning,
        stacklevel=outside_stacklevel(),
    )


def record_tool_penetration(model: CompiledModel, result: Any, solver: str, warn: bool) -> None:
    """Put ``tool_penetration_report`` at ``result``'s last frame into
    ``result.info["tool_penetration"]`` (a model with rigid tools), and where ``warn`` (a
    run that ended as asked) ``warn_tool_penetrations``."""
    if not result.frames or model.n_tools == 0:
        return
    report = tool_penetration_report(model, result.frames[-1])
    result.info["tool_penetration"] = report
    if warn:
        warn_tool_penetrations(report, solver)
