"""benchmarks/static_plies_iterates.py's record of a Static ply solve
(benchmarks/static_plies_newton.py ``--detail``): the solver's pieces it wraps are those the
load path calls, so every attempt and iterate is recorded (the wrapped Newton entry once moved
from solvers/load_path.py to solvers/penalty_start.py and the script stopped at its start)."""

from __future__ import annotations

import importlib.util
import os
import sys
from pathlib import Path

import numpy as np
import pytest

import solvers.line_search as line_search
import solvers.penalty_start as penalty_start_module
import solvers.static as static_module
from elements.plies import PlyStack
from femcore import Mesh
from materials import BendingLaw, Fabric, ShearLaw
from solvers import Static

BENCHMARKS = Path(__file__).resolve().parents[1] / "benchmarks"


def _script(name: str = "static_plies_newton"):
    """The benchmark script ``name`` loaded as a module (its siblings imported as the
    benchmarks package's)."""
    spec = importlib.util.spec_from_file_location(f"{name}_script", BENCHMARKS / f"{name}.py")
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
    script = _script()  # the command that runs the record
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


def test_the_compared_change_of_a_stack_lowered_whole(monkeypatch):
    """``compared_change`` (``--case heavy --active-set``: what plies-heavy-cantilever
    compares between two equilibria of its plies) on the coarse case's 4 plies laid flat,
    lowered whole by 1 mm and by 1.25 mm: a translation, so the path's heights change by 0.25
    mm, the director angles and the thickness along the director not at all (round-off), and
    the tip's deflection goes from 1 to 1.25 mm."""
    monkeypatch.setenv("NUMBA_NUM_THREADS", os.environ.get("NUMBA_NUM_THREADS", "1"))
    monkeypatch.setattr(sys, "path", list(sys.path))
    from types import SimpleNamespace

    from fibreshell.plies import ply_stack
    from validation.cases import plies_heavy_cantilever as heavy
    from validation.ground_truth import _case

    script = _script("static_plies_active_set")
    case = _case(heavy.FILE, heavy.CELLS["coarse"])
    stack = ply_stack(case, heavy.PLIES["coarse"])
    directors = np.tile([0.0, 0.0, 1.0], (stack.mesh.n_nodes, 1))
    states = [
        SimpleNamespace(positions=stack.mesh.points - [0.0, 0.0, drop], directors=directors)
        for drop in (1.0, 1.25)
    ]
    change = script.compared_change(case, stack, *states)
    assert change["height_mm"] == pytest.approx(0.25, abs=1e-12)
    for key in ("angle_deg", "angle_whole_deg", "angle_mean_deg", "thickness"):
        assert change[key] <= 1e-9, key
    assert change["tip_before_mm"] == pytest.approx(1.0, abs=1e-12)
    assert change["tip_after_mm"] == pytest.approx(1.25, abs=1e-12)


@pytest.mark.parametrize("name", ["deck", "sag"])
def test_the_active_set_comparison_refuses_a_case_without_a_ply_stack_law(monkeypatch, name):
    """``--active-set`` builds the stack with ``static_law``: bai and heavy do, the deck and
    the sag (plies_deck_of_cards' own stacks) do not, and are refused before any solve."""
    monkeypatch.setenv("NUMBA_NUM_THREADS", os.environ.get("NUMBA_NUM_THREADS", "1"))
    monkeypatch.setattr(sys, "path", list(sys.path))
    script = _script("static_plies_active_set")
    with pytest.raises(ValueError, match="expected bai or heavy"):
        script.active_set(name, "coarse", None, 1)
