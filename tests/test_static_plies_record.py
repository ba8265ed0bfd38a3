"""benchmarks/static_plies_newton.py's record of a Static ply solve (its ``--detail``): the
solver's pieces it wraps are those the load path calls, so every attempt and iterate is
recorded (the wrapped Newton entry once moved from solvers/load_path.py to
solvers/penalty_start.py and the script stopped at its start)."""

from __future__ import annotations

import importlib.util
import os
import sys
from pathlib import Path

import numpy as np

import solvers.line_search as line_search
import solvers.penalty_start as penalty_start_module
import solvers.static as static_module
from elements.plies import PlyStack
from femcore import Mesh
from materials import BendingLaw, Fabric, ShearLaw
from solvers import Static

SCRIPT = Path(__file__).resolve().parents[1] / "benchmarks" / "static_plies_newton.py"


def _script():
    spec = importlib.util.spec_from_file_location("static_plies_newton_script", SCRIPT)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_detail_records_every_iterate_of_a_ply_stack(monkeypatch):
    # The wrapped names, the environment and the path the script sets restored after the
    # test (it replaces them for good).
    monkeypatch.setenv("NUMBA_NUM_THREADS", os.environ.get("NUMBA_NUM_THREADS", "1"))
    monkeypatch.setattr(sys, "path", list(sys.path))
    monkeypatch.setattr(penalty_start_module, "newton", penalty_start_module.newton)
    monkeypatch.setattr(static_module.StaticRun, "tangent", static_module.StaticRun.tangent)
    monkeypatch.setattr(line_search.Watchdog, "step", line_search.Watchdog.step)
    script = _script()
    script.instrument()
    fabric = Fabric(
        thickness=2.0,
        areal_density=5.7e-9,
        tension=1200.0,
        shear=ShearLaw.linear(0.01),
        bending=BendingLaw.linear(1.0),
    )
    stack = PlyStack(Mesh.rectangle(40.0, 10.0, nx=4, ny=1), fabric, 2)
    model = stack.model()
    model.fix(stack.nodes("left"))
    model.gravity((0.0, 0.0, -9810.0))
    result = Static(increments=2, seek_stable=False, progress=False).solve(model)
    attempts = script.RECORD["attempts"]
    info = result.info
    # one record an attempt (the cut ones too), their iterations those the solver counts
    failed = [entry for entry in attempts if entry["failed"] is not None]
    converged = [entry for entry in attempts if entry["failed"] is None]
    assert len(failed) == info["cuts"]
    assert sum(len(entry["history"]) - 1 for entry in failed) == info["iterations_cut"]
    assert sum(len(entry["history"]) - 1 for entry in converged) == result.steps
    # each tangent's row holds the plies' points; after an attempt's first, the changes
    # between iterates and the largest gap change
    rows = [row for entry in attempts for row in entry["iterations"]]
    assert len(rows) == info["evaluations"]["tangent"]
    assert all(row["touching"] >= row["ramp"] >= 0 for row in rows)
    later = [row for entry in attempts for row in entry["iterations"][1:]]
    assert later and all(np.isfinite(row["gap_change"]) for row in later)
