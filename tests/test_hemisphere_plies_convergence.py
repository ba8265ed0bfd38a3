"""validation/studies/hemisphere_plies_convergence.py ``measure`` on a made record whose
answers are closed forms: a two-ply [0/90] blank shrunk uniformly in its plane by a factor s
(no shear; every draw-in a share 1 - s of its distance to the pole, every fibre's strain
s - 1) under a punch whose force grows linearly with its travel (the force at a share of the
travel and the work up to it known exactly)."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from femcore.blank import ply_blank, ply_directions
from validation.studies.hemisphere_plies_convergence import STROKES, measure
from validation.studies.hemisphere_plies_setup import HALF, THICKNESS, TRAVEL

SHRINK = 0.9  # the blank's plane factor s
STIFFNESS = 2.0  # N/mm: the punch's force over its travel


def _record(cells: int = 8, lift: float = 0.0) -> dict:
    """A record of two plies of ``cells`` shrunk by SHRINK, the +x edge middle of both plies
    raised by ``lift`` mm."""
    blanks = [ply_blank(2 * HALF, 2 * HALF, cells, angle) for angle in (0.0, 90.0)]
    heights = np.array([0.5, 1.5]) * THICKNESS
    reference = np.concatenate([b.points + [0.0, 0.0, z] for b, z in zip(blanks, heights)])
    count = blanks[0].n_nodes
    triangles = np.concatenate([blanks[0].triangles, blanks[1].triangles + count])
    final = reference * [SHRINK, SHRINK, 1.0]
    for k in range(2):
        middle = k * count + np.argmin(np.linalg.norm(blanks[k].points[:, :2] - [HALF, 0], axis=1))
        final[middle, 2] += lift
    travel = np.linspace(0.0, TRAVEL, 2001)
    prefix = "0-90_fibrous_20_N"
    parameters = {f"{prefix}_ply1_0deg_rms_shear_error_deg": 1.5}
    parameters[f"{prefix}_ply2_90deg_rms_shear_error_deg"] = 2.5
    return {
        "reference": reference,
        "triangles": triangles,
        "ply_cells": [
            np.arange(len(blanks[0].triangles)) + k * len(blanks[0].triangles) for k in (0, 1)
        ],
        "ply_nodes": [np.arange(count) + k * count for k in (0, 1)],
        "angles": np.array([0.0, 90.0]),
        "warps": np.array([ply_directions(a)[0] for a in (0.0, 90.0)]),
        "heights": heights,
        "times": np.array([0.0, 0.1]),
        "positions": np.stack([reference, final]),
        "tool_forces": np.zeros((2, 3, 3))
        + [[0.0, 0.0, 0.0], [0.0, 0.0, STIFFNESS * TRAVEL], [0.0] * 3],
        "history": {
            "time": np.linspace(0.0, 0.1, travel.size),
            "tool2_displacement_z": -travel,
            "tool2_force_z": STIFFNESS * travel,
        },
        "parameters": json.loads(json.dumps(parameters)),
        "checks": [["the run reaches the end of the stroke (s)", True]],
        "cells": cells,
    }


def test_a_shrunk_blank_and_a_linear_punch():
    out = measure(_record())
    values = out["values"]
    assert out["stopped"] == [] and out["failed"] == []
    shrink = 1.0 - SHRINK
    for ply in ("ply 1 (0 deg)", "ply 2 (90 deg)"):
        assert values[f"{ply} edges' mean draw-in, mm"] == pytest.approx(shrink * HALF)
        assert values[f"{ply} corners' mean draw-in, mm"] == pytest.approx(
            shrink * math.sqrt(2.0) * HALF
        )
        assert values[f"{ply} draw-in of the edge middle (+x), mm"] == pytest.approx(shrink * HALF)
        assert values[f"{ply} centre lines' mean strain (+x, +y, -x, -y)"] == pytest.approx(-shrink)
        assert values[f"{ply} centre lines lifted (of 4)"] == 0
        assert values[f"{ply} lifted places"] == 0
        assert math.isnan(values[f"{ply} lifted from (share of the travel)"])
    # no shear: the field is zero at every material point, and defined at each (all inside)
    assert all(np.isfinite(f).all() and np.abs(f).max() < 1e-12 for f in out["fields"])
    # so its distance from the net is the net's own shear, which grows from the pole toward
    # the equator (zero along the fibres through the pole, largest on the diagonals' far end):
    # the rms over a larger polar angle is larger
    for ply in ("ply 1 (0 deg)", "ply 2 (90 deg)"):
        within = [values[f"{ply} rms of shear - net within {a} deg, deg"] for a in (45, 60, 75)]
        assert 0.0 < within[0] < within[1] < within[2], within
    assert (
        values["ply 2 (90 deg) rms of shear - net over the cells in the die (the run's), deg"]
        == 2.5
    )
    for share in STROKES:
        # a linear force: its mean over the +-2 % window is its value at the window's middle
        # (0.99 at the end, the window one-sided), to the records' spacing at its ends
        middle = min(share, 0.99) * TRAVEL
        assert values[f"punch force at {share:g} of the travel, N"] == pytest.approx(
            STIFFNESS * middle, abs=STIFFNESS * TRAVEL / 2000
        )
        # trapezoids integrate a linear force exactly
        assert values[f"punch work to {share:g} of the travel, N mm"] == pytest.approx(
            0.5 * STIFFNESS * (share * TRAVEL) ** 2, rel=1e-9
        )


def test_a_raised_edge_middle_is_a_lifted_line():
    values = measure(_record(lift=2.0))["values"]
    for ply in ("ply 1 (0 deg)", "ply 2 (90 deg)"):
        assert values[f"{ply} centre lines lifted (of 4)"] == 1
        assert values[f"{ply} lifted places"] == 1
        assert values[f"{ply} largest rise past the die's opening, mm"] == pytest.approx(2.0)
        assert values[f"{ply} edge middles' draw-in, lifted lines' mean, mm"] == pytest.approx(
            (1.0 - SHRINK) * HALF
        )
