"""The curvature a bending law takes is the deformed fibre's in both kinematics: a strip
stretched by lambda along its warp and rolled onto a cylinder of radius R has fibres of
curvature 1/R whatever lambda (docs/theory.md §5.7; the fibrous shell's §3)."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from elements import FibrousShell, MindlinShell
from femcore import Mesh, Model
from materials import Fabric

FABRIC = Fabric(thickness=0.3, areal_density=1e-9, tension=10.0, shear=0.2, bending=7.5)
LENGTH, WIDTH, RADIUS = 40.0, 10.0, 100.0


@pytest.mark.parametrize("kinematics", ["fibrous", "mindlin"])
@pytest.mark.parametrize("stretch", [1.0, 1.05, 1.2])
def test_a_stretched_strip_rolled_on_a_cylinder_has_the_cylinders_curvature(kinematics, stretch):
    """Exact positions (arc length lambda X along the circle of radius R) and directors (the
    cylinder's normals): every interior cell's warp curvature is 1/R. Tolerance 1e-4
    relative: the fibrous shell's curvature is that of the circle through nodes a chord
    c = 2.5 lambda mm apart, measured against the arc (c / R)^2 / 24 = 3.75e-5 at lambda =
    1.2; the Mindlin section's is exact (1e-13 measured). Before the fix the Mindlin section
    gave lambda^2 / R (1.44e-2 at lambda = 1.2, 44 % off)."""
    mesh = Mesh.rectangle(LENGTH, WIDTH, nx=16, ny=2)
    model = Model(mesh)
    model.add(FibrousShell(FABRIC) if kinematics == "fibrous" else MindlinShell(FABRIC))
    compiled = model.compile()
    state = compiled.initial_state()
    reference = compiled.reference_positions
    angle = stretch * reference[:, 0] / RADIUS
    positions = np.column_stack(
        [RADIUS * np.sin(angle), reference[:, 1], RADIUS * (1.0 - np.cos(angle))]
    )
    normals = np.column_stack([-np.sin(angle), np.zeros(len(angle)), np.cos(angle)])
    state = dataclasses.replace(state, positions=positions, directors=normals)
    curvature = np.abs(np.asarray(compiled.fields(state)["triangle"]["warp_curvature"]))
    centre = reference[mesh.triangles].mean(axis=1)[:, 0]
    interior = (centre > LENGTH / 8) & (centre < LENGTH - LENGTH / 8)
    assert curvature[interior] == pytest.approx(1.0 / RADIUS, rel=1e-4)


@pytest.mark.parametrize("stretch", [1.0, 1.05, 1.2])
def test_a_strip_curved_in_its_reference_takes_the_change_of_its_fibres_curvature(stretch):
    """The Mindlin section on a strip whose reference lies on a cylinder of radius R0 = 50 mm,
    stretched by lambda onto one of R = 100 mm: the bending law takes the change of the
    fibre's curvature 1/R - 1/R0 at every stretch (the output's sign: -(kappa - kappa0), as
    -1/R for a flat strip rolled towards +z). Tolerance 2e-4 relative: the reference directors
    are the faceted cylinder's nodal normals (7e-5 measured). Dividing the change of x_,a .
    V_,a alone by lambda^2 gave 1/R - 1/(R0 lambda^2) (0.39 of it at lambda = 1.2)."""
    flat = Mesh.rectangle(LENGTH, WIDTH, nx=16, ny=2)
    reference, bent = flat.points, 50.0
    angle0 = reference[:, 0] / bent
    curved = Mesh(
        np.column_stack([bent * np.sin(angle0), reference[:, 1], bent * (1 - np.cos(angle0))]),
        triangles=flat.triangles,
    )
    model = Model(curved)
    model.add(MindlinShell(FABRIC))
    compiled = model.compile()
    state = compiled.initial_state()
    angle = stretch * reference[:, 0] / RADIUS
    positions = np.column_stack(
        [RADIUS * np.sin(angle), reference[:, 1], RADIUS * (1.0 - np.cos(angle))]
    )
    normals = np.column_stack([-np.sin(angle), np.zeros(len(angle)), np.cos(angle)])
    state = dataclasses.replace(state, positions=positions, directors=normals)
    curvature = np.asarray(compiled.fields(state)["triangle"]["warp_curvature"])
    centre = reference[flat.triangles].mean(axis=1)[:, 0]
    interior = (centre > LENGTH / 8) & (centre < LENGTH - LENGTH / 8)
    assert curvature[interior] == pytest.approx(-(1.0 / RADIUS - 1.0 / bent), rel=2e-4)
