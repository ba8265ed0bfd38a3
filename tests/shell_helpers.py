"""Helpers shared by the shell tests: small fibrous models, a finite-difference stiffness and
energy gradient, a cylinder mapping, the tables of a clamped-strip case file."""

import numpy as np

from elements import FibrousShell
from femcore import Mesh, Model
from femcore.rotation import nodal_frames, rotate_about
from materials import BendingLaw, Fabric, ShearLaw


def fabric(tension=100.0, shear=5.0, bending=20.0, thickness=3.0, areal_density=1e-9, **kw):
    return Fabric(
        thickness=thickness,
        areal_density=areal_density,
        tension=tension,
        shear=ShearLaw.linear(shear),
        bending=BendingLaw.linear(bending),
        **kw,
    )


def compiled(mesh: Mesh, material=None, **options):
    model = Model(mesh)
    model.add(FibrousShell(material or fabric(), **options))
    return model.compile()


def position_gradient(energy, state, step=1e-6) -> np.ndarray:
    """Central-difference dW/dx (n, 3) of ``energy(state)`` over every node's position."""
    gradient = np.zeros((state.n_nodes, 3))
    for node in range(state.n_nodes):
        for j in range(3):
            plus, minus = state.copy(), state.copy()
            plus.positions[node, j] += step
            minus.positions[node, j] -= step
            gradient[node, j] = (energy(plus) - energy(minus)) / (2 * step)
    return gradient


def stiffness_and_mass(model, state, step=1e-7):
    """Central-difference stiffness over (ux, uy, uz, alpha, beta) per node (alpha: a small
    rotation of the director about V2, beta: about V1, docs/theory.md §1.3) and the lumped diagonal
    mass, on the free DOFs."""
    n = state.n_nodes
    v1, v2 = nodal_frames(state.directors)

    def forces(s):
        f, m = model.internal_force(s)
        return np.column_stack([f, np.sum(m * v2, 1), np.sum(m * v1, 1)]).ravel()

    stiffness = np.zeros((5 * n, 5 * n))
    for node in range(n):
        for j in range(5):
            plus, minus = state.copy(), state.copy()
            if j < 3:
                plus.positions[node, j] += step
                minus.positions[node, j] -= step
            else:
                psi = np.zeros((n, 3))
                psi[node] = (v2 if j == 3 else v1)[node] * step
                plus.directors = rotate_about(state.directors, psi)
                minus.directors = rotate_about(state.directors, -psi)
            stiffness[:, 5 * node + j] = (forces(plus) - forces(minus)) / (2 * step)
    mass, inertia = model.lumped_mass(state)
    diagonal = np.column_stack([mass, mass, mass, inertia, inertia]).ravel()
    free = np.column_stack([model.translation_free, ~model.rotation_fixed]).ravel()
    return stiffness[np.ix_(free, free)], diagonal[free]


def on_cylinder(points, radius):
    """Map a flat x-y sheet onto a cylinder of axis y, arc length along x preserved, bending
    towards +z (curvature chi = -1/radius with Bai's sign, Eq. 1-3); directors normal."""
    theta = points[:, 0] / radius
    positions = np.column_stack(
        [radius * np.sin(theta), points[:, 1], radius * (1 - np.cos(theta))]
    )
    directors = np.column_stack([-np.sin(theta), np.zeros_like(theta), np.cos(theta)])
    return positions, directors


def clamped_strip_tables(length, cells, bending, density, thickness, shear, increments,
                         paths=None) -> dict:  # fmt: skip
    """The tables of a case file (as tomllib reads them): a fibrous strip, ``length`` x 10 mm
    in ``cells`` x 1 cells, clamped at its left edge and sagging under its weight (Static in
    ``increments``); history: the clamp's reaction, the right edge's displacement."""
    output: dict = {"history": {"reactions": ["left"], "displacements": ["right"]}}
    if paths:
        output["paths"] = paths
    material = {"thickness": thickness, "areal_density": density, "tension": 1000.0,
                "shear": shear, "bending": bending}  # fmt: skip
    return {
        "title": "clamped strip",
        "mesh": {"rectangle": {"lx": length, "ly": 10.0, "nx": cells, "ny": 1}},
        "part": [{"element": "fibrous", "material": material, "options": {"clamped": "left"}}],
        "fix": [{"nodes": "left"}],
        "gravity": {"acceleration": [0.0, 0.0, -9810.0]},
        "solver": {"kind": "static", "increments": increments},
        "output": output,
    }
