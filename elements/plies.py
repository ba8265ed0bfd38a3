"""The stack as N sliding plies: the discrete ground truth of the fibrous shell's kinematics
(docs/theory.md "The stack as plies"; the deck of cards, §1.7).

A stack of thickness h described by one Fabric is split into N equal plies (``Fabric.plies``:
thickness h/N, 1/N of the mass and of every law), each a shell of its own on a copy of the
stack's mid-surface mesh offset along the reference normal by z_k = -h/2 + (k - 1/2) h/N,
k = 1..N, and neighbouring plies touch through a penalty contact between their facing faces
(elements/ply_contact.py), frictionless unless ``friction`` gives a Coulomb coefficient.
Nothing else ties the plies, so frictionless they slide on each other freely: the material
line through the points of the plies that started on one normal tilts as the stack bends,
which is what the fibrous shell's directors stand for.

The ply element is a factory argument. The default is ``MindlinShell(ply_fabric)``, a
Reissner-Mindlin shell whose section is the ply's own laws (docs/theory.md §5.7): each ply is
a card whose normals stay normal. ``ply_section`` is the homogeneous elastic alternative from
the laws' initial slopes: a homogeneous section cannot carry both the fibres' tension T and the
ply's bending B at the ply's thickness, so its own thickness is h_s = sqrt(12 B / T), E = T /
h_s (then E h_s = T and E h_s^3 / 12 = B); the ply's geometric thickness h/N places the plies
and their contact faces.

Units mm, N, t, s.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from elements.mindlin import MindlinShell
from elements.ply_contact import PlyContact, join_neighbours
from femcore.element import ElementType
from femcore.mesh import Mesh
from femcore.model import Model
from femcore.topology import nodal_normals
from materials.elastic import ElasticShell
from materials.fabric import Fabric

__all__ = ["MaterialLines", "PlyStack", "ply_section"]


def _slope(law: Any) -> float:
    return float(np.asarray(law.slope(np.array(0.0))))


def ply_section(ply: Fabric, shear_ratio: float = 0.5) -> ElasticShell:
    """The Mindlin section of one ply from its fabric's initial slopes (module docstring).

    Section thickness h_s = sqrt(12 B / T) from the warp bending slope B (N mm) and tension
    slope T (N/mm), so that the membrane stiffness E1 h_s is T and the bending stiffness
    E1 h_s^3 / 12 is B; E2 = T_weft / h_s (the weft bends as E2 h_s^3 / 12, which is the
    weft bending slope when B_weft / T_weft = B / T); nu12 = 0; G12 = K / h_s from the shear
    slope K (at least 1e-6 E1: a section needs some in-plane shear stiffness); transverse
    G13 = G23 = ``shear_ratio`` E1; density rho_A / h_s (the ply's mass per area).

    Parameters
    ----------
    ply : Fabric
        The ply's fabric (``stack.plies(N)``).
    shear_ratio : float
        G13 / E1, > 0.

    Returns
    -------
    ElasticShell
        Orthotropic, warp along +x, thickness h_s (mm), moduli MPa, density t/mm^3.
    """
    tension, bending = _slope(ply.tension), _slope(ply.bending)
    if not (tension > 0.0 and bending > 0.0):
        raise ValueError(
            f"ply_section needs tension and bending laws with stiffness at zero, got slopes "
            f"{tension!r} N/mm and {bending!r} N mm"
        )
    thickness = float(np.sqrt(12.0 * bending / tension))
    e1 = tension / thickness
    return ElasticShell.orthotropic(
        E1=e1,
        E2=_slope(ply.tension_weft) / thickness,
        nu12=0.0,
        G12=max(_slope(ply.shear) / thickness, 1e-6 * e1),
        G13=shear_ratio * e1,
        G23=shear_ratio * e1,
        thickness=thickness,
        density=ply.areal_density / thickness,
    )


def mindlin_ply(ply: Fabric) -> ElementType:
    """The default ply element: ``MindlinShell(ply)``, the Mindlin shell whose section is the
    ply's own laws (docs/theory.md §5.7): fibre tension, shear and bending as the stack's
    shared out, non-linear laws as given."""
    return MindlinShell(ply)


@dataclass(frozen=True)
class MaterialLines:
    """The material lines of a ply stack at one configuration, one per mid-surface node
    (``PlyStack.material_lines``).

    direction : (n_mid, 3) float
        Unit direction of the line, from ply 1 (bottom) to ply N (top).
    angle : (n_mid,) float
        Its tilt from the unit normal of the stack's mid-surface (the surface through the
        mid-points, ``normal``), rad.
    thickness : (n_mid,) float
        The stack's thickness along the line, mm: from the bottom face of ply 1 to the top
        face of ply N (definition in ``PlyStack.material_lines``).
    midpoint : (n_mid, 3) float
        The middle of that extent: the stack's mid-surface, mm.
    gap : (n_mid,) float
        The largest ply-to-ply gap along the line, mm (< 0: the plies overlap there).
    normal : (n_mid, 3) float
        Unit nodal normal of the surface through the mid-points.
    straightness : (n_mid,) float
        The largest distance of a ply's point from the line, mm (0 for N <= 2).
    """

    direction: np.ndarray
    angle: np.ndarray
    thickness: np.ndarray
    midpoint: np.ndarray
    gap: np.ndarray
    normal: np.ndarray
    straightness: np.ndarray


class PlyStack:
    """A stack of thickness h as ``count`` shells that slide on each other (module docstring).

    Parameters
    ----------
    mesh : Mesh
        The stack's mid-surface (triangles, flat or not, counter-clockwise about the side
        the plies are stacked towards), with its node and triangle sets.
    fabric : Fabric
        The whole stack's fabric (thickness h, mm).
    count : int
        N >= 1, the number of plies.
    element : callable, optional
        ``element(ply_fabric) -> ElementType`` building one ply's shell (called once per
        ply); default ``MindlinShell(ply_fabric)``.
    penalty : float, optional
        The ply contact's penalty, N/mm per node (None: the automatic one of
        elements/ply_contact.py).
    rule : str
        The contact points of each upper triangle (``elements.ply_contact.RULES``).
    smoothing : float, optional
        The penetration over which the contact penalty stiffens, mm (None: the default, 1e-3
        of the ply thickness; 0: the one-sided penalty).
    friction : float
        The Coulomb coefficient mu >= 0 between neighbouring plies, given to every PlyContact
        (0, default: frictionless).
    static_law : str
        The ply contact's normal law under Static (``PlyContact(static_law=...)``): "ramp"
        (default) or "active_set" (elements/ply_active_set.py).

    Attributes
    ----------
    mesh : Mesh
        The N disconnected ply meshes as one: node i of ply k (1-based) is
        ``(k - 1) n_mid + i``, its triangles likewise; every node set of the mid-surface
        becomes the set of all plies' copies, every triangle set too; node and triangle sets
        "ply_k" hold ply k.
    ply_fabric : Fabric
        ``fabric.plies(count)``.
    offsets : (N,) float
        z_k, mm: each ply's offset from the mid-surface along its reference normal.
    ply_nodes : (N, n_mid) int
        Node id of ply k at mid-surface node i (row k - 1).
    ply_cells : (N, m_mid) int
        Triangle id of ply k on mid-surface triangle j.

    Raises
    ------
    ValueError
        Not a Mesh with triangles, not a Fabric, a bad count, an element factory that is
        not callable, a bad penalty, rule, smoothing, friction or static_law.
    """

    def __init__(
        self,
        mesh: Mesh,
        fabric: Fabric,
        count: int,
        element: Callable[[Fabric], ElementType] | None = None,
        penalty: float | None = None,
        rule: str = "centroid",
        smoothing: float | None = None,
        friction: float = 0.0,
        static_law: str = "ramp",
    ):
        if not isinstance(mesh, Mesh) or len(mesh.triangles) == 0:
            raise ValueError(f"PlyStack needs a triangle Mesh (the mid-surface), got {mesh!r}")
        if not isinstance(fabric, Fabric):
            raise ValueError(f"PlyStack needs a materials.Fabric, got {fabric!r}")
        self.ply_fabric = fabric.plies(count)  # validates count
        if element is not None and not callable(element):
            raise ValueError(
                f"element must be a callable ply_fabric -> ElementType, got {element!r}"
            )
        if penalty is not None and not (
            isinstance(penalty, (int, float))
            and not isinstance(penalty, bool)
            and np.isfinite(penalty)
            and penalty > 0
        ):
            raise ValueError(f"penalty must be a positive number (N/mm) or None, got {penalty!r}")
        self.mid = mesh
        self.fabric = fabric
        self.count = int(count)
        self.element = mindlin_ply if element is None else element
        self.penalty = penalty
        # validated here, at the API boundary, rather than when the model is built
        PlyContact(
            "ply_2", "ply_1", penalty=penalty, rule=rule, smoothing=smoothing, friction=friction,
            static_law=static_law,
        )  # fmt: skip
        self.rule, self.smoothing, self.friction = rule, smoothing, float(friction)
        self.static_law = static_law
        h = fabric.thickness
        self.offsets = -h / 2.0 + (np.arange(1, count + 1) - 0.5) * h / count
        n, m = mesh.n_nodes, len(mesh.triangles)
        normals = nodal_normals(mesh.points, mesh.triangles)
        points = (mesh.points[None] + self.offsets[:, None, None] * normals[None]).reshape(-1, 3)
        self.ply_nodes = np.arange(count * n).reshape(count, n)
        self.ply_cells = np.arange(count * m).reshape(count, m)
        triangles = (mesh.triangles[None] + (np.arange(count) * n)[:, None, None]).reshape(-1, 3)
        node_sets = {name: self.ply_nodes[:, ids].ravel() for name, ids in mesh.node_sets.items()}
        cell_sets = {
            name: self.ply_cells[:, ids].ravel() for name, ids in mesh.cell_sets("triangle").items()
        }
        for k in range(count):
            node_sets[f"ply_{k + 1}"] = self.ply_nodes[k]
            cell_sets[f"ply_{k + 1}"] = self.ply_cells[k]
        self.mesh = Mesh(
            points,
            triangles=triangles,
            node_sets=node_sets,
            element_sets=cell_sets,
            fold_set_names=mesh.fold_set_names,  # a deck's names, found as in its mesh
        )

    @property
    def ply_thickness(self) -> float:
        """h / N, mm."""
        return self.ply_fabric.thickness

    def nodes(self, selection: Any) -> np.ndarray:
        """All plies' copies of mid-surface nodes.

        Parameters
        ----------
        selection : str, (s,) int or callable
            A node-set name of the mid-surface mesh, mid-surface node ids, or a predicate
            ``(x, y, z) -> mask`` over the mid-surface coordinates.

        Returns
        -------
        (N s,) int
            The node ids of every ply at those mid-surface nodes, ply by ply.
        """
        if isinstance(selection, str) or callable(selection):
            ids = self.mid.nodes(selection)
        else:
            ids = np.atleast_1d(np.asarray(selection))
            if ids.dtype == bool or not np.issubdtype(ids.dtype, np.integer):
                raise ValueError(f"mid-surface node ids must be integers, got {ids.dtype}")
            if ids.size == 0 or ids.min() < 0 or ids.max() >= self.mid.n_nodes:
                raise ValueError(
                    f"mid-surface node ids must be in 0..{self.mid.n_nodes - 1}, got {ids!r}"
                )
        return self.ply_nodes[:, ids].ravel()

    def model(self) -> Model:
        """A Model of the stack: one element block per ply (``element(ply_fabric)`` on the
        triangle set "ply_k", block k - 1) and a PlyContact between each pair of
        neighbouring plies (points of ply k + 1's triangles on ply k's triangles, the faces
        h / (2N) from the mid-surfaces), interactions 0..N-2. Supports, loads and gravity are the
        caller's (``stack.nodes`` maps mid-surface selections to every ply)."""
        model = Model(self.mesh)
        for k in range(self.count):
            model.add(self.element(self.ply_fabric), cells=f"ply_{k + 1}")
        half = 0.5 * self.ply_thickness
        join_neighbours(
            model,
            self.count,
            half,
            penalty=self.penalty,
            rule=self.rule,
            smoothing=self.smoothing,
            friction=self.friction,
            static_law=self.static_law,
        )
        return model

    def material_lines(self, positions: np.ndarray, directors: np.ndarray) -> MaterialLines:
        """The material line through the plies' points that started on one normal, at each
        mid-surface node.

        With X_k the position of ply k at the node and d_k its director: the line passes
        through the points' centroid c along the unit direction e of least squares (the
        principal axis of the X_k; for N = 2 the chord; for N = 1 the ply's director),
        oriented from ply 1 to ply N. Each X_k sits at t_k = (X_k - c) . e along it, and ply
        k's faces h_p / 2 from its mid-surface along its director lie (h_p / 2) / (e . d_k)
        from X_k along the line (h_p = h / N). The thickness is the extent from the bottom
        face of ply 1 to the top face of ply N, (t_N + (h_p / 2) / (e . d_N)) - (t_1 -
        (h_p / 2) / (e . d_1)) (the chord plus the two half-ply thicknesses along the line);
        the mid-point the middle of that extent; the gap between plies k and k + 1 is
        (t_{k+1} - (h_p/2) / (e . d_{k+1})) - (t_k + (h_p/2) / (e . d_k)).

        Parameters
        ----------
        positions : (n, 3) float
            Positions of every node of ``mesh``, mm.
        directors : (n, 3) float
            Unit directors of every node.

        Returns
        -------
        MaterialLines
        """
        positions = np.asarray(positions, dtype=float)
        directors = np.asarray(directors, dtype=float)
        expected = (self.mesh.n_nodes, 3)
        if positions.shape != expected or directors.shape != expected:
            raise ValueError(
                f"positions and directors must be {expected}, got {positions.shape} and "
                f"{directors.shape}"
            )
        points = np.swapaxes(positions[self.ply_nodes], 0, 1)  # (n_mid, N, 3)
        along_ply = np.swapaxes(directors[self.ply_nodes], 0, 1)
        centre = points.mean(axis=1)
        relative = points - centre[:, None, :]
        if self.count == 1:
            direction = along_ply[:, 0]
        else:
            direction = np.linalg.svd(relative)[2][:, 0]  # principal axis, (n_mid, 3)
            flip = np.sum((points[:, -1] - points[:, 0]) * direction, axis=1) < 0.0
            direction = np.where(flip[:, None], -direction, direction)
        t = np.einsum("nki,ni->nk", relative, direction)
        half = 0.5 * self.ply_thickness / np.einsum("nki,ni->nk", along_ply, direction)
        bottom, top = t[:, 0] - half[:, 0], t[:, -1] + half[:, -1]
        midpoint = centre + (0.5 * (bottom + top))[:, None] * direction
        if self.count > 1:
            gaps = (t[:, 1:] - half[:, 1:]) - (t[:, :-1] + half[:, :-1])
            gap = gaps.max(axis=1)
        else:
            gap = np.zeros(len(t))
        off_line = relative - t[:, :, None] * direction[:, None, :]
        normal = nodal_normals(midpoint, self.mid.triangles)
        cosine = np.clip(np.sum(direction * normal, axis=1), -1.0, 1.0)
        return MaterialLines(
            direction=direction,
            angle=np.arccos(cosine),
            thickness=top - bottom,
            midpoint=midpoint,
            gap=gap,
            normal=normal,
            straightness=np.linalg.norm(off_line, axis=2).max(axis=1),
        )
