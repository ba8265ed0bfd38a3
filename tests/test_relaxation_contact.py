"""Dynamic relaxation with contact: a node about to touch a tool carries its contact spring in
its fictitious mass (solvers/fictitious_masses.py, docs/theory.md §6.4a "Contact"), so that
the penalty it meets before the next estimate is within the stability limit of the nominal
step dt = 1; a node far from every tool keeps the mass its elements give it."""

from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from elements import FibrousShell, RigidPlane
from femcore import Mesh, Model
from fibreshell.case import case_from_data, read_case_data
from fibreshell.sweep import apply_overrides
from materials import Fabric
from solvers import DynamicRelaxation, Static
from solvers.fictitious_masses import GershgorinMasses

ROOT = Path(__file__).resolve().parents[1]
H = 1.0  # mm, the fabric's thickness
LOAD = 1.0  # N, pressing the plate onto the die


def plate_above_a_die(gap: float, tool: bool = True) -> Model:
    """A 20 x 20 mm fibrous plate (Bai's fabric scale: 1000 N/mm tension, 0.833 N mm
    bending), ``gap`` mm above a flat rigid die (its underside, h / 2 below the mid-surface),
    pressed by LOAD spread equally over its 25 nodes; the in-plane translations held, so
    that only the die holds it along z. ``tool`` False: no die (the same plate)."""
    flat = Mesh.rectangle(20.0, 20.0, nx=4, ny=4)
    mesh = flat.with_points(flat.points + [0.0, 0.0, 0.5 * H + gap])
    model = Model(mesh)
    fabric = Fabric(thickness=H, areal_density=1e-9, tension=1000.0, shear=1.0, bending=0.833)
    model.add(FibrousShell(fabric))
    nodes = np.arange(mesh.n_nodes)
    model.fix(nodes, ("ux", "uy"))
    if tool:
        model.contact(RigidPlane((0.0, 0.0, 0.0), (0.0, 0.0, 1.0)))
    model.force(nodes, (0.0, 0.0, -LOAD / mesh.n_nodes))
    return model


def test_a_fabric_plate_pressed_onto_a_flat_die_by_relaxation_bears_the_load_on_the_die():
    """The plate falls 0.1 mm onto the die and rests on it: the die bears the load, -LOAD
    along z (equilibrium of the whole plate; the in-plane supports carry nothing along z).
    Tolerance 2e-4 of LOAD: the residual the relaxation leaves, summed over the 25 nodes, is
    at most sqrt(25) ||r|| <= 5 tol F_ref, with tol = 1e-4 and F_ref about ||F_ext|| = LOAD
    / 5 (measured 2.8e-5). Within 1000 iterations (113 measured); the masses estimated
    before it touched, without the penalty (0.1 m (2 / dt_elements)^2, hundreds of times
    what those masses bear at dt = 1), left it chattering on the die: no convergence in
    20 000 iterations (ratio 0.93)."""
    result = DynamicRelaxation(max_iterations=1000, progress=False).solve(plate_above_a_die(0.1))
    assert result.converged
    np.testing.assert_allclose(result.frames[-1].tool_forces, [[0.0, 0.0, -LOAD]], atol=2e-4)
    gaps = result.field("contact_gap")
    assert (gaps < 0.0).all() and (gaps > -1e-3).all()  # every node on the die, just into it


def test_a_node_far_from_every_tool_keeps_the_mass_its_elements_give_it():
    """5 mm above the die (50 times the reach REACH_SHARE L_e = 0.02 x 5 mm), the plate's
    fictitious masses and inertia are those of the same plate without a die, to rounding
    (1e-14: the die's tangent, zero there, changes the order of the sparse sums): a node
    pays nothing for a tool it cannot meet before it has moved 5 mm; and the watch
    asks for new masses once a node has moved that far (``approached``), not before."""
    masses = []
    for tool in (True, False):
        compiled = plate_above_a_die(5.0, tool).compile()
        state = compiled.initial_state()
        estimate = GershgorinMasses(compiled, 0.9)
        mass, inertia, _ = estimate(state, 1.0)
        masses.append((mass.values, inertia))
        if tool:
            down = state.positions - [0.0, 0.0, 4.99]
            assert not estimate.approached(replace(state, positions=down))
            assert estimate.approached(replace(state, positions=down - [0.0, 0.0, 0.01]))
    np.testing.assert_allclose(masses[0][0], masses[1][0], rtol=1e-14, atol=0.0)
    np.testing.assert_allclose(masses[0][1], masses[1][1], rtol=1e-14, atol=0.0)


@pytest.mark.slow
def test_the_shipped_strip_over_a_cylinder_relaxes_to_the_equilibrium_static_reaches():
    """cases/strip_over_cylinder.toml by relaxation, at 20 cells along (``mesh.rectangle.nx``; at
    the case's 50, omega_max / omega_min of its fictitious masses is 1.60e4 at the equilibrium,
    the stiff fibres against the bending, contact or not, and the Gershgorin masses alone stall
    on the progress watch: docs/theory.md §6.4a; the default goes on with the factored masses
    there, tests/test_relaxation_factored.py): every node within 2e-3 mm of Static's equilibrium
    on the same mesh (measured 6.2e-4: the relaxation stops at 1e-4 of the forces) and the tip
    within 0.3 mm of the heavy elastica (validation/references/elastica.py, as
    tests/test_case_files.py; 0.10 mm at 20 cells), in at most 80 000 iterations (64 863
    measured, 17 s). The masses made where the nodes by the clamp did not touch, without their
    springs, stalled it: its smallest residual ratio 0.23 after 40 000 iterations."""
    from validation.references.elastica import heavy_strip_over_cylinder

    path = ROOT / "cases" / "strip_over_cylinder.toml"
    tables, _ = apply_overrides(read_case_data(path), {"mesh.rectangle.nx": 20})
    case = case_from_data(tables, path)
    static = Static(increments=10, progress=False).solve(case.model())
    assert static.converged
    relaxed = DynamicRelaxation(max_iterations=80_000, progress=False).solve(case.model())
    assert relaxed.converged
    np.testing.assert_allclose(relaxed.positions, static.positions, atol=2e-3)
    reference = heavy_strip_over_cylinder(100.0, 1.66e-9 * 9810.0, 0.833, 20.5)
    tip = relaxed.positions[case.mesh.nodes("tip")]
    np.testing.assert_allclose(tip[:, 0], reference["tip_x"], atol=0.3)
    np.testing.assert_allclose(tip[:, 2], reference["tip_z"], atol=0.3)


@pytest.mark.parametrize("driven", [False, True], ids=["fixed", "driven"])
def test_a_rigid_tool_s_clearance_is_each_node_s_gap_to_where_its_spring_starts(driven):
    """The plate 0.3 mm above the die: each node's clearance is its gap to the contact
    surface, 0.3 mm (to the contact's 1e-9 of the model's size); a force-driven die moves
    too, so half of it, and the die's own node the least of them (its spring joins every
    node's); inf at no node of the plate."""
    model = plate_above_a_die(0.3, tool=False)
    die = RigidPlane((0.0, 0.0, 0.0), (0.0, 0.0, 1.0))
    if driven:
        die = RigidPlane(
            (0.0, 0.0, 0.0), (0.0, 0.0, 1.0), free="z", force=(0.0, 0.0, 1.0), mass=1e-3
        )
    model.contact(die)
    compiled = model.compile()
    state = compiled.initial_state()
    clearance = compiled.interactions[0].clearance(state)
    plate = np.arange(25)
    share = 0.5 if driven else 1.0
    np.testing.assert_allclose(clearance[plate], share * 0.3, rtol=0.0, atol=1e-7)
    assert len(clearance) == compiled.n_nodes == 25 + driven
    if driven:
        assert clearance[25] == clearance[plate].min()
