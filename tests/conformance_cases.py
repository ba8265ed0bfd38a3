"""The element cases of the conformance suite (tests/test_conformance.py).

Each ``ElementCase`` (femcore.testing, the public conformance kit) builds a small model of one
element type (one material, one set of options), a jittered deformed state, the total mass
computed from the mesh, the states at which the stable step is checked, and its tolerances,
each with a one-line justification. A new
element type is done when it has a case in ``CASES`` and the suite passes for it.

The set-ups and tolerances are those the per-element tests used before the suite replaced
them (tests/test_cable.py, test_fibrous.py, test_mindlin.py): the same meshes, materials,
jitter amplitudes and seeds, with tolerances equal or tighter. Differences: the stable step of
the shells is checked on the 40 x 30 mm patch of the other checks (the former tests used a
30 x 20 one: same 10 mm cells, same wrap angles 0.5 and 1 rad) and also at the jittered state;
the mass sums use each case's own material.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping

import numpy as np

from elements import Cable, FibrousShell, MindlinShell
from femcore import Mesh
from femcore.model import CompiledModel
from femcore.state import State
from femcore.testing import (
    CENTRAL_DIFFERENCE,
    ENERGY_ROUND_OFF,
    FIELD_ROUND_OFF,
    MASS_SUM,
    ROUND_OFF,
    ROUND_OFF_SQUARED,
    TANGENT_DIFFERENCES,
    WITHIN_TWO,
    ElementCase,
    EnergyPart,
    jitter,
)
from materials import BendingLaw, ElasticShell, Fabric, ShearLaw
from tests.shell_helpers import fabric, on_cylinder

# The shared tolerances (femcore.testing, the kit's defaults) are the values the former
# per-element tests used, or tighter; each case still names them, so that a change of the
# kit's defaults does not loosen the project's own checks unnoticed.


# ---------------------------------------------------------------------- cables
def net_mesh(nx: int = 4, ny: int = 3, size: float = 10.0) -> Mesh:
    """A square cable net: every grid edge of an nx x ny grid is a cable, plus the diagonals."""
    i, j = np.meshgrid(np.arange(nx + 1), np.arange(ny + 1), indexing="xy")
    points = np.column_stack([i.ravel() * size, j.ravel() * size, np.zeros(i.size)])
    ids = np.arange(points.shape[0]).reshape(ny + 1, nx + 1)
    lines = np.vstack(
        [
            np.column_stack([ids[:, :-1].ravel(), ids[:, 1:].ravel()]),
            np.column_stack([ids[:-1, :].ravel(), ids[1:, :].ravel()]),
            np.column_stack([ids[:-1, :-1].ravel(), ids[1:, 1:].ravel()]),
        ]
    )
    return Mesh(points, lines=lines)


CABLE_AXIAL_STIFFNESS = 2.0e4  # N
CABLE_MASS_PER_LENGTH = 3.0e-9  # t/mm


def _cable_length(mesh: Mesh) -> float:
    return float(np.linalg.norm(np.diff(mesh.points[mesh.lines], axis=1)[:, 0], axis=1).sum())


_cable_jitter = jitter(amplitude=0.5, seed=3)


def _stretched(factor: float) -> Callable[[CompiledModel], State]:
    def build(model: CompiledModel) -> State:
        state = model.initial_state()
        state.positions = state.positions * factor
        return state

    return build


def _cable_case(name: str, tension_only: bool, reference_state: tuple) -> ElementCase:
    return ElementCase(
        name=name,
        element=lambda: Cable(
            CABLE_AXIAL_STIFFNESS, CABLE_MASS_PER_LENGTH, tension_only=tension_only
        ),
        mesh=lambda refine: net_mesh(4 * refine, 3 * refine, 10.0 / refine),
        total_mass=lambda mesh: CABLE_MASS_PER_LENGTH * _cable_length(mesh),
        deform=_cable_jitter,
        step_states={reference_state[0]: reference_state[1], "jittered": _cable_jitter},
        rigid_fields=("axial_strain", "axial_force"),
        rigid=ROUND_OFF,
        rigid_energy=ROUND_OFF_SQUARED,
        rigid_field=FIELD_ROUND_OFF,
        objectivity=ROUND_OFF,
        objective_energy=ENERGY_ROUND_OFF,
        gradient=CENTRAL_DIFFERENCE,
        tangent=TANGENT_DIFFERENCES,
        mass=MASS_SUM,
        step_floor=WITHIN_TWO,
        shrink=(2.0 * (1 - 1e-12), 2.0 * (1 + 1e-12), "the cable step is L / c: exactly ~L"),
    )


CABLE = _cable_case("cable", False, ("reference", lambda model: model.initial_state()))
# At the reference a tension-only cable sits on its kink (taut stiffness on one side, none on
# the other): the exact eigenvalues are those of the taut net, just stretched.
TENSION_ONLY_CABLE = _cable_case("cable-tension-only", True, ("taut", _stretched(1.001)))


# ---------------------------------------------------------------------- shells
PATCH = (40.0, 30.0, 4, 3)  # mm, mm, cells, cells: 10 mm right triangles


def patch(refine: int) -> Mesh:
    lx, ly, nx, ny = PATCH
    return Mesh.rectangle(lx, ly, nx=nx * refine, ny=ny * refine)


def _wrapped(angle: float) -> Callable[[CompiledModel], State]:
    """The patch wrapped on a cylinder through ``angle`` rad over its length, the directors
    left as they were: the element normals tilt up to ``angle`` against them."""

    def build(model: CompiledModel) -> State:
        state = model.initial_state()
        state.positions, _ = on_cylinder(model.reference_positions, PATCH[0] / angle)
        return state

    return build


def _patch_area(mesh: Mesh) -> float:
    x = mesh.points[mesh.triangles]
    return float(0.5 * np.linalg.norm(np.cross(x[:, 1] - x[:, 0], x[:, 2] - x[:, 0]), axis=1).sum())


def _fibrous_parts(parts: tuple[str, ...]):
    def build(model: CompiledModel) -> Mapping[str, EnergyPart]:
        block = model.blocks[0]
        return {
            part: (
                lambda s, part=part: block.strain_energy_parts(s)[part],
                lambda s, part=part: block.internal_force_parts(s)[part],
            )
            for part in parts
        }

    return build


CURRENT_BENDING = (
    "bending_geometry='current' holds the current c_as fixed in the variation (Bai, "
    "docs/theory.md §4.4): bending is the gradient only to first order in the folds "
    "(tests/test_fibrous.py, "
    "tests/test_static.py test_fibrous_tangent_with_current_bending_coefficients_is_close)"
)


def _fibrous_case(
    name: str, material, bending_geometry: str, thickness: str = "nodal"
) -> ElementCase:
    exact = bending_geometry == "reference"
    return ElementCase(
        name=name,
        element=lambda: FibrousShell(
            material, bending_geometry=bending_geometry, thickness=thickness
        ),
        mesh=patch,
        total_mass=lambda mesh: material.areal_density * _patch_area(mesh),
        deform=jitter(amplitude=0.6, tilt=0.3),
        step_states={
            "reference": lambda model: model.initial_state(),
            "wrapped 0.5 rad": _wrapped(0.5),
            "wrapped 1 rad": _wrapped(1.0),
            "jittered": jitter(amplitude=0.6, tilt=0.3),
        },
        rigid_fields=(
            "warp_strain",
            "weft_strain",
            "shear_angle_deg",
            "warp_curvature",
            "weft_curvature",
            "warp_moment",
            "weft_moment",
        ),
        rigid=ROUND_OFF,
        rigid_energy=ROUND_OFF_SQUARED,
        rigid_field=FIELD_ROUND_OFF,
        objectivity=ROUND_OFF,
        objective_energy=ENERGY_ROUND_OFF,
        gradient=CENTRAL_DIFFERENCE,
        tangent=TANGENT_DIFFERENCES,
        mass=MASS_SUM,
        step_floor=WITHIN_TWO,
        shrink=(1.9, 4.1, "tension and shear: dt ~ L; bending: dt ~ L^2"),
        energy_parts=_fibrous_parts(
            ("tension", "shear", "bending") if exact else ("tension", "shear")
        ),
        not_a_potential=None if exact else CURRENT_BENDING,
    )


# Bai et al. (2020) Table 1, linearised: tension 1200 N/mm and the initial bending slope 7.5
# N mm of the paper's table, on the 20-ply G986 stack of materials.presets.g986_stack (6 mm,
# 5.7e-9 t/mm^2, shear 20 x 0.2 N/mm, assumed there): the balance of tension, shear and
# bending of a real fabric (the stable-step bound combines the three).
BAI_FABRIC = fabric(tension=1200.0, shear=4.0, bending=7.5, thickness=6.0, areal_density=5.7e-9)

FIBROUS = _fibrous_case("fibrous", fabric(), "current")
FIBROUS_REFERENCE_BENDING = _fibrous_case("fibrous-reference-bending", fabric(), "reference")
FIBROUS_BAI = _fibrous_case("fibrous-bai-fabric", BAI_FABRIC, "current")
# Bai's Eq. 15 thickness (each element's own normal), kept as an option.
FIBROUS_ELEMENT_THICKNESS = _fibrous_case(
    "fibrous-element-thickness", fabric(), "reference", thickness="element"
)


def _mindlin_case(
    name: str,
    material,
    shrink: tuple[float, float, str],
    rigid_fields: tuple[str, ...] = ("membrane_force", "bending_moment", "shear_force"),
) -> ElementCase:
    """MindlinShell of ``material`` (an ElasticShell, or a Fabric: the section of its own laws,
    docs/theory.md §5.7), the same checks and tolerances for both sections."""
    return ElementCase(
        name=name,
        element=lambda: MindlinShell(material),
        mesh=patch,
        total_mass=lambda mesh: material.areal_density * _patch_area(mesh),
        deform=jitter(amplitude=0.5, tilt=0.2),
        step_states={
            "reference": lambda model: model.initial_state(),
            "wrapped 1 rad": _wrapped(1.0),
            "jittered": jitter(amplitude=0.5, tilt=0.2),
        },
        rigid_fields=rigid_fields,
        rigid=ROUND_OFF,
        rigid_energy=ROUND_OFF_SQUARED,
        rigid_field=FIELD_ROUND_OFF,
        objectivity=ROUND_OFF,
        objective_energy=ENERGY_ROUND_OFF,
        gradient=CENTRAL_DIFFERENCE,
        tangent=TANGENT_DIFFERENCES,
        mass=MASS_SUM,
        step_floor=WITHIN_TWO,
        shrink=shrink,
    )


def _elastic(thickness: float) -> ElasticShell:
    return ElasticShell(1000.0, 0.3, thickness, 1e-9)


# The stable step is each element's own eigenvalue bound (docs/theory.md §6.2 B4), so how it
# shrinks with the cells follows the element's modes: the ratios of the assembled system's
# exact 2 / omega_max between 10 mm and 5 mm cells are 2.08 (h = 2), 1.41 (h = 5) and 2.00
# (h = 0.2); the bound's are 2.02, 1.28 and 2.00 (and it stays 0.84-0.98 of the exact step).
# On 10 mm cells h = 2 and 0.2 mm have the rotary inertia scaled (B2: j ~ altitude^2): the
# membrane and shear terms of omega^2 go as 1 / L^2, bending through the rotations faster.
MINDLIN = _mindlin_case(
    "mindlin",
    _elastic(2.0),
    (2.0, 2.1, "scaled inertia: dt ~ L, a little more where bending counts"),
)
# docs/theory.md §6.2 (B1, B2), the two thicknesses of the former per-element step test: a thick
# shell with the physical rotary inertia, whose shear-rotation term does not depend on L, and a
# thin one that must keep the membrane step.
MINDLIN_THICK = _mindlin_case(
    "mindlin-thick",
    _elastic(5.0),
    (1.2, 2.0, "membrane terms dt ~ L; the unscaled rotation term fixed"),
)
MINDLIN_THIN = _mindlin_case(
    "mindlin-thin", _elastic(0.2), (1.99, 2.01, "scaled inertia, membrane-dominated: dt ~ L")
)


# The rotary inertia is scaled (B2) as in the elastic section, so the membrane and transverse
# shear terms set the step: dt ~ L (ratios 1.90 and 1.9x measured between 10 and 5 mm cells).
SCALED_INERTIA = "scaled rotary inertia: dt ~ L"


def _mindlin_fabric_case(name: str, material, note: str) -> ElementCase:
    return _mindlin_case(
        name,
        material,
        (1.85, 2.1, note),
        rigid_fields=(
            "membrane_force",
            "bending_moment",
            "warp_strain",
            "weft_strain",
            "shear_angle_deg",
            "warp_curvature",
            "weft_curvature",
        ),
    )


# The fabric of the fibrous cases, and a non-linear one: Bai's bilinear bending law with the
# knee below every curvature of the jittered patch (so both slopes and the offset of the law
# act, away from its kink), a cubic shear law and warp and weft laws that differ.
MINDLIN_FABRIC = _mindlin_fabric_case("mindlin-fabric", fabric(), SCALED_INERTIA)
MINDLIN_FABRIC_NONLINEAR = _mindlin_fabric_case(
    "mindlin-fabric-nonlinear",
    Fabric(
        thickness=3.0,
        areal_density=1e-9,
        tension=100.0,
        tension_weft=60.0,
        shear=ShearLaw.polynomial(5.0, 40.0),
        bending=BendingLaw.bilinear(20.0, 2.0, knee=1e-6),
        bending_weft=BendingLaw.bilinear(10.0, 1.0, knee=1e-6),
    ),
    SCALED_INERTIA,
)

CASES: list[ElementCase] = [
    CABLE,
    TENSION_ONLY_CABLE,
    FIBROUS,
    FIBROUS_REFERENCE_BENDING,
    FIBROUS_BAI,
    FIBROUS_ELEMENT_THICKNESS,
    MINDLIN,
    MINDLIN_THICK,
    MINDLIN_THIN,
    MINDLIN_FABRIC,
    MINDLIN_FABRIC_NONLINEAR,
]
