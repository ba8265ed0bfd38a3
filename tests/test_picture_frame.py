"""The picture-frame test with non-linear shear laws, by Static at its default settings, to 55 deg.

A square of fabric, side L = 100 mm, fibres along its sides (6 x 6 fibre-aligned cells), its
corner at the origin pinned and the opposite corner pulled along the diagonal; the sides stay
in the plane (the frame's clamps), the rest of the sheet is free in three dimensions. With
quasi-inextensible fibres (1e6 N/mm against shear moments of about 1 N/mm) the sheet shears
uniformly, and the power balance F dD = M_s(gamma) L^2 dgamma, with the diagonal
D = 2 L cos(pi/4 - gamma/2), gives the frame force F = M_s(gamma) L / sin(pi/4 - gamma/2)
(docs/theory.md §3). The pull that takes gamma to 55 deg is D(55 deg) - sqrt(2) L.

Past about 25 deg the flat sheet is a saddle of the discrete energy: the shear moment's
geometric stiffness is indefinite out of plane, and the tangent has 1 to 2 negative
eigenvalues. No push along those modes lowers the energy (solvers.stability.push_descends),
so Static keeps the flat sheet and follows it by plain Newton: 5 Newton iterations per
increment up to about 35 deg, then 6 (7 in the last increment of the polynomial law), over the
default 10 increments. Turning the steps downhill along those modes instead
stopped both laws near 40 deg.
"""

import numpy as np
import pytest

from elements import FibrousShell
from femcore import Mesh, Model
from materials import Fabric, ShearLaw
from solvers import Static

SIDE, CELLS, ANGLE = 100.0, 6, np.radians(55.0)

LAWS = {
    # Boisse-group odd polynomial: softening to about 35 deg, then stiffening (N/mm).
    "polynomial": ShearLaw.polynomial(0.4, -0.6, 0.5),
    # A tabulated law stiffening towards locking (rad, N/mm).
    "table": ShearLaw.table(
        [0, 0.2, 0.4, 0.6, 0.8, 1.0, 1.2], [0, 0.06, 0.1, 0.14, 0.22, 0.4, 0.8]
    ),
}


def frame_force(law, gamma):
    """F = M_s(gamma) L / sin(pi/4 - gamma/2), N: the power balance of the frame."""
    return float(law.value(gamma)) * SIDE / np.sin(np.pi / 4 - gamma / 2)


@pytest.fixture(scope="module", params=sorted(LAWS))
def sheared(request):
    law = LAWS[request.param]
    mesh = Mesh.rectangle(SIDE, SIDE, CELLS, CELLS)
    fabric = Fabric(thickness=0.3, areal_density=2.85e-10, tension=1e6, shear=law, bending=7.5)
    model = Model(mesh)
    model.add(FibrousShell(fabric))
    x, y = mesh.points[:, 0], mesh.points[:, 1]
    origin = int(np.flatnonzero((x == 0.0) & (y == 0.0))[0])
    pulled = int(np.flatnonzero((x == SIDE) & (y == SIDE))[0])
    sides = np.flatnonzero((x == 0.0) | (y == 0.0) | (x == SIDE) | (y == SIDE))
    model.fix(sides, dofs=("uz",))
    model.fix([origin])
    pull = 2 * SIDE * np.cos(np.pi / 4 - ANGLE / 2) - np.sqrt(2) * SIDE
    model.displace([pulled], ux=pull / np.sqrt(2), uy=pull / np.sqrt(2))
    result = Static(progress=False).solve(model)
    return law, result, pulled


def test_the_frame_reaches_55_degrees_with_the_sheet_flat_and_uniformly_sheared(sheared):
    _, result, _ = sheared
    assert result.frames[-1].load_factor == pytest.approx(1.0)
    gamma = np.abs(result.frames[-1].fields["triangle"]["shear_angle_deg"])
    np.testing.assert_allclose(gamma, 55.0, atol=0.01)
    assert np.abs(result.displacements[:, 2]).max() < 1e-6
    assert result.info["branch_switches"] == []
    assert max(result.info["iterations_per_increment"]) <= 7


def test_the_flat_sheared_sheet_is_a_saddle_kept_not_left(sheared):
    _, result, _ = sheared
    assert max(result.info["negative_eigenvalues"]) >= 1
    assert result.info["saddles_kept"]


def test_the_frame_force_at_55_degrees_is_the_shear_laws_closed_form(sheared):
    law, result, pulled = sheared
    diagonal = np.array([1.0, 1.0, 0.0]) / np.sqrt(2)
    force = result.frames[-1].reactions[pulled] @ diagonal
    assert force == pytest.approx(frame_force(law, ANGLE), rel=2e-4)
