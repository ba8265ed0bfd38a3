"""Static tells the user when it accepted an increment at the round-off floor above its
tolerance (solvers/floor_acceptance.py, docs/theory.md §6.5, "The round-off floor"): counted in
info["round_off_converged"], each ratio in info["floor_accepted"], one warning per solve."""

import warnings

import numpy as np
import pytest

from elements import MindlinShell, RigidPlane
from femcore import Mesh, Model
from materials import ElasticShell
from solvers import Static

PULL, MU, PRESS = 0.2, 0.3, 1.0  # N, -, N


def pressed_and_pulled_ply():
    """A Mindlin ply 20 x 10 mm (8 x 4 cells, E = 1e4 MPa, h = 0.5 mm) on a rough rigid plane
    (mu 0.3, the automatic penalty), pressed by dead forces totalling 1 N at once and its right
    edge pulled in x by 0.2 N, ramped: below mu N, so it sticks (Coulomb)."""
    mesh = Mesh.rectangle(20.0, 10.0, nx=8, ny=4, origin=(0, 0, 0.25))
    model = Model(mesh)
    model.add(MindlinShell(ElasticShell(E=1e4, nu=0.3, thickness=0.5, density=1e-9)))
    n = len(mesh.points)
    model.contact(RigidPlane((0, 0, 0), (0, 0, 1)), friction=MU, penalty=None)
    model.force(np.arange(n), (0.0, 0.0, -PRESS / n), amplitude="step")
    right = np.flatnonzero(mesh.points[:, 0] > 20.0 - 1e-9)
    model.force(right, (PULL / len(right), 0.0, 0.0), amplitude="linear")
    return model


def test_an_acceptance_at_the_round_off_floor_above_the_tolerance_is_counted_and_told():
    # The answer still holds (Coulomb: a pull below mu N sticks, the plane's tangential force
    # equals the pull, to 1e-6 of it: the penalty's elastic slip carries no force error), and
    # the user is told of every acceptance above tol: counted, recorded, warned once with the
    # largest ratio (the reviewer measured 2.4e-4 at tol 1e-8 here, counted 0 before).
    model = pressed_and_pulled_ply()
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        result = Static(progress=False).solve(model)
    assert result.converged
    assert abs(result.tool_forces[-1][0][0]) == pytest.approx(PULL, rel=1e-6)
    tol = result.info["tol"]
    accepted = result.info["floor_accepted"]
    ratios = [ratio for _, ratio in accepted]
    assert ratios and max(ratios) > tol
    assert result.info["round_off_converged"] >= len(accepted)
    summary = result.info["round_off_accepted"]
    assert summary["count"] == len(accepted)
    assert summary["largest_ratio"] == max(ratios)
    told = [w for w in caught if "round-off floor" in str(w.message)]
    assert len(told) == 1
    assert f"{max(ratios):.3g}" in str(told[0].message)
