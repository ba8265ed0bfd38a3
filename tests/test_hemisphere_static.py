"""The hemisphere drape by Static: a quasi-static forming run, as implicit forming codes do it.

The blank, die and punch of validation/cases/hemisphere_forming.py at 8 x 8 cells (fibrous),
with a blank holder: a flat meshed ring (validation.specimens.holder_ring) fixed on the
blank's top face from 2 mm outside the die's rim outwards, zero clearance, frictionless: it
keeps the coarse flange from wrinkling up and leaves the draw-in free. Static steps the punch
in 10 increments with the viscous stabilisation c = 300 1/s^2 per unit load factor
(solvers/stabilisation.py). Reference: the pin-jointed net of the case, over the cells in the
die, with the case's tolerance at its coarse mesh (4 deg; its explicit run measured 2.93 deg at
12 cells). benchmarks/hemisphere_static.py prints the same run with its timing and the explicit
run of the same model beside it.

The case's own coarse mesh (12 x 12 cells, the same holder and solver: every increment
converges with 2 cuts, rms 2.96 deg over 86 cells; 28-63 s of CPU) is drawn by
benchmarks/hemisphere_static.py, not here: the 8-cell drape fails on the defect that run
measures (the inertia correction of solvers/inertia.py taken out: a cut, where none is
allowed) at a tenth of its CPU (benchmarks/suite_item_cpu.py).
"""

import numpy as np
import pytest
from scipy.interpolate import RegularGridInterpolator

from elements import RigidSurface
from solvers import Static
from validation.cases import hemisphere_forming as case
from validation.specimens import hemisphere_die, holder_ring

CELLS, INCREMENTS, STABILISE = 8, 10, 300.0


def held_blank(cells: int = CELLS, kinematics: str = "fibrous"):
    mesh, model = case.model(cells, kinematics, holder_force=0.0)  # its own fixed holder
    ring = holder_ring(case.DIE + 2.0, 1.7 * case.HALF, 0.5 * np.pi * case.DIE / 12.0)
    model.contact(RigidSurface(ring.with_points(ring.points + [0.0, 0.0, case.THICKNESS])))
    return mesh, model


@pytest.mark.slow
def test_static_drapes_the_hemisphere_as_the_pin_jointed_net():
    """Every increment converges, none cut (measured Newton iterations 8, 7, 8, 9, 15, 10, 11,
    5, 5, 6 with the tool contacts' sets predicted on each step's linear model,
    elements/contact_set_model.py; before, 7, 10, 13, 18, 14, 29, 18, 11, 12, 4 with the
    contacts' default release, elements/contact.py, and the meshed
    tools' normal turning round their edges in the tangent (16 in the seventh without), 42 in
    the sixth
    without it; without the inertia correction of solvers/inertia.py the sixth increment met 7
    or more negative eigenvalues, was cut once and its attempt took 98 iterations; 8-25 s on
    this machine as it is loaded); the dashpots dissipate less than 5 %
    of the strain energy (measured 0.6 %); the rms of shear - net over the cells in the die
    is within the case's coarse tolerance (measured 3.51 deg over 26 cells)."""
    mesh, model = held_blank()
    result = Static(increments=INCREMENTS, stabilise=STABILISE, progress=False).solve(model)
    assert result.converged
    assert max(result.info["iterations_per_increment"]) <= 50
    assert result.info["cuts"] == 0
    assert_drapes_as_the_net(mesh, result, 20)


@pytest.mark.slow
def test_static_drapes_the_hemisphere_with_a_smoothed_die_and_the_tools_followed():
    """The same run with the die's facets smoothed (``RigidSurface(smooth=True)``) and the
    punch's nodes carried at each increment's start (``Static(follow_tools=True)``): every
    increment converges, none cut (measured Newton iterations 9, 14, 15, 14, 65, 10, 11, 6,
    6, 3 with the tool contacts' sets predicted; before, 8, 17, 17, 21, 16, 29, 23, 12,
    11, 7 with the smoothed normal's turn in the contact tangent, 8, 17, 17, 21, 16, 31, 24,
    12, 11, 4 without; 10 s CPU at load 6), and the drape is the net's within the case's
    coarse tolerance (measured 2.1 deg, as without the options: the options change the path,
    not the equilibrium)."""
    mesh, model = held_blank()
    model.interactions[0].tool = RigidSurface(
        hemisphere_die(case.DIE, 1.7 * case.HALF, rings=48), smooth=True
    )
    solver = Static(increments=INCREMENTS, stabilise=STABILISE, follow_tools=True, progress=False)
    result = solver.solve(model)
    assert result.converged
    assert result.info["cuts"] == 0
    assert_drapes_as_the_net(mesh, result, 20)


@pytest.mark.slow
def test_static_drapes_the_mindlin_blank_at_the_fibrous_blanks_stabilisation():
    """The Mindlin blank (ElasticShell.equivalent), 8 cells, the same holder, c = 300: every
    increment converges (measured 3-186 Newton iterations per increment, 4 cuts, the
    increments whose attempt with predicted contact sets failed tried again without them,
    solvers/newton.py; 4-154 and 5-9 cuts before the tool contact's sets were predicted; no
    step on a shifted tangent, about 35 s; it needed c = 3000 on older code) and the dashpots
    dissipate less than 5 % of the strain energy (measured 0.25 %). Its shear is not checked:
    its soft membrane leaves only 7 cells on the bowl (benchmarks/hemisphere_static.py)."""
    _, model = held_blank(kinematics="mindlin")
    result = Static(increments=INCREMENTS, stabilise=STABILISE, progress=False).solve(model)
    assert result.converged
    assert result.info["stabilisation"]["dissipated_over_strain_energy"] < 0.05


def assert_drapes_as_the_net(mesh, result, cells_in_die: int) -> None:
    """The dashpots dissipated less than 5 % of the strain energy, and the rms of shear - net
    over the cells in the die (at least ``cells_in_die`` of them) is within the case's coarse
    tolerance."""
    report = result.info["stabilisation"]
    assert report["dissipated_over_strain_energy"] < 0.05
    net = case.fishnet_on_sphere(
        case.DIE - 0.5 * case.THICKNESS,
        case.NET_CELL,
        int(0.5 * np.pi * case.DIE / case.NET_CELL),
    )
    interpolate = RegularGridInterpolator((net["u"], net["v"]), net["shear"], bounds_error=False)
    net_shear = interpolate(mesh.points[mesh.triangles].mean(axis=1)[:, :2])
    x = result.positions
    # In the die: within 1 mm of the mid-surface's sphere, below z = -5 mm. The punch presses
    # the stiffening shear law's cells 0.4-0.5 mm off that sphere (into the punch's penalty
    # springs by 0.06 mm at most), so the explicit case's 0.5 mm band would miss half of them.
    on_bowl = (np.abs(np.linalg.norm(x, axis=1) - (case.DIE - 0.5 * case.THICKNESS)) < 1.0) & (
        x[:, 2] < -5.0
    )
    in_die = on_bowl[mesh.triangles].all(axis=1) & np.isfinite(net_shear)
    assert in_die.sum() >= cells_in_die
    error = np.degrees(case.blank_shear(mesh, x)[in_die] - net_shear[in_die])
    assert np.sqrt(np.mean(error**2)) < case.RMS_TOLERANCE_DEG["coarse"]
