"""A layup: plies of one fabric laid at different angles on a rectangular blank, each its own
mesh along its own fibres and its own shell, with ply-to-ply contact and Coulomb friction
between every ply and the plies below it (docs/theory.md §9.3b).

Each ply k (1 = bottom) is ``femcore.blank.ply_blank`` at its angle a_k: a mesh of right
triangles along its warp w_k = (cos a_k, sin a_k, 0) and weft, whole cells inside the blank
(the outline exact at 0, 90 and 45 deg mod 90), its mid-surface at z = bottom + (k - 1/2) h,
h the fabric's thickness (the plies' faces touch). The shell is a ``FibrousShell(fabric,
warp=w_k)`` ("fibrous"), a ``MindlinShell(fabric, warp=w_k)`` of the fabric's own laws
("mindlin", as a Mindlin part of that fabric and a case file's ``[layup]`` build it), a
``MindlinShell`` of the fabric's equivalent elastic section with the same warp
(``ElasticShell.equivalent(fabric, warp=w_k)``, the laws' initial slopes: "mindlin-elastic",
as the single-ply forming case), or any element a factory builds from (fabric, warp).
Neighbouring plies touch through ``PlyContact`` (the upper ply's lower face on the lower
ply's upper face, h / 2 from the mid-surfaces along the nodal normals of fibrous plies,
along the directors of Mindlin ones) with the Coulomb coefficient ``friction``; its node
fields hold the inter-ply slip (``ply_slip``, mm, elements/ply_slip.py).

Unlike ``elements.plies.PlyStack`` (copies of one mesh splitting one stack's thickness), the
plies here are whole fabrics with meshes of their own that do not match from ply to ply.
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Callable, Sequence
from typing import Any

import numpy as np

from elements.fibrous import FibrousShell
from elements.fibrous.fibres import fibre_ordering, shear_orientation
from elements.mindlin import MindlinShell
from elements.ply_contact import PAIRS, RULES, PlyContact, join_plies
from femcore.blank import ply_blank, ply_directions
from femcore.element import ElementType
from femcore.mesh import Mesh
from femcore.model import Model
from materials.elastic import ElasticShell
from materials.fabric import Fabric

__all__ = ["KINEMATICS", "Layup", "ply_element", "ply_shear"]

KINEMATICS = ("fibrous", "mindlin", "mindlin-elastic")
#: More plies than this is a typo rather than a preform.
MAX_PLIES = 200
#: Ply angles all within +-pi/2 (and a little: pi/2 rounded up to 1.5708), not all zero and
#: not all whole degrees, look like radians: warned.
RADIANS = 0.5 * math.pi + 1e-4


def ply_element(kinematics: str, fabric: Fabric, warp: np.ndarray, **options: Any) -> ElementType:
    """The shell of one ply, ``options`` passed to its element.

    "fibrous": ``FibrousShell(fabric, warp=warp)``; "mindlin": ``MindlinShell(fabric,
    warp=warp)``, the fabric's own laws (docs/theory.md §5.7); "mindlin-elastic":
    ``MindlinShell(ElasticShell.equivalent(fabric, warp=warp))``, the linear section of the
    laws' initial slopes (docs/theory.md §5.4).
    """
    if kinematics == "fibrous":
        return FibrousShell(fabric, warp=warp, **options)
    if kinematics == "mindlin":
        return MindlinShell(fabric, warp=warp, **options)
    if kinematics == "mindlin-elastic":
        return MindlinShell(ElasticShell.equivalent(fabric, warp=warp), **options)
    raise ValueError(f"kinematics must be one of {KINEMATICS}, got {kinematics!r}")


def _angles(angles: Any) -> tuple[float, ...]:
    """The ply angles as floats, degrees: any 1-D sequence of numbers (a list, a tuple, a
    1-D numpy array); a warning where they look like radians (``RADIANS``)."""
    if isinstance(angles, np.ndarray) and angles.ndim == 1:
        angles = angles.tolist()
    if isinstance(angles, (str, bytes)) or not isinstance(angles, Sequence):
        raise ValueError(
            f"angles must be a sequence of ply angles in degrees, bottom ply first, e.g. "
            f"(0, 90), got {angles!r}"
        )
    if not 1 <= len(angles) <= MAX_PLIES:
        raise ValueError(f"a layup needs 1 to {MAX_PLIES} plies, got {len(angles)} angles")
    out = []
    for k, angle in enumerate(angles):
        if isinstance(angle, bool) or not isinstance(angle, (int, float, np.integer, np.floating)):
            raise ValueError(f"ply {k + 1}: the angle must be a number of degrees, got {angle!r}")
        if not math.isfinite(angle):
            raise ValueError(f"ply {k + 1}: the angle must be finite, got {angle!r}")
        out.append(float(angle))
    magnitudes = np.abs(out)
    if (
        np.all(magnitudes <= RADIANS)
        and np.any(magnitudes > 0.0)
        and np.any(magnitudes != np.round(magnitudes))
    ):
        warnings.warn(
            f"ply angles {tuple(out)}: radians? angles are in degrees (every one within "
            f"+-{RADIANS:.4g}, not all zero and not whole numbers: +-pi/2 written in "
            "radians); write (0, 90), not (0, pi / 2)",
            UserWarning,
            stacklevel=3,
        )
    return tuple(out)


class Layup:
    """Plies of ``fabric`` at ``angles`` on an lx x ly blank, in one mesh (module docstring).

    Parameters
    ----------
    fabric : Fabric
        One ply's fabric (thickness h, mm).
    angles : sequence of float
        Each ply's warp angle from +x about +z, degrees, bottom ply first, e.g. (0, 90) or
        (0, 45).
    lx, ly : float
        The blank's sides, mm (ly None: square).
    cells : int
        Fibre segments across lx (``femcore.blank.ply_blank``).
    kinematics : str or callable
        "fibrous", "mindlin" (the fabric's own laws), "mindlin-elastic" (the equivalent
        elastic section) (``ply_element``), or ``element(fabric, warp) -> ElementType``.
    friction : float
        The Coulomb coefficient mu >= 0 between neighbouring plies (0: frictionless).
    bottom : float
        The height of the bottom ply's lower face, mm.
    centre : (2,) float
        The blank's centre in the plane, mm.
    penalty, rule, smoothing
        Of every ``PlyContact`` (None: their defaults).
    faces : str, optional
        Of every ``PlyContact``: "director" or "normal"; None: "normal" for fibrous plies
        (their directors tilt freely, elements/ply_contact.py "Faces along the normal"),
        "director" otherwise, judged from the shell ``kinematics`` builds (a factory's
        ``FibrousShell`` plies get "normal" too).
    surface : str
        Of every ``PlyContact``: "flat" (default) or "curved", the lower ply's face as the
        curved surface over its nodal normals (elements/ply_surface.py; the choice for plies
        whose meshes do not match on a curved tool).
    lower_rule : str, optional
        A key of ``elements.ply_contact.RULES``: every ``PlyContact`` then has its mirrored
        pass, the lower ply's points at that rule against the upper ply's face
        (elements/ply_contact.py, "Both ways"; "vertices": the lower ply's nodes); None
        (default): one pass, the upper ply's points alone.
    pairs : str
        Which plies touch, ``elements.ply_contact.PAIRS``: "all" (default), every ply on every
        ply below it (a pair that are not neighbours acts only at its points that face none of
        the plies between them, where those have left: a middle ply drawn out of the stack;
        elements/ply_between.py); "neighbours", ply k + 1 on ply k alone
        (``elements.ply_contact.join_plies``).

    Attributes
    ----------
    mesh : Mesh
        The plies as one mesh, ply after ply; node and triangle sets "ply_k" (1-based), the
        node sets of each ply's blank as "ply_k_<name>" ("left", "right", "bottom", "top",
        "outline") and their union over the plies as "<name>".
    angles : (N,) float
        Degrees.
    warps : (N, 3) float
        Unit warp directions.
    ply_nodes, ply_cells : list of (n_k,) and (m_k,) int
        Each ply's node and triangle ids in ``mesh``.
    heights : (N,) float
        Each ply's mid-surface height, mm.

    Raises
    ------
    ValueError
        Not a Fabric; angles that are not 1 to ``MAX_PLIES`` finite numbers; a bad size,
        cell count, kinematics, friction, penalty, rule, smoothing, faces, surface or
        lower_rule.

    Warns
    -----
    UserWarning
        A ply at an angle whose blank has a staircase outline (``ply_blank``); angles that
        look like radians (``RADIANS``).
    """

    def __init__(
        self,
        fabric: Fabric,
        angles: Sequence[float],
        lx: float,
        ly: float | None = None,
        cells: int = 20,
        kinematics: str | Callable[[Fabric, np.ndarray], ElementType] = "fibrous",
        friction: float = 0.0,
        bottom: float = 0.0,
        centre: Sequence[float] = (0.0, 0.0),
        penalty: float | None = None,
        rule: str = "centroid",
        smoothing: float | None = None,
        faces: str | None = None,
        surface: str = "flat",
        lower_rule: str | None = None,
        pairs: str = "all",
    ):
        if not isinstance(fabric, Fabric):
            raise ValueError(f"Layup needs a materials.Fabric (one ply), got {fabric!r}")
        self.fabric = fabric
        self.angles = np.array(_angles(angles))
        if isinstance(kinematics, str):
            if kinematics not in KINEMATICS:
                raise ValueError(
                    f"kinematics must be one of {KINEMATICS} or a callable (fabric, warp) -> "
                    f"ElementType, got {kinematics!r}"
                )
        elif not callable(kinematics):
            raise ValueError(
                f"kinematics must be one of {KINEMATICS} or a callable (fabric, warp) -> "
                f"ElementType, got {kinematics!r}"
            )
        self.kinematics = kinematics
        # the contact's options checked here, at the API boundary
        if faces is None:  # a fibrous ply's director tilts freely: its faces along the normal
            # (decided from the shell the plies are, not from how it is named: a factory's
            # fibrous plies too, else their faces follow the directors, a zero-energy path)
            built = self.element_of(ply_directions(0.0)[0])
            faces = "normal" if isinstance(built, FibrousShell) else "director"
        PlyContact(
            "ply_2",
            "ply_1",
            penalty=penalty,
            rule=rule,
            smoothing=smoothing,
            friction=friction,
            faces=faces,
            surface=surface,
        )
        if lower_rule is not None:
            if lower_rule not in RULES:  # (PlyContact's message names its own "rule")
                raise ValueError(
                    f"lower_rule must be None or one of {sorted(RULES)}, got {lower_rule!r}"
                )
            PlyContact("ply_2", "ply_1", rule=lower_rule, points="lower")
        self.lower_rule = lower_rule
        if pairs not in PAIRS:
            raise ValueError(f"pairs must be one of {PAIRS}, got {pairs!r}")
        self.pairs = pairs
        self.penalty, self.rule, self.smoothing, self.faces = penalty, rule, smoothing, faces
        self.surface = surface
        self.friction = float(friction)
        if isinstance(bottom, bool) or not isinstance(bottom, (int, float)):
            raise ValueError(f"bottom must be a height in mm, got {bottom!r}")
        centre_xy = np.asarray(centre, dtype=float).ravel()
        if centre_xy.shape != (2,) or not np.isfinite(centre_xy).all() or not math.isfinite(bottom):
            raise ValueError(
                f"centre must be a finite (x, y) and bottom finite, got {centre!r}, {bottom!r}"
            )
        ly = lx if ly is None else ly
        h = fabric.thickness
        self.heights = float(bottom) + (np.arange(len(self.angles)) + 0.5) * h
        self.warps = np.array([ply_directions(a)[0] for a in self.angles])
        blanks = [
            ply_blank(lx, ly, cells, angle, centre=(centre_xy[0], centre_xy[1], z))
            for angle, z in zip(self.angles, self.heights)
        ]
        self.blanks = blanks
        starts = np.cumsum([0] + [b.n_nodes for b in blanks])
        cell_starts = np.cumsum([0] + [len(b.triangles) for b in blanks])
        self.ply_nodes = [np.arange(starts[k], starts[k + 1]) for k in range(len(blanks))]
        self.ply_cells = [np.arange(cell_starts[k], cell_starts[k + 1]) for k in range(len(blanks))]
        node_sets: dict[str, np.ndarray] = {}
        cell_sets: dict[str, np.ndarray] = {}
        for k, blank in enumerate(blanks):
            node_sets[f"ply_{k + 1}"] = self.ply_nodes[k]
            cell_sets[f"ply_{k + 1}"] = self.ply_cells[k]
            for name, ids in blank.node_sets.items():
                node_sets[f"ply_{k + 1}_{name}"] = ids + starts[k]
        for name in blanks[0].node_sets:
            node_sets[name] = np.concatenate(
                [node_sets[f"ply_{k + 1}_{name}"] for k in range(len(blanks))]
            )
        self.mesh = Mesh(
            np.vstack([b.points for b in blanks]),
            triangles=np.vstack([b.triangles + s for b, s in zip(blanks, starts)]),
            node_sets=node_sets,
            element_sets=cell_sets,
        )

    @property
    def count(self) -> int:
        """N, the number of plies."""
        return len(self.angles)

    def element(self, k: int) -> ElementType:
        """The shell of ply ``k`` (1-based)."""
        return self.element_of(self.warps[k - 1])

    def element_of(self, warp: np.ndarray) -> ElementType:
        """The shell of a ply of unit warp ``warp`` (3,): ``ply_element``'s or the factory's."""
        if isinstance(self.kinematics, str):
            return ply_element(self.kinematics, self.fabric, warp)
        return self.kinematics(self.fabric, warp)

    def model(self) -> Model:
        """A Model of the layup: ply k's shell on triangle set "ply_k" (element block k - 1)
        and a ``PlyContact`` of ply k + 1 on ply k (interactions 0..N-2, offsets h / 2,
        friction mu; with ``lower_rule`` each followed by its mirrored pass, interactions
        0..2N-3, the pass of ply k + 1's points at 2k - 2), then with ``pairs="all"`` those
        of every ply on the plies below its neighbour (``elements.ply_contact.join_plies``).
        Supports, loads and tools are the caller's."""
        model = Model(self.mesh)
        for k in range(1, self.count + 1):
            model.add(self.element(k), cells=f"ply_{k}")
        half = 0.5 * self.fabric.thickness
        join_plies(
            model,
            self.count,
            half,
            pairs=self.pairs,
            penalty=self.penalty,
            rule=self.rule,
            smoothing=self.smoothing,
            friction=self.friction,
            faces=self.faces,
            surface=self.surface,
            lower_rule=self.lower_rule,
        )
        return model

    def shear(self, positions: np.ndarray) -> list[np.ndarray]:
        """Each ply's shear angle per triangle at ``positions`` (``ply_shear``), rad: a list
        of (m_k,) arrays, ply 1 first.

        Parameters
        ----------
        positions : (n, 3) float
            Positions of every node of ``mesh``, mm (rows past n, a model's tool nodes, are
            left out).
        """
        positions = np.asarray(positions, dtype=float)
        n = self.mesh.n_nodes
        if positions.ndim != 2 or positions.shape[1] != 3 or len(positions) < n:
            raise ValueError(
                f"positions must be ({n}, 3) or longer (every node of the layup first; the "
                f"nodes of force-driven tools after them), got {positions.shape}"
            )
        positions = positions[:n]
        triangles = self.mesh.triangles
        return [
            ply_shear(self.mesh.points, positions, triangles[cells], self.warps[k])
            for k, cells in enumerate(self.ply_cells)
        ]


def ply_shear(
    reference: np.ndarray, positions: np.ndarray, triangles: np.ndarray, warp: np.ndarray
) -> np.ndarray:
    """(m,) the shear angle of each fibre-aligned triangle, rad: 90 degrees less the angle
    between its deformed warp and weft legs, each leg taken in the sense of the fibre's
    positive direction (warp w, weft e3 x w in the reference plane), so that the sign is the
    pin-jointed net's (validation/references/drape.py: positive where the warp and the weft
    close up) at every ply angle.

    Parameters
    ----------
    reference, positions : (n, 3) float
        Reference and current positions, mm.
    triangles : (m, 3) int
        Right triangles with their legs along the fibres (``femcore.blank.ply_blank``).
    warp : (3,) float
        The ply's unit warp in the reference plane.
    """
    # The fibrous shell's own fibre frame (Bai Eq. 9): node 0 at the right-angled corner, and
    # the sign that gives the shear one convention in every cell.
    warp = np.asarray(warp, dtype=float)
    cells = np.arange(len(triangles))
    connectivity, xi_is_warp = fibre_ordering(reference, triangles, cells, warp, 1.0)
    sign = shear_orientation(reference, connectivity, xi_is_warp, warp)
    x = positions[connectivity]
    legs = x[:, 1] - x[:, 0], x[:, 2] - x[:, 0]  # along the two fibres (either order)
    cosine = np.sum(legs[0] * legs[1], axis=1) / (
        np.linalg.norm(legs[0], axis=1) * np.linalg.norm(legs[1], axis=1)
    )
    return sign * (0.5 * np.pi - np.arccos(np.clip(cosine, -1.0, 1.0)))
