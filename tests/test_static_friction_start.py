"""Static with friction from a start where the surfaces touch with no pressure
(solvers/stick_start.py): a [0/90] pair of plies, the bottom one held, the top one pressed by
P = 1 N and pulled along x by T = 0.15 N < mu P (mu 0.3). Coulomb: the top ply sticks and the
bottom ply's supports carry T. Loaded together, Newton's first iterate had no stick stiffness
(the ply contact's stick spring, the normal law's W''(g), is 0 at zero penetration) and the
solve stopped in its first increment; the increment is now tried again with stiff stick
springs first, then with the normal law, and holds the ply, as pressing it first does. Pulled
past mu P the ply has no static equilibrium, and the stop says so
(solvers/stop_diagnosis.py ``FRICTION_AT_START``)."""

from __future__ import annotations

import numpy as np
import pytest

from elements.layup import Layup
from materials import Fabric
from solvers import Static
from solvers.common import ConvergenceError

PLY = Fabric(thickness=0.3, areal_density=2.85e-10, tension=60.0, shear=0.2, bending=0.375)
MU, PRESS, PULL = 0.3, 1.0, 0.15  # -, N, N


def _pair(kinematics, pull=PULL):
    layup = Layup(PLY, (0.0, 90.0), 20.0, cells=2, friction=MU, kinematics=kinematics)
    model = layup.model()
    bottom, top = layup.ply_nodes
    model.fix(bottom)
    x = layup.mesh.points
    tri = layup.mesh.triangles[layup.ply_cells[1]]
    area = 0.5 * np.abs(np.cross(x[tri[:, 1]] - x[tri[:, 0]], x[tri[:, 2]] - x[tri[:, 0]])[:, 2])
    lumped = np.bincount(tri.ravel(), np.repeat(area / 3.0, 3), layup.mesh.n_nodes)
    share = lumped[top] / lumped[top].sum()
    for node, s in zip(top, share):
        model.force([int(node)], (0.0, 0.0, -PRESS * s), amplitude="step")
        model.force([int(node)], (pull * s, 0.0, 0.0), amplitude="linear")
    return layup, model


@pytest.mark.parametrize("first", [False, True], ids=["together", "pressed-first"])
@pytest.mark.parametrize("kinematics", ["fibrous", "mindlin"])
def test_a_ply_pressed_and_pulled_below_mu_p_sticks(kinematics, first):
    layup, model = _pair(kinematics)
    result = Static(increments=4, progress=False, seek_stable=False, step_loads_first=first).solve(
        model
    )
    bottom, top = layup.ply_nodes
    # statics: the supports carry the pull and the press (the Newton tolerance far below)
    assert result.reactions[bottom].sum(axis=0) == pytest.approx([-PULL, 0.0, PRESS], abs=1e-8)
    # Coulomb, T < mu P: stuck, the top ply moved by its stick springs' give alone, a few
    # micrometres (measured 0.94 um fibrous, 0.27 um Mindlin, either way); under T > mu P no
    # state of the ply would be in equilibrium
    assert np.all(np.abs(result.displacements[top, 0]) < 1e-2)


def test_a_ply_pulled_past_mu_p_has_no_static_equilibrium_and_the_stop_says_so():
    _, model = _pair("mindlin", pull=2.0 * MU * PRESS)
    with pytest.raises(ConvergenceError, match=r"no static equilibrium.*step_loads_first=True"):
        Static(increments=2, progress=False, seek_stable=False, max_cuts=1).solve(model)
