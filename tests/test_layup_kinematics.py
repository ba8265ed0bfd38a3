"""A layup's ply kinematics mean one shell whether the stack is written in Python
(``elements.layup.Layup(kinematics=...)``) or in a case file (``[layup] kinematics``):
"mindlin" the fabric's own laws, "mindlin-elastic" the equivalent elastic section
(README "A layup of plies", docs/theory.md §9.3b)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from elements.layup import Layup
from fibreshell.case import case_from_data
from materials import ElasticShell, Fabric
from solvers import Static

# One ply of the tension law T(eps) = C eps (eps the logarithmic strain, N/mm per unit width),
# its bending slope far below the membrane's so that the two sections differ by ~1000 x.
C, B, H = 2300.0, 72.0, 15.0
FABRIC = Fabric(thickness=H, areal_density=6.93e-9, tension=C, shear=2.2, bending=B)
LX, LY, CELLS = 40.0, 20.0, 2
STRETCH = 1.01


def _pull(layup: Layup) -> float:
    """The force (N) that holds the one-ply layup stretched uniformly to STRETCH along its
    warp (x), its left edge held in x, one node in y, every node in z."""
    model = layup.model()
    left, right = layup.mesh.nodes("left"), layup.mesh.nodes("right")
    model.fix(left, ["ux"])
    model.fix(left[:1], "uy")
    model.fix(layup.mesh.nodes(lambda x, y, z: np.ones_like(x, dtype=bool)), "uz")
    model.displace(right, ux=(STRETCH - 1.0) * LX)
    result = Static(increments=1, progress=False).solve(model)
    return float(result.reactions[right, 0].sum())


def _case_layup(kinematics: str) -> Layup:
    data = {
        "mesh": {"rectangle": {"lx": LX, "ly": LY, "nx": CELLS, "ny": CELLS // 2}},
        "part": [
            {
                "element": "mindlin",
                "material": {
                    "thickness": H,
                    "areal_density": 6.93e-9,
                    "tension": C,
                    "shear": 2.2,
                    "bending": B,
                },
            }
        ],  # fmt: skip
        "layup": {"angles": [0.0], "kinematics": kinematics},
        "solver": {"kind": "static"},
    }
    layup = case_from_data(data, "ply.toml").layup
    assert layup is not None
    return layup


@pytest.mark.parametrize("kinematics", ["mindlin", "mindlin-elastic"])
def test_a_ply_pulled_carries_the_same_force_in_python_and_in_a_case_file(kinematics):
    """The same [0] ply by each name, built both ways, pulled 1 %: the two forces agree to
    1e-12 (the same shell, the same arithmetic) and each is its section's closed form in
    uniaxial tension (no lateral contraction: the fabric's fibres are uncoupled, the elastic
    section is at nu = 0). "mindlin": the tension law's Kirchhoff stress C ln(lambda) over
    lambda, per unit width, over LY (the fabric's own laws, docs/theory.md §5.7);
    "mindlin-elastic": the section's St Venant-Kirchhoff membrane, A11 (lambda^2 - 1) / 2
    times lambda, A11 = E h of the laws' initial slopes (docs/theory.md §5.4). Tolerance
    1e-9 relative: a uniform state, Newton converged to round-off."""
    python = _pull(
        Layup(
            FABRIC,
            [0.0],
            LX,
            LY,
            cells=CELLS,
            kinematics=kinematics,
            bottom=-0.5 * H,
            centre=(0.5 * LX, 0.5 * LY),
        )  # fmt: skip
    )
    case = _pull(_case_layup(kinematics))
    assert case == pytest.approx(python, rel=1e-12)
    if kinematics == "mindlin":
        expected = LY * C * math.log(STRETCH) / STRETCH
    else:
        section = ElasticShell.equivalent(FABRIC, warp=np.array([1.0, 0.0, 0.0]))
        a11 = section.plane_stress[0, 0] * H
        expected = LY * a11 * 0.5 * (STRETCH**2 - 1.0) * STRETCH
    assert python == pytest.approx(expected, rel=1e-9)
