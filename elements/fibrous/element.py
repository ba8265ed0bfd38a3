"""The FibrousShell element type: the fabric, the options, their checks, and ``bind``, which
builds a FibrousShellBlock over the triangles of a mesh (elements/fibrous/block.py).

The fibre levels through the thickness are Gauss-Lobatto points by default
(``lobatto_levels``, docs/theory.md §2.1).
"""

from __future__ import annotations

import numpy as np

from elements import kernels
from elements.base import ElementType
from elements.fibrous.block import FibrousShellBlock
from femcore.checks import as_flag, as_number, as_reals
from femcore.mesh import Mesh
from materials.fabric import Fabric

__all__ = ["FibrousShell", "lobatto_levels"]


def lobatto_levels(count: int) -> tuple[np.ndarray, np.ndarray]:
    """Gauss-Lobatto fibre positions zeta_f in [-1, 1] and weights w_f (sum 1), ``count`` >= 2.

    Three levels give bottom, middle, top with Simpson weights 1/6, 2/3, 1/6 (docs/theory.md §2.1):
    the inextensibility acts on the physical top and bottom surfaces, and sum w zeta^2 = 1/3
    is the continuum moment of inertia of the section.
    """
    n = count
    interior = (
        np.polynomial.legendre.Legendre.basis(n - 1).deriv().roots() if n > 2 else np.zeros(0)
    )
    zeta = np.concatenate(([-1.0], np.sort(np.real(interior)), [1.0]))
    p = np.polynomial.legendre.Legendre.basis(n - 1)(zeta)
    weights = 2.0 / (n * (n - 1) * p**2)
    return zeta, weights / weights.sum()


def _levels(levels) -> tuple[np.ndarray, np.ndarray]:
    if isinstance(levels, (int, np.integer)) and not isinstance(levels, bool):
        if levels < 2:
            raise ValueError(
                f"levels must be >= 2 (fibres at the bottom and top at least: with one level "
                f"the directors have no stiffness), got {levels}"
            )
        return lobatto_levels(int(levels))
    try:
        zeta, weights = (np.array(v, dtype=float).ravel() for v in levels)
    except (TypeError, ValueError):
        raise ValueError(
            f"levels must be an integer >= 2 or a pair (positions, weights), got {levels!r}"
        ) from None
    if zeta.size != weights.size or zeta.size < 2:
        raise ValueError("levels: positions and weights must have the same length >= 2")
    if not (np.all(np.abs(zeta) <= 1.0) and np.all(weights > 0)):
        raise ValueError(
            "levels: positions must lie in [-1, 1] (zeta along the director) and weights be > 0"
        )
    if np.all(zeta == 0.0):
        raise ValueError("levels: at least one fibre level must be off the mid-surface")
    return zeta, weights / weights.sum()


class FibrousShell(ElementType):
    """Bai's fibrous shell triangle for a fabric or a stack of plies.

    fabric : materials.Fabric (thickness, areal density, tension, shear and bending laws).
    levels : number of fibre levels through the thickness (Gauss-Lobatto, default 3: bottom,
        middle, top with Simpson weights), or a pair (positions zeta in [-1, 1], weights).
    warp : warp direction in the reference configuration, (3,); default x. The weft is the
        in-plane perpendicular. Each triangle must have one edge along each (Eq. 9).
    fibre_angle_tolerance : degrees; how far an edge may deviate from a fibre direction.
    clamped : node ids (or a node-set name) of clamped edges, or a list of them as
        ``symmetric`` takes (both ends: ``["left", "right"]``): sides of the block whose two
        nodes are in these sets bend against a rigid wall in the element's reference plane
        (docs/theory.md §4.5); on an interior line both sides do. The nodes must be held by the
        supports (translations and directors fixed with ``model.fix``, or the translations
        prescribed), else compiling the model raises ValueError. The supports clamp the
        bending by themselves (every side whose two nodes are held is clamped, every element
        whose three nodes are held carries no bending), so fixing the nodes of a line or of a
        region is a clamp with or without this option; it states the intent and is checked.
    symmetric : node ids (or a node-set name) of a symmetry plane, or a list of them (a quarter
        model's two planes): the block's boundary sides whose two nodes are in a set bend
        against the mirror image of their cell (docs/theory.md §4.5, "Symmetry plane"), and
        their nodes' nodal normals are the mirrored whole's (projected on the plane), as the
        whole, mirrored model would have them. Each plane's normal is inferred from its sides (in
        the plane, perpendicular to the shell) and must be a coordinate axis; a set that makes
        no boundary edge, or whose edges or nodes are not on one plane, is refused
        (ValueError). The supports must keep the plane's nodes in it: with ``model.fix``, the
        translation along the normal and the director DOF that turns the director out of the
        plane (on a sheet whose directors are +-z: a plane x = const fixes "ux" and "alpha",
        a plane y = const "uy" and "beta"); compiling the model refuses it otherwise.
    thickness : "nodal" (default) or "element": the normal n of h_m = h / (V . n) (docs/theory.md
        §1.4). "nodal" takes the angle-weighted normal of the block's triangles around each node,
        so the thickness along the director is continuous and a bent stack's directors tilt as
        its layers slip (atan(theta) for a strip bent by theta from a clamp); the force at a
        node then reaches three rings of cells. "element" is Bai's Eq. 15, each element's own
        normal: every element sees three parallel directors as strain-free, so the directors
        keep their orientation whatever the curvature.
    thickness_variation : include the variation of h_m (docs/theory.md §2.5) in the forces, so that
        they are the exact gradient of the strain energy (default). False follows Bai Eq. 28,
        which leaves it out.
    bending_geometry : "current" (the curvature coefficients c_as of §4.2 from the current
        geometry, held fixed in the variation as Bai and S3 do) or "reference" (from the
        reference geometry: total Lagrangian, exactly conservative).
    kernel : "compiled" (default when numba is installed: the forces, the energy and the
        nodal normal sums by the loops of elements/fibrous/kernels.py) or "numpy" (the
        vectorised reference).
    """

    dofs = FibrousShellBlock.dofs
    cell_type = FibrousShellBlock.cell_type
    defines_directors = True
    # Its directors are material normals (their turn is the layers' slip, docs/theory.md
    # §1.7) and its bending is rotation-free (§4): a nodal moment would not bend it.
    takes_moments = False

    def __init__(
        self,
        fabric: Fabric,
        levels=3,
        warp=(1.0, 0.0, 0.0),
        fibre_angle_tolerance: float = 1.0,
        clamped=None,
        symmetric=None,
        thickness_variation: bool = True,
        bending_geometry: str = "current",
        thickness: str = "nodal",
        kernel: str | None = None,
    ):
        self.kernel = kernels.choose(kernel)
        if not isinstance(fabric, Fabric):
            raise ValueError(f"FibrousShell needs a materials.Fabric, got {fabric!r}")
        self.fabric = fabric
        self.zeta, self.weights = _levels(levels)
        warp = as_reals(warp, "FibrousShell warp", "a non-zero 3-vector").ravel()
        if warp.shape != (3,) or not np.isfinite(warp).all() or np.linalg.norm(warp) == 0:
            raise ValueError(f"warp must be a non-zero 3-vector, got {warp!r}")
        self.warp = warp / np.linalg.norm(warp)
        tolerance = as_number(
            fibre_angle_tolerance, "fibre_angle_tolerance", "a number of degrees in (0, 45)"
        )
        if not 0.0 < tolerance < 45.0:
            raise ValueError(
                f"fibre_angle_tolerance must be in (0, 45) degrees, got {fibre_angle_tolerance!r}"
            )
        self.fibre_angle_tolerance = tolerance
        self.clamped = clamped
        self.symmetric = symmetric
        self.thickness_variation = as_flag(thickness_variation, "thickness_variation")
        if thickness not in ("nodal", "element"):
            raise ValueError(
                f"thickness must be 'nodal' (h_m from the nodal normals) or 'element' (Bai "
                f"Eq. 15, the element normals), got {thickness!r}"
            )
        self.thickness = thickness
        if bending_geometry not in ("current", "reference"):
            raise ValueError(
                f"bending_geometry must be 'current' or 'reference', got {bending_geometry!r}"
            )
        self.bending_geometry = bending_geometry

    @property
    def half_thickness(self) -> float:
        """h / 2, mm: the contact surface's offset from the mid-surface along the normal."""
        return 0.5 * self.fabric.thickness

    def bind(self, mesh: Mesh, cell_ids: np.ndarray, directors: np.ndarray) -> FibrousShellBlock:
        return FibrousShellBlock(self, mesh, cell_ids, directors)
