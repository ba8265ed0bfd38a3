"""The Mindlin shell's scaled rotary inertia (docs/theory.md §6.2 B2): held to the membrane's
step on the element's own eigenproblem, and without effect on statics."""

from __future__ import annotations

import numpy as np
import pytest

from elements import MindlinShell
from elements.rotary_scaling import membrane_held_factors
from femcore import Mesh, Model
from materials import ElasticShell, Fabric
from solvers import CentralDifference, Static

# The two-ply hemisphere's ply (validation/studies/hemisphere_plies_setup.py: a G986-like
# fabric, 0.3 mm, 285 g/m^2) on its 25-mm cells.
PLY = Fabric(thickness=0.3, areal_density=2.85e-10, tension=60.0, shear=0.2, bending=0.375)


def _block(material, rotary_scaling=True, cell=25.0):
    mesh = Mesh.rectangle(2 * cell, 2 * cell, nx=2, ny=2)
    model = Model(mesh)
    model.add(MindlinShell(material, rotary_scaling=rotary_scaling))
    return next(p for p in model.compile().parts if hasattr(p, "rotary_factor"))


def _steps(block, factor=1.0):
    """Each cell's critical step 2 / omega_max, s, from the element eigenproblem (B4) with the
    block's j times ``factor``."""
    x0, v0 = block._reference_cells()
    own = block.rotary_factor.copy()
    try:
        block.rotary_factor = own * factor
        return 2.0 / np.sqrt(block.element_omega2(x0, v0))
    finally:
        block.rotary_factor = own


def _blocks_top(block):
    """(the rotations', the translations') largest omega^2 of each cell, each block of the
    element's eigenproblem alone (the other's degrees of freedom held)."""
    x0, v0 = block._reference_cells()
    k = block._cell_tangent(x0, v0, slice(None)).reshape(-1, 18, 18)
    k = 0.5 * (k + np.swapaxes(k, 1, 2))
    share = block.material.areal_density * block.reference_area / 3.0
    rot, tr = np.array([3, 4, 5, 9, 10, 11, 15, 16, 17]), np.array([0, 1, 2, 6, 7, 8, 12, 13, 14])
    top = []
    for idx, mass in ((rot, share * block.rotary_factor), (tr, share)):
        sub = k[:, idx][:, :, idx] / mass[:, None, None]
        top.append(np.linalg.eigvalsh(sub)[:, -1])
    return top


@pytest.mark.parametrize("section", ["equivalent", "fabric"])
def test_the_scaled_rotations_keep_the_membranes_step(section):
    # B2 asks that a thin shell keep the membrane's step: the element's step with the scaled
    # j within a few per cent of its step with the rotations held (j x 100: the step no
    # longer moves with j, to 1e-6). The closed form j = kappa (1 - nu) L_e^2 / 16 alone gave
    # the hemisphere's Mindlin plies (ElasticShell.equivalent) 0.47 of it: the MITC3
    # element's rotational omega^2 is three times the nodal estimate kappa G / (2 rho j), its
    # membrane's 3 c^2 / L_e^2 where B2 reads 4 (nu = 0, G12 near nothing). Asked: 0.95
    # (STEP_SHARE), held to 0.4 % by the bisection; the test asks 0.94.
    material = ElasticShell.equivalent(PLY) if section == "equivalent" else PLY
    block = _block(material, "element")
    scaled, held = _steps(block), _steps(block, 100.0)
    assert np.all(scaled >= 0.94 * held)
    assert np.all(scaled <= held * (1 + 1e-12))
    rotations, translations = _blocks_top(block)
    assert np.all(rotations <= translations)  # the rotations' own top below the membrane's
    closed = _block(material, "closed")
    assert np.all(_steps(closed) < 0.6 * held)  # the closed form alone: 0.47 (0.51 fabric)
    # the default (True) is the closed form, on either section: results as they were
    assert np.array_equal(_block(material).rotary_factor, closed.rotary_factor)


def test_an_elastic_section_keeps_the_closed_form_unless_asked():
    # An aluminium sheet 1 mm thick on 25-mm cells: by default (True) j is B2's closed form
    # to the bit (an ElasticShell's results as they were). There too the closed form gives
    # the element less than the membrane's step (the rotations' omega^2 three times the
    # nodal estimate: 0.60 of the held step); "element" holds it to 0.95.
    sheet = ElasticShell(E=70000.0, nu=0.33, thickness=1.0, density=2.7e-9)
    block = _block(sheet)
    closed = np.maximum(1.0 / 12.0, sheet.shear_factor * (1 - 0.33) * block._altitude() ** 2 / 16)
    assert np.array_equal(block.rotary_factor, closed)
    held = _steps(block, 100.0)
    assert np.all(_steps(block) < 0.9 * held)
    assert np.all(_steps(_block(sheet, "element")) >= 0.94 * held)
    with pytest.raises(ValueError, match="rotary_scaling"):
        MindlinShell(sheet, rotary_scaling="yes")


def test_membrane_held_factors_checks_its_share():
    with pytest.raises(ValueError, match="step_share"):
        membrane_held_factors(np.zeros((1, 18, 18)), np.ones(1), np.ones(1), step_share=1.5)


@pytest.mark.parametrize("section", ["equivalent", "fabric"])
def test_statics_does_not_see_the_rotary_inertia(section):
    # j is a mass: a Static solve (no inertia) of a cantilever strip bent by a tip load gives
    # the same bits with j scaled and with the physical h^2 / 12.
    material = ElasticShell.equivalent(PLY) if section == "equivalent" else PLY
    answers = []
    for scaling in (True, False):
        mesh = Mesh.rectangle(100.0, 10.0, nx=8, ny=1)
        model = Model(mesh)
        model.add(MindlinShell(material, rotary_scaling=scaling))
        model.fix("left")
        tip = mesh.nodes("right")
        model.force(tip, (0.0, 0.0, 2e-3 / len(tip)), amplitude="linear")
        answers.append(Static(increments=2, progress=False).solve(model).positions)
    assert np.array_equal(answers[0], answers[1])
    assert answers[0][:, 2].max() > 1.0  # it did bend


@pytest.mark.slow
@pytest.mark.parametrize("scaling", ["closed", "element"])
def test_a_quasi_static_explicit_fabric_cantilever_ends_at_its_static_solution(scaling):
    # A Mindlin fabric cantilever (50 x 10 mm, 4 x 1 cells) under a tip load ramped smoothly
    # over about five periods of its first bending mode (omega_1 = 3.516 sqrt(B / (rho_A
    # L^4)) = 51 rad/s) with mass-proportional damping 50/s ends where the Static solve does:
    # the rotary inertia shapes the path, not the end. Measured 0.17 % ("element") against
    # Static's 2.455 mm tip deflection; tolerance 1 %, a residual motion of that size being
    # visible as kinetic energy (the smooth ramp starts and ends at rest). The larger j runs
    # the membrane's step: fewer steps than the closed form.
    fabric = Fabric(thickness=0.3, areal_density=2.85e-10, tension=6.0, shear=0.2, bending=0.375)

    def strip(amplitude):
        mesh = Mesh.rectangle(50.0, 10.0, nx=4, ny=1)
        model = Model(mesh)
        model.add(MindlinShell(fabric, rotary_scaling=scaling))
        model.fix("left")
        tip = mesh.nodes("right")
        model.force(tip, (0.0, 0.0, 2.25e-4 / len(tip)), amplitude=amplitude)
        return model, tip

    model, tip = strip("linear")
    static = Static(increments=2, progress=False).solve(model).positions[tip, 2].mean()
    model, tip = strip("smooth")
    run = CentralDifference(duration=0.6, damping=50.0, progress=False).solve(model)
    assert run.positions[tip, 2].mean() == pytest.approx(static, rel=1e-2)
    assert static == pytest.approx(2.455, rel=1e-3)  # the strip bent (B = 0.375 N mm)
