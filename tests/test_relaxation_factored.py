"""Dynamic relaxation with the factored stiffness as its masses (solvers/factored_masses.py,
docs/theory.md §6.4a, "Factored masses"): the bound it keeps, and the stiff-fibre strip it
relaxes where the diagonal masses stalled."""

from pathlib import Path

import numpy as np
import pytest
import scipy.linalg

from elements import FibrousShell
from femcore import Mesh, Model
from fibreshell.case import load_case
from materials import Fabric
from solvers import DynamicRelaxation, Static
from solvers.factored_masses import FactoredMasses, factored_fallback
from solvers.fictitious_masses import GershgorinMasses, PhysicalMasses

ROOT = Path(__file__).resolve().parents[1]


def bent_strip():
    """A 60 x 10 mm fibrous strip (8 x 1 cells, fibres 1000 N/mm, bending 1 N mm) clamped at
    x = 0, compiled, and a state bent into a quarter circle about y with its directors on
    the normals: a configuration far from the flat one, as a relaxation meets on its way."""
    mesh = Mesh.rectangle(60.0, 10.0, nx=8, ny=1)
    model = Model(mesh)
    fabric = Fabric(thickness=0.5, areal_density=1e-10, tension=1000.0, shear=0.5, bending=1.0)
    model.add(FibrousShell(fabric, clamped="left"))
    model.fix("left")
    compiled = model.compile()
    x, y = mesh.points[:, 0], mesh.points[:, 1]
    radius = 60.0 / (0.5 * np.pi)
    angle = x / radius
    positions = np.column_stack([radius * np.sin(angle), y, -radius * (1.0 - np.cos(angle))])
    directors = np.column_stack([np.sin(angle), np.zeros_like(x), np.cos(angle)])
    state = compiled.initial_state()
    from dataclasses import replace

    return compiled, replace(state, positions=positions, directors=directors)


def test_every_eigenvalue_of_the_factored_masses_against_the_stiffness_is_within_the_limit():
    # The bound of the module docstring: K <= blockdiag(A + D_B + E, G_theta) as quadratic
    # forms, so every eigenvalue of M^-1 K is at most (2 s)^2 (here 3.24 at s = 0.9), the
    # central-difference limit at dt = 1, as for the Gershgorin masses. Checked on the dense
    # generalised eigenproblem of the free DOFs (in the node axes of the masses) at a bent
    # state, to 1e-9 of the limit (round-off of the eigensolver).
    compiled, state = bent_strip()
    base = GershgorinMasses(compiled, 0.9)
    factored = FactoredMasses(base)
    mass, inertia, dt = factored(state, 1.0)
    assert dt == 1.0
    k, _, _ = base.stiffness(state)
    dofs = compiled.dofs
    free = dofs.free_slots
    k = k[free][:, free].toarray()
    k = 0.5 * (k + k.T)
    m = np.zeros_like(k)
    translation = free % 5 < 3
    node = free // 5
    places = 3 * node + free % 5
    where = {int(p): i for i, p in enumerate(places[translation])}
    rows = np.flatnonzero(translation)
    index = np.array([where[int(p)] for p in mass.slots])
    m[np.ix_(rows[index], rows[index])] = mass.matrix.toarray()
    rotation = np.flatnonzero(~translation)
    m[rotation, rotation] = inertia[node[rotation]]
    largest = scipy.linalg.eigh(k, m, eigvals_only=True).max()
    assert largest <= (2 * 0.9) ** 2 * (1 + 1e-9)
    # and the diagonal masses' slowest mode is far slower: the preconditioning this is for
    mass_g, inertia_g, _ = base(state, 1.0)
    diagonal = np.zeros(len(free))
    diagonal[rows] = mass_g.values.ravel()[places[translation]]
    diagonal[rotation] = inertia_g[node[rotation]]
    spectrum = scipy.linalg.eigh(k, m, eigvals_only=True)
    spectrum_g = scipy.linalg.eigh(k, np.diag(diagonal), eigvals_only=True)
    positive, positive_g = spectrum[spectrum > 0], spectrum_g[spectrum_g > 0]
    assert positive.max() / positive.min() < positive_g.max() / positive_g.min()


def test_only_the_gershgorin_masses_fall_back_to_the_factored_ones():
    compiled, _ = bent_strip()
    base = GershgorinMasses(compiled, 0.9)
    assert isinstance(factored_fallback(base), FactoredMasses)
    assert factored_fallback(FactoredMasses(base)) is None
    assert factored_fallback(PhysicalMasses(compiled, 0.9)) is None


def test_an_increment_stalled_with_the_gershgorin_masses_goes_on_with_the_factored_ones():
    """The strip of cases/strip_over_cylinder.toml without its cylinder, 10 cells along: a
    heavy cantilever. With a watch of 1000 iterations the Gershgorin masses stall (before:
    ConvergenceError "stalled"; they converge in 19 487 iterations without the watch), and the
    increment goes on once with the factored masses to convergence (6265 iterations measured).
    Reference: the heavy elastica (validation/references/elastica.py heavy_cantilever, tip
    (45.16, -62.19) mm) within 1 mm, the 10-cell mesh's own gap (0.33 and 0.65 mm, the same
    with the Gershgorin masses alone to 0.01 mm)."""
    from fibreshell.case import case_from_data, read_case_data
    from fibreshell.sweep import apply_overrides
    from validation.references.elastica import heavy_cantilever

    path = ROOT / "cases" / "strip_over_cylinder.toml"
    tables, _ = apply_overrides(read_case_data(path), {"mesh.rectangle.nx": 10})
    del tables["contact"]
    case = case_from_data(tables, path)
    solver = DynamicRelaxation(plateau_iterations=1000, progress=False)
    result = solver.solve(case.model())
    assert result.converged and result.info["factored_after_stall"] == 1
    reference = heavy_cantilever(100.0, 1.66e-9 * 9810.0, 0.833)
    tip = result.positions[case.mesh.nodes("tip")]
    np.testing.assert_allclose(tip[:, 0], reference["tip_x"], atol=1.0)
    np.testing.assert_allclose(tip[:, 2], 20.5 - reference["tip_deflection"], atol=1.0)


@pytest.mark.slow
def test_the_shipped_strip_over_a_cylinder_relaxes_at_the_defaults():
    """cases/strip_over_cylinder.toml (50 cells) by DynamicRelaxation at its defaults. Before:
    the Gershgorin masses' slowest mode (omega_max / omega_min = 1.6e4, the fibres against
    the bending) outlasted the progress watch and the run stopped as stalled (ConvergenceError
    at 40 000 iterations); now it goes on from there with the factored masses. References:
    Static on the same case (its own solver, 10 increments), every node within 2e-3 mm (the
    relaxation stops at 1e-4 of the forces; the 20-cell test of
    tests/test_relaxation_contact.py measured 6.2e-4), and the heavy elastica
    over the cylinder (validation/references/elastica.py) for the tip, 0.3 mm as
    tests/test_case_files.py."""
    from validation.references.elastica import heavy_strip_over_cylinder

    case = load_case(ROOT / "cases" / "strip_over_cylinder.toml")
    relaxed = DynamicRelaxation(progress=False).solve(case.model())
    assert relaxed.converged
    assert relaxed.steps <= ITERATIONS
    static = Static(increments=10, progress=False).solve(case.model())
    np.testing.assert_allclose(relaxed.positions, static.positions, atol=2e-3)
    reference = heavy_strip_over_cylinder(100.0, 1.66e-9 * 9810.0, 0.833, 20.5)
    tip = relaxed.positions[case.mesh.nodes("tip")]
    np.testing.assert_allclose(tip[:, 0], reference["tip_x"], atol=0.3)
    np.testing.assert_allclose(tip[:, 2], reference["tip_z"], atol=0.3)


#: The iterations the shipped strip may take: 68 433 measured (the Gershgorin masses up to the
#: watch's stall at 40 000, the factored ones after), with a margin of 17 % for the round-off
#: of another machine; before, the Gershgorin masses alone took 127 814 without the watch.
ITERATIONS = 80_000
