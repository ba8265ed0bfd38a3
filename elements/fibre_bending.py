"""In-plane fibre bending for the fibrous shell, an option (docs/theory.md §4.7): the tows'
resistance to curving in the fabric's plane, energy 1/2 B_in kappa_g^2 per unit area and per
fibre family, kappa_g the geodesic curvature of the fibre.

Bai's fibrous membrane has no length in its plane: past a weft compression of about G / E it
loses its uniform state to rows that shear alternately at the mesh's own width
(docs/hemisphere_forming.md, "Why the rows beside the held centre lines alternate"). The
second-gradient models of woven fabrics (Ferretti, Madeo, dell'Isola, Boisse, Z. Angew.
Math. Phys. 65 (2014) 587; Barbagallo, Madeo, Morestin, Boisse, Math. Mech. Solids 22 (2017))
give the fibres a bending stiffness in the plane, which sets a length sqrt(B_in / G) and
makes short waves costly. Off unless added: the paper's model is unchanged.

Rotation-free, as the out-of-plane bending (§4): the curvature is read from neighbouring cells
along each fibre (elements/fibre_bending_patches.py, elements/fibre_bending_terms.py); it acts
between the body's own nodes, so it is an interaction of the model
(``model.interact(FibreBending(b_in))``), beside the fibrous element blocks it reads.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from elements import kernels
from elements.fibre_bending_kernels import patch_forces, patch_spring_bounds
from elements.fibre_bending_patches import FibrePatches, fibre_patches, warp_groups
from elements.fibre_bending_terms import patch_angles, patch_gradients, vector_spring_bounds
from femcore.assembly import CellTangent
from femcore.checks import check_positive
from femcore.interaction import Body, Interaction, InteractionBlock
from femcore.state import State

__all__ = ["FibreBending", "FibreBendingBlock"]

FAMILIES = {"warp": 0, "weft": 1}

#: The explicit step's springs: each patch's whole stiffness k (g g^T + theta H) bounded node
#: by node (block Gershgorin in its four vectors, ``FibreBendingBlock.springs_at``), a bound
#: at the state they are taken, times this margin for its change until the step is evaluated
#: again
#: (femcore.interaction, SPRINGS_HELD_STEPS).
SPRING_MARGIN = 2.0

#: The springs' Hessian of theta: a forward difference of the gradient over this step (times
#: the patch's segment length), off the complex step's exact value by 1.7e-8 of the largest
#: spring at 48 cells, nothing against the bound's slack and margin, at 0.39 of its cost
#: (benchmarks/fibre_bending_force.py).
SPRING_STEP = 1e-7

#: The complex step of the tangent (times the patch's segment length): the Hessian of theta
#: is the imaginary part of its gradient at x + i h e_r, over h, exact to round-off.
COMPLEX_STEP = 1e-30


class FibreBending(Interaction):
    """In-plane bending of the fibres of the model's FibrousShell blocks.

    Parameters
    ----------
    stiffness : float
        B_in, N mm: the in-plane bending moment per unit width of fabric per unit geodesic
        curvature of its fibres (the same for both families unless ``families`` names one).
    families : tuple of str, or str
        The fibre families bent, "warp" and/or "weft" each once: ("warp", "weft") by
        default; one name alone stands for the tuple of it.
    kernel : "compiled" (default when numba is installed: the force and energy by the loop of
        elements/fibre_bending_kernels.py) or "numpy" (the vectorised reference).

    Raises
    ------
    ValueError
        For a stiffness that is not positive and finite, or families not a tuple (or list) of
        "warp" and/or "weft" each once (or one of them alone); at bind, when
        the model has no FibrousShell block or a cell has no edge along a fibre family.
    """

    dofs = ("ux", "uy", "uz")

    def __init__(self, stiffness: float, families=("warp", "weft"), kernel: str | None = None):
        self.kernel = kernels.choose(kernel)
        self.stiffness = check_positive(stiffness, "FibreBending stiffness", "N mm")
        expected = "a tuple of 'warp' and/or 'weft', each once"
        names = (families,) if isinstance(families, str) else families
        if not isinstance(names, (tuple, list)):
            raise ValueError(f"FibreBending families must be {expected}, got {families!r}")
        if (
            not names
            or any(not isinstance(name, str) or name not in FAMILIES for name in names)
            or len(set(names)) != len(names)
        ):
            raise ValueError(f"FibreBending families must be {expected}, got {families!r}")
        self.families = tuple(names)

    def bind(self, body: Body) -> FibreBendingBlock:
        """The patches over all the FibrousShell blocks' cells together: a fibre that runs
        from one block into another on shared nodes is bent where it crosses, when the two
        blocks' warps agree either way along their line (within the smaller of the blocks'
        fibre angle tolerances; elements/fibre_bending_patches.py ``warp_groups``, the same
        in any order of the blocks); blocks whose warps differ meet at a seam of different
        tows and are not paired across it."""
        from elements.fibrous import FibrousShell

        found = [
            (part.element, np.asarray(part.cells, dtype=np.int64))
            for part in body.parts
            if isinstance(part.element, FibrousShell)
        ]
        if not found:
            raise ValueError(
                "FibreBending bends the fibres of FibrousShell blocks; the model has none"
            )
        group_of_block, sign = warp_groups(
            np.array([shell.warp for shell, _ in found], dtype=float),
            np.array([shell.fibre_angle_tolerance for shell, _ in found], dtype=float),
        )
        cells = np.concatenate([cells for _, cells in found])
        sizes = [len(cells) for _, cells in found]
        patches = fibre_patches(
            body.mesh.points,
            cells,
            np.repeat([a * np.asarray(shell.warp) for a, (shell, _) in zip(sign, found)], sizes, 0),
            self.stiffness,
            tuple(FAMILIES[name] for name in self.families),
            np.repeat([shell.fibre_angle_tolerance for shell, _ in found], sizes),
            np.repeat(group_of_block, sizes),
        )
        return FibreBendingBlock(patches, body.mesh.points, self.kernel == "compiled")


class FibreBendingBlock(InteractionBlock):
    """A bound ``FibreBending``: ``connectivity`` (P, 5) the patches' nodes
    (elements/fibre_bending_patches.py), energy sum 1/2 k theta^2."""

    dofs = FibreBending.dofs
    reach = 1

    def __init__(self, patches: FibrePatches, points: np.ndarray, compiled: bool = False):
        self.patches = patches
        self.compiled = compiled
        self.connectivity = patches.nodes
        self.n_nodes = len(points)
        self.reference = np.array(points, dtype=float)

    def angles(self, state: State) -> np.ndarray:
        """theta (P,), rad: each patch's in-plane turning angle."""
        return patch_angles(state.positions[self.connectivity], self.patches.ends)

    def strain_energy(self, state: State, history: Any = None) -> float:
        """sum 1/2 k theta^2, N mm."""
        if self.compiled:
            return self._force_and_energy(state)[1]
        theta = self.angles(state)
        return float(0.5 * np.sum(self.patches.stiffness * theta * theta))

    def _patch_forces(self, state: State) -> np.ndarray:
        x = state.positions[self.connectivity]
        theta = patch_angles(x, self.patches.ends)
        grad = patch_gradients(x, self.patches.ends)
        return (self.patches.stiffness * theta)[:, None, None] * grad

    def internal_force(self, state: State, history: Any = None) -> tuple[np.ndarray, None]:
        """dW/dx (n, 3), N."""
        if self.compiled:
            return self._force_and_energy(state)[0], None
        force = np.zeros((self.n_nodes, 3))
        np.add.at(force, self.connectivity, self._patch_forces(state))
        return force, None

    def _force_and_energy(self, state: State) -> tuple[np.ndarray, float]:
        """The compiled pass: dW/dx (n, 3), N, and the energy, N mm, at once."""
        force = np.zeros((self.n_nodes, 3))
        patches = self.patches
        positions = np.ascontiguousarray(state.positions, dtype=float)
        energy = patch_forces(positions, patches.nodes, patches.ends, patches.stiffness, force)
        return force, float(energy)

    def tangent(self, state: State, history: Any = None) -> list[CellTangent]:
        """k (grad theta grad theta^T + theta Hess theta) per patch (P, 5, 3, 5, 3), N/mm; the
        Hessian by the complex step of the gradient (exact to round-off)."""
        x = state.positions[self.connectivity]
        ends = self.patches.ends
        theta = patch_angles(x, ends)
        grad = patch_gradients(x, ends)
        scale = np.linalg.norm(x[:, 1] - x[:, 0], axis=1)
        step = COMPLEX_STEP * scale
        hessian = np.empty(x.shape + x.shape[1:])
        for node in range(5):
            for component in range(3):
                shifted = x.astype(complex)
                shifted[:, node, component] += 1j * step
                hessian[:, :, :, node, component] = (
                    patch_gradients(shifted, ends).imag / step[:, None, None]
                )
        k = self.patches.stiffness
        blocks = k[:, None, None, None, None] * (
            grad[:, :, :, None, None] * grad[:, None, None, :, :]
            + theta[:, None, None, None, None] * hessian
        )
        return [CellTangent(self.connectivity, blocks)]

    def springs_at(self, state: State, step: float | None = None) -> tuple[np.ndarray, np.ndarray]:
        """Springs to the ground that bound the patches' stiffness for the explicit step: a
        patch's whole K = k (g g^T + theta H) bounded in its four vectors by block Gershgorin
        and carried to their ends (elements/fibre_bending_terms.py ``vector_spring_bounds``),
        exact at this state, times SPRING_MARGIN."""
        return self._springs(state.positions)

    def springs(self) -> tuple[np.ndarray, np.ndarray]:
        """``springs_at`` in the reference configuration."""
        return self._springs(self.reference)

    def _springs(self, positions: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        patches = self.patches
        x = np.ascontiguousarray(positions, dtype=float)
        step = SPRING_STEP * np.linalg.norm(x[patches.nodes[:, 1]] - x[patches.nodes[:, 0]], axis=1)
        if self.compiled:
            bound = np.zeros(patches.nodes.shape)
            patch_spring_bounds(x, patches.nodes, patches.ends, patches.stiffness, step, bound)
        else:
            bound = vector_spring_bounds(
                x[self.connectivity], patches.ends, patches.stiffness, step
            )
        return self.connectivity.ravel(), (SPRING_MARGIN * bound).ravel()

    def node_fields(self, state: State, history: Any = None) -> dict[str, np.ndarray]:
        """``fibre_inplane_angle``: at each node the largest |theta| (rad) of the patches
        centred there (the turning of a fibre through it, either family)."""
        out = np.zeros(self.n_nodes)
        np.maximum.at(out, self.connectivity[:, 1], np.abs(self.angles(state)))
        return {"fibre_inplane_angle": out}
