"""The hemisphere forming case (validation/cases/hemisphere_forming.py): its observed orders
over three meshes, and its coarse blank formed to the end against the net."""

import math
from types import SimpleNamespace

import numpy as np
import pytest

from solvers.quasi_static import KINETIC_BOUND
from validation.cases import hemisphere_forming as case


def fake_run(cells: int, value: float) -> dict:
    """A ``run`` record of ``cells`` whose three measured quantities are ``value``."""
    return {
        "cells": cells,
        "result": SimpleNamespace(converged=True),
        **{key: value for key in case.ORDER_QUANTITIES},
    }


def test_the_orders_recover_a_second_order_sequence_over_the_three_meshes():
    """f(h) = 3 + 0.01 h^2 on the blank's meshes h = 200 / n: order 2, extrapolated 3."""
    runs = [fake_run(n, 3.0 + 0.01 * (200.0 / n) ** 2) for n in (12, 20, 32)]
    records = case.orders({"fibrous": runs})
    assert len(records) == len(case.ORDER_QUANTITIES)
    for record in records:
        assert record.cells == (12, 20, 32)
        assert record.sizes == pytest.approx((200 / 12, 10.0, 6.25))
        assert record.order == pytest.approx(2.0, rel=1e-9)
        assert record.extrapolated == pytest.approx(3.0, rel=1e-9)


def test_an_oscillating_sequence_has_no_order_and_fails_its_check(monkeypatch):
    runs = [fake_run(n, v) for n, v in zip((12, 20, 32), (3.0, 2.0, 2.5))]
    records = case.orders({"fibrous": runs})
    assert all(math.isnan(record.order) for record in records)
    monkeypatch.setattr(case, "ORDER_TOLERANCE", {"fibrous rms_deg": 0.05})
    (verdict,) = case.order_checks(records)
    assert not verdict.passed


@pytest.mark.slow
def test_the_coarse_blank_forms_to_the_end_along_the_net_and_comes_to_rest():
    """12 x 12 cells, fibrous, about 16000 steps (31-35 s of CPU). Measured: the rms shear error
    against the net 2.90 deg; the kinetic energy 0.012 of the work at the end of the stroke
    (the wrinkles of the flange snap through half way down: a burst to 0.24 of the work)."""
    record = case.run(12, "fibrous")
    result = record["result"]
    assert result.converged
    assert record["rms_deg"] < case.RMS_TOLERANCE_DEG["coarse"]
    assert record["kinetic_over_work"] < 0.5 * KINETIC_BOUND
    assert result.info["quasi_static"]["kinetic_over_work_final"] == record["kinetic_over_work"]
    assert record["holder_travel_mm"] is None  # the case runs without a holder


def test_the_fine_resolution_reports_and_checks_the_orders_of_its_three_meshes(monkeypatch):
    """compute("fine") runs the two coarser meshes too (here: flat blanks standing in for the
    runs, their numbers f = f0 + C h^p) and reports an order per kinematics and quantity; the
    quantities ORDER_TOLERANCE names are checked."""
    from femcore import Mesh

    def flat_run(cells, kinematics, net=None):
        mesh = Mesh.rectangle(200.0, 200.0, nx=cells, ny=cells, origin=(-100.0, -100.0, 0.0))
        h = 200.0 / cells
        result = SimpleNamespace(
            converged=True,
            positions=mesh.points,
            steps=10,
            wall_time=1.0,
        )
        return {
            "cells": cells,
            "mesh": mesh,
            "result": result,
            "shear": np.zeros(len(mesh.triangles)),
            "in_die": np.zeros(len(mesh.triangles), dtype=bool),
            "compared": 0,
            "rms_deg": 2.0 + 0.001 * h**2,
            "largest_shear_deg": 0.0,
            "draw_in_mm": 50.0 - 0.01 * h**2,
            "punch_force_N": 75.0 - 0.5 * h,
            "holder_travel_mm": None,
            "kinetic_over_work": 0.01,
            "largest_kinetic_over_work": 0.05,
            "cost": {"wall_s": 1.0, "cpu_s": 1.0, "load": (1.0, 1.0)},
        }

    monkeypatch.setattr(case, "run", flat_run)
    outcome = case.compute("fine")
    assert {(o.kinematics, o.cells) for o in outcome.orders} == {
        ("fibrous", (12, 20, 32)),
        ("mindlin", (12, 20, 32)),
    }
    draw_in = next(
        o for o in outcome.orders if o.kinematics == "fibrous" and o.quantity.startswith("draw")
    )
    assert draw_in.order == pytest.approx(2.0, rel=1e-9)
    ordered = [c for c in outcome.checks if "observed order" in c.name]
    assert len(ordered) == len(case.ORDER_TOLERANCE) and all(c.passed for c in ordered)
    assert "fibrous n = 12: runtime" in outcome.parameters
