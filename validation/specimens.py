"""Specimens of Bai et al. (2020) §5.1 and §6, built for either kinematics on the same mesh.

Two geometries:

* ``strip``: the cantilever of §5.1 (Fig. 6a), an L x b strip clamped at x = 0 whose end
  x = L is moved horizontally and vertically.
* ``corner``: the specimens of §6.1-6.2 (Fig. 8). Of an L x W rectangle, the triangle beyond the
  diagonal is clamped (§6.1.1, 6.2.1: "the part above the diagonal 1-3 is clamped"; §6.1.2,
  6.2.2: "the diagonal is clamped", the same boundary condition for the free part). Only the
  free triangle is meshed (``femcore.Mesh.corner``): corners (0, 0) (the loaded corner), (L, 0)
  and (0, W); the clamp is the diagonal from (L, 0) to (0, W). With n x n cells the cell
  diagonals of ``Mesh.rectangle`` run parallel to it, so the clamp is a straight line of mesh
  edges and the fibrous shell can use its exact clamped-edge curvature
  (``FibrousShell(clamped=...)``).

Sides (the specimen edges filmed in the experiments): side 1 along the warp (y = 0, from the
clamp at x = L to the corner at x = 0), side 2 along the weft (x = 0, from y = W to y = 0).
``s`` is the distance from the clamp along the side (mm).

Gravity is -z in every case. Units: mm, N, t, s.

Also the set-ups that several validation cases, tests and benchmarks build alike: the Mindlin
cantilever strip (``mindlin_strip``), the fibrous cantilever strip under its own weight
(``fibrous_strip``), the strip bent into an arc of the deck-of-cards cases (``deck_of_cards``)
and the hanging chain of the catenary cases (``hanging_chain``).
"""

from __future__ import annotations

import functools
from dataclasses import dataclass

import numpy as np

from elements import Cable, FibrousShell, Grip, MindlinShell
from femcore import Mesh, Model
from fibreshell.calibration import Calibration
from materials import ElasticShell, Fabric

__all__ = [
    "CHAIN_DROP",
    "CHAIN_LENGTH",
    "CHAIN_MU",
    "CHAIN_SEGMENTS",
    "CHAIN_SPAN",
    "CORNER_LIFT",
    "G1151_SIZE",
    "GRAVITY",
    "PAPER_STACK_GRIP",
    "PAPER_STACK_SIZE",
    "Specimen",
    "arc_length",
    "box_chain",
    "build",
    "corner",
    "deck_of_cards",
    "fibrous_strip",
    "grip_stiffness",
    "hanging_chain",
    "holder_ring",
    "mindlin_equivalent",
    "mindlin_fabric_strip",
    "mindlin_strip",
    "strip",
]

GRAVITY = 9810.0  # mm/s^2
# Sizes (L, W) in mm of the §6 corner specimens: A5 paper sheets (assumed; §6.1) and the G1151
# laminate (§6.2); the §6.1.1 / §6.2.1 corner lift (ux, uy, uz; None = free), assumed.
PAPER_STACK_SIZE = (210.0, 148.0)
# The patch (a, b) in mm at the paper stack's corner that a gripper holds in §6.1.1 (assumed:
# one tenth of each side, as bai-6.2.1's; shared by bai-6.1.1 and its sensitivity study).
PAPER_STACK_GRIP = (21.0, 14.8)
G1151_SIZE = (200.0, 150.0)
CORNER_LIFT = (None, None, 40.0)
# The chain of the catenary cases: span and unstretched length (mm), the depth of the box it
# starts as (mm), its mass per length (t/mm) and the segments per resolution.
CHAIN_SPAN, CHAIN_LENGTH, CHAIN_DROP, CHAIN_MU = 96.0, 120.0, 12.0, 1.0e-6
CHAIN_SEGMENTS = {"coarse": 20, "default": 40, "fine": 160}


@dataclass(frozen=True)
class Specimen:
    """A meshed specimen: the mesh, its clamp, its loaded nodes and its two filmed sides."""

    mesh: Mesh
    clamp: np.ndarray  # node ids, fully fixed (translations and directors)
    loaded: np.ndarray  # node ids of the imposed displacement
    sides: dict  # {"side_1": (node ids ordered from the clamp, s (mm)), "side_2": ...}
    # The loaded nodes are a patch a gripper holds: they translate together (elements.Grip) and
    # their directors (Mindlin: rotations) are held, as the jaws of a clamp hold the plies
    # (``build``).
    gripped: bool = False


def strip(length: float, width: float, cells: int, across: int = 1) -> Specimen:
    """§5.1 cantilever: clamp at x = 0, displacement imposed at x = L; side 1 = the strip's
    edge y = 0, side 2 = its centre line is not a free edge, so only side 1 is filmed."""
    mesh = Mesh.rectangle(length, width, nx=cells, ny=across)
    p = mesh.points
    edge = np.flatnonzero(np.abs(p[:, 1]) < 1e-9 * width)
    edge = edge[np.argsort(p[edge, 0])]
    return Specimen(
        mesh=mesh,
        clamp=mesh.nodes("left"),
        loaded=mesh.nodes("right"),
        sides={"side_1": (edge, p[edge, 0].copy())},
    )


def corner(
    length: float, width: float, cells: int, grip: float | tuple[float, float] | None = None
) -> Specimen:
    """§6 corner specimen: the free triangle of an L x W rectangle with n x n cells
    (``Mesh.corner``: node sets "clamp" and "corner"), with its two filmed sides.

    Parameters
    ----------
    length, width : float
        L along x (warp) and W along y (weft), mm.
    cells : int
        n, cells along each side of the rectangle before the cut.
    grip : float, (a, b) or None
        None: the loaded nodes are the corner node alone (a point load). A size (mm): the
        a x b patch at the corner that a gripper holds is the loaded set (``Mesh.corner``'s
        node set "grip", on grid lines at every n, so the same physical patch at every
        resolution), its directors held too (``Specimen.gripped``).

    Returns
    -------
    Specimen
    """
    mesh = Mesh.corner(length, width, cells, grip)
    points = mesh.points
    side_1 = np.flatnonzero(np.abs(points[:, 1]) < 1e-9 * width)
    side_1 = side_1[np.argsort(-points[side_1, 0])]
    side_2 = np.flatnonzero(np.abs(points[:, 0]) < 1e-9 * length)
    side_2 = side_2[np.argsort(-points[side_2, 1])]
    return Specimen(
        mesh=mesh,
        clamp=mesh.nodes("clamp"),
        loaded=mesh.nodes("corner" if grip is None else "grip"),
        sides={
            "side_1": (side_1, length - points[side_1, 0]),
            "side_2": (side_2, width - points[side_2, 1]),
        },
        gripped=grip is not None,
    )


def bias_extension_mesh(length: float, width: float, cells: int) -> Mesh:
    """A bias-extension specimen: an L x W rectangle meshed with fibres at +/-45 deg to x.

    The nodes are the points (i a, j a), a = L / (2 cells), with i + j even: squares standing
    on a corner ("diamonds", diagonal 2 a, ``cells`` of them along x), each split along its
    horizontal diagonal, so that every triangle has its right angle between a +45 and a -45
    deg edge (the fibre directions of the fibrous shell are the two edges at that corner).
    The half-diamonds at the ends are split along the vertical diagonal. W must be a whole
    number of a. Node sets "left" (x = 0) and "right" (x = L).
    """
    a = length / (2 * cells)
    rows = round(width / a)
    if cells < 1 or rows < 2 or abs(rows * a - width) > 1e-9 * width:
        raise ValueError(
            f"a bias-extension mesh needs W = k L / (2 cells) with k >= 2, got L = {length}, "
            f"W = {width}, cells = {cells}"
        )
    columns = 2 * cells
    i, j = np.meshgrid(np.arange(columns + 1), np.arange(rows + 1), indexing="ij")
    keep = (i + j) % 2 == 0
    number = np.full(i.shape, -1)
    number[keep] = np.arange(int(keep.sum()))
    points = np.column_stack([i[keep] * a, j[keep] * a, np.zeros(int(keep.sum()))])
    ci, cj = np.meshgrid(np.arange(columns + 1), np.arange(rows + 1), indexing="ij")
    centre = (ci + cj) % 2 == 1
    ci, cj = ci[centre], cj[centre]
    triangles = []
    inner = (ci > 0) & (ci < columns)
    up = inner & (cj < rows)
    down = inner & (cj > 0)
    triangles.append(
        np.column_stack(
            [number[ci[up] - 1, cj[up]], number[ci[up] + 1, cj[up]], number[ci[up], cj[up] + 1]]
        )
    )
    triangles.append(
        np.column_stack(
            [
                number[ci[down] - 1, cj[down]],
                number[ci[down], cj[down] - 1],
                number[ci[down] + 1, cj[down]],
            ]
        )
    )
    for end, side in ((0, 1), (columns, -1)):  # the half-diamonds at x = 0 and x = L
        at = (ci == end) & (cj > 0) & (cj < rows)
        corner_i = ci[at] + side
        tri = np.column_stack(
            [number[ci[at], cj[at] - 1], number[corner_i, cj[at]], number[ci[at], cj[at] + 1]]
        )
        triangles.append(tri if side > 0 else tri[:, ::-1])
    mesh = Mesh(points, np.concatenate(triangles))
    x = points[:, 0]
    mesh.add_node_set("left", np.flatnonzero(x < 1e-9 * length))
    mesh.add_node_set("right", np.flatnonzero(x > length * (1.0 - 1e-9)))
    return mesh


def pin_jointed_shear(length: float, width: float, elongation: float) -> float:
    """Shear angle (rad) of the central zone of a bias-extension test by the pin-jointed net
    (inextensible fibres, no slip): gamma = pi/2 - 2 acos((D + d) / (sqrt(2) D)), D = L - W,
    d the elongation (Cao et al., Compos. Part A 39 (2008) 1037)."""
    gauge = length - width
    return float(np.pi / 2 - 2 * np.arccos((gauge + elongation) / (np.sqrt(2.0) * gauge)))


def mindlin_strip(
    length: float, width: float, thickness: float, young: float, cells: int, across: int = 1
) -> tuple[Mesh, Model]:
    """An isotropic Mindlin strip (nu = 0, so that beam references apply) of cells x across
    cells, clamped at x = 0 (node set "left"); loads are the caller's."""
    mesh = Mesh.rectangle(length, width, nx=cells, ny=across)
    model = Model(mesh)
    model.add(MindlinShell(ElasticShell(young, 0.0, thickness, 1e-9)))
    model.fix("left")
    return mesh, model


def fibrous_strip(
    length: float, width: float, fabric: Fabric, cells: int, across: int = 1
) -> tuple[Mesh, Model]:
    """A fibrous cantilever strip of cells x across cells under its own weight: clamped at
    x = 0 (node set "left", with the clamped-edge option of the rotation-free bending),
    gravity -z."""
    mesh = Mesh.rectangle(length, width, nx=cells, ny=across)
    model = Model(mesh)
    model.add(FibrousShell(fabric, clamped="left"))
    model.fix("left")
    model.gravity((0.0, 0.0, -GRAVITY))
    return mesh, model


def mindlin_fabric_strip(
    length: float, width: float, fabric: Fabric, cells: int, across: int = 1
) -> tuple[Mesh, Model]:
    """The Mindlin twin of ``fibrous_strip``: ``MindlinShell(fabric)`` (the section by stress
    resultants from the fabric's own laws) on the same mesh, clamped at x = 0 (node set
    "left": translations and rotations fixed), gravity -z."""
    mesh = Mesh.rectangle(length, width, nx=cells, ny=across)
    model = Model(mesh)
    model.add(MindlinShell(fabric))
    model.fix("left")
    model.gravity((0.0, 0.0, -GRAVITY))
    return mesh, model


@dataclass(frozen=True)
class DeckOfCards:
    """A fibrous strip whose mid-surface is carried onto a circular arc, its directors free.

    mesh, model : the strip and its model (clamped at x = 0, every other node displaced).
    rotation : (n,) rad, the rotation theta of the mid-surface at each node from the clamp.
    normal : (n, 3) the exact unit normal of the arc at each node.
    """

    mesh: Mesh
    model: Model
    rotation: np.ndarray
    normal: np.ndarray


def deck_of_cards(
    cells: int,
    bend: float,
    fabric: Fabric,
    thickness: str = "nodal",
    length: float = 100.0,
    width: float = 5.0,
) -> DeckOfCards:
    """Pure bending of a stack into an arc: a length x width strip of cells x 1 cells, clamped
    at x = 0 (translations and directors fixed), every other node moved onto the circular arc
    of total angle ``bend`` (rad) that starts horizontally at the clamp and curls up towards
    +z, its nodes one element length apart along the chords (the fibres of the mid-surface
    keep their length). Only the directors of the free nodes are unknown: they settle where
    the fibres of the other levels keep their length too.
    """
    mesh = Mesh.rectangle(length, width, nx=cells, ny=1)
    p = mesh.points
    radius = length / bend
    spacing = length / cells
    step = 2.0 * np.arcsin(spacing / (2.0 * radius))
    rotation = np.rint(p[:, 0] / spacing) * step
    target = np.column_stack(
        [radius * np.sin(rotation), p[:, 1], radius * (1.0 - np.cos(rotation))]
    )
    model = Model(mesh)
    model.add(FibrousShell(fabric, thickness=thickness))
    model.fix("left")
    moved = np.flatnonzero(rotation > 0.0)
    shift = target[moved] - p[moved]
    model.displace(moved, ux=shift[:, 0], uy=shift[:, 1], uz=shift[:, 2])
    normal = np.column_stack([-np.sin(rotation), np.zeros_like(rotation), np.cos(rotation)])
    return DeckOfCards(mesh, model, rotation, normal)


def box_chain(segments: int) -> Mesh:
    """A chain of ``segments`` equal links (multiple of 10) hung as a box between two supports
    ``CHAIN_SPAN`` apart: down ``CHAIN_DROP``, across, up."""
    leg, across = segments // 10, segments - 2 * (segments // 10)
    corners = np.array(
        [[0.0, 0, 0], [0, 0, -CHAIN_DROP], [CHAIN_SPAN, 0, -CHAIN_DROP], [CHAIN_SPAN, 0, 0]]
    )
    pieces = [corners[0]]
    for a, b, n in zip(corners[:-1], corners[1:], (leg, across, leg)):
        pieces.extend(a + (b - a) * np.arange(1, n + 1)[:, None] / n)
    points = np.array(pieces)
    lines = np.column_stack([np.arange(len(points) - 1), np.arange(1, len(points))])
    return Mesh(points, lines=lines)


def hanging_chain(segments: int, axial_stiffness: float) -> Model:
    """The box chain of cables (EA = ``axial_stiffness``, mass ``CHAIN_MU`` per length) pinned
    at its two ends (z = 0), under gravity -z."""
    mesh = box_chain(segments)
    model = Model(mesh)
    model.add(Cable(axial_stiffness, CHAIN_MU))
    model.fix(mesh.nodes(lambda x, y, z: np.isclose(z, 0.0)))
    model.gravity((0.0, 0.0, -GRAVITY))
    return model


def arc_length(mesh: Mesh) -> np.ndarray:
    """Distance of each node of a chain from its first node along the chain."""
    return np.r_[0.0, np.cumsum(np.linalg.norm(np.diff(mesh.points, axis=0), axis=1))]


def mindlin_equivalent(fabric: Fabric, shear_ratio: float = 0.5) -> ElasticShell:
    """The "initial-slope" section of a fabric (``materials.ElasticShell.equivalent``; the
    paper cases use the fabric's own laws, ``build``)."""
    return ElasticShell.equivalent(fabric, shear_ratio)


def grip_stiffness(fabric: Fabric) -> float:
    """The stiffness (N/mm) of the springs that make a gripped patch translate as one
    (elements.Grip): 10 times the fibres' tension stiffness per unit width, so that the
    nodes of a patch part by a tenth of the strain the load would give the fabric over 1 mm
    (measured on bai-6.2.1: 1e-3 mm at most, for either kinematics)."""
    return 10.0 * float(fabric.tension.slope(np.array(0.0)))


def build(
    specimen: Specimen,
    kinematics: str,
    fabric: Fabric,
    displacement: tuple[float | None, float | None, float | None],
    calibration: Calibration | str = "laws",
    levels: int = 3,
    thickness: str = "nodal",
) -> Model:
    """Model of a specimen with "fibrous" or "mindlin" kinematics, clamp fixed, gravity, and
    ``displacement`` (ux, uy, uz; None leaves a component free) imposed on the loaded nodes,
    which translate together (elements.Grip, ``grip_stiffness``) and whose directors (Mindlin:
    rotations) are held when the specimen is ``gripped``.

    Parameters
    ----------
    specimen : Specimen
    kinematics : str
        "fibrous" or "mindlin".
    fabric : materials.Fabric
    displacement : (ux, uy, uz)
        mm; None leaves a component free.
    calibration : fibreshell.calibration.Calibration or str
        How the Mindlin shell is made of the fibrous one (``Calibration.mindlin``): "laws"
        (default: ``MindlinShell(fabric)``, the fabric's own laws, so that the comparison
        changes the kinematics alone), "fit" values or "initial-slope". The case files build
        their Mindlin shell by the same rule (``fibreshell.case.Case.model``), so a case file
        and this function give the same model.
    levels : int
        Fibre levels of the fibrous shell.
    thickness : str
        The fibrous shell's option of the same name: "nodal" (the thickness along the
        director from the nodal normals, the default) or "element" (Bai Eq. 15).

    Returns
    -------
    femcore.Model
    """
    model = Model(specimen.mesh)
    fibrous = FibrousShell(fabric, levels=levels, clamped=specimen.clamp, thickness=thickness)
    if kinematics == "fibrous":
        model.add(fibrous)
    elif kinematics == "mindlin":
        model.add(Calibration.from_options(calibration).mindlin(fibrous))
    else:
        raise ValueError(f"kinematics must be 'fibrous' or 'mindlin', got {kinematics!r}")
    model.fix(specimen.clamp)
    ux, uy, uz = displacement
    model.displace(specimen.loaded, ux=ux, uy=uy, uz=uz)
    if specimen.gripped:
        model.fix(specimen.loaded, ("alpha", "beta"))
        model.interact(Grip(specimen.loaded, grip_stiffness(fabric)))
    model.gravity((0.0, 0.0, -GRAVITY))
    return model


def hemisphere_die(radius: float, flange: float, rings: int, rim: float = 0.0) -> Mesh:
    """A forming die meshed with triangles: a hemispherical bowl of ``radius`` (mm, centre
    at the origin, rim at z = 0) and a flat flange out to radius ``flange``, for
    ``elements.RigidSurface``. ``rings`` rings of points from the bowl's bottom pole to its
    rim at equal angles, the flange's rings as wide; each ring has as many points as make its
    spacing that width, so the facets are all of about one size (no slivers at the pole),
    and neighbouring rings are zipped into triangles in order of angle. The facets' normals
    point up and into the bowl (the side the blank is on).

    ``rim`` (mm, default 0: a sharp edge): the radius of a round joining the bowl to the
    flange, tangent to both, as a forming die's entry radius. Its centre lies rim below the
    flange and radius + rim from the bowl's centre, so the flange starts at sqrt(radius^2 +
    2 radius rim) from the axis and the bowl ends at the polar angle whose sine is that over
    radius + rim; the round has rings as wide as the others (at least two).

    The arrays of a die are made once a process (zipping the rings is a loop over them, 0.2 s
    of CPU for the report's 48-ring dice, which the hemisphere cases build once a run: four
    runs in hemisphere-plies); each Mesh copies them (femcore/topology.py)."""
    if rim < 0.0:
        raise ValueError(f"hemisphere_die rim must be >= 0, got {rim}")
    if isinstance(rings, bool) or not isinstance(rings, (int, np.integer)) or rings < 1:
        raise ValueError(f"hemisphere_die rings must be a whole number >= 1, got {rings!r}")
    points, triangles = _die_arrays(float(radius), float(flange), int(rings), float(rim))
    return Mesh(points, triangles=triangles)


@functools.lru_cache(maxsize=8)
def _die_arrays(
    radius: float, flange: float, rings: int, rim: float
) -> tuple[np.ndarray, np.ndarray]:
    """The points (p, 3) and triangles (t, 3) of ``hemisphere_die``, kept by the cache: the
    caller copies them."""
    width = radius * 0.5 * np.pi / rings
    start = np.sqrt(radius**2 + 2.0 * radius * rim)  # the flange's inner radius
    last = np.arcsin(start / (radius + rim))  # the bowl's last polar angle (pi/2 sharp)
    polar = np.linspace(0.0, last, max(1, round(radius * last / width)) + 1)[1:]
    # The round: from the bowl's tangent point (angle pi - atan(rim / start) about its
    # centre (start, -rim) in the (r, z) plane) to the flange's (angle pi/2).
    span = 0.5 * np.pi - np.arctan2(rim, start)
    turn = np.linspace(0.5 * np.pi + span, 0.5 * np.pi, max(2, round(rim * span / width)) + 1)
    turn = turn[1:] if rim > 0.0 else turn[:0]
    outer = np.linspace(start, flange, max(1, round((flange - start) / width)) + 1)[1:]
    ring_radius = np.r_[radius * np.sin(polar), start + rim * np.cos(turn), outer]
    ring_z = np.r_[-radius * np.cos(polar), -rim + rim * np.sin(turn), np.zeros(len(outer))]
    points = [np.array([[0.0, 0.0, -radius]])]
    angles = [np.zeros(1)]
    for r, z in zip(ring_radius, ring_z):
        count = max(6, round(2.0 * np.pi * r / width))
        angle = np.linspace(0.0, 2.0 * np.pi, count, endpoint=False)
        points.append(np.column_stack([r * np.cos(angle), r * np.sin(angle), np.full(count, z)]))
        angles.append(angle)
    starts = np.cumsum([0] + [len(a) for a in angles])
    triangles = []
    for ring in range(len(angles) - 1):
        triangles += _zip_rings(angles[ring], angles[ring + 1], starts[ring], starts[ring + 1])
    return np.vstack(points), np.array(triangles)


def holder_ring(
    inner: float,
    outer: float,
    width: float,
    edge: float | None = None,
    wall: float | None = None,
) -> Mesh:
    """A blank holder meshed with triangles: an annulus in the plane z = 0 from radius
    ``inner`` to ``outer`` (mm, about the z axis), facets of about ``width`` mm, for
    ``elements.RigidSurface``. Its facets' normals point down (the side the blank is on, the
    holder pressing it onto a die's flange from above); move it to its height with the tool's
    own offset or by shifting the points.

    With ``edge`` and ``wall`` (mm) the holder has a bore, as a press's holder has: the face
    turns up at ``inner`` over a quarter round of radius ``edge`` (the face flat from
    ``inner + edge`` out) into a cylindrical wall of radius ``inner`` up to ``edge + wall``
    above the face, its normals towards the axis. Without it the flat ring ends in an open
    edge at ``inner``, and a point that rises above the face in the bore and then moves out
    past that edge's line is inside the ring at once, as deep as it rose
    (``RigidSurface``'s open edges): its contact energy jumps by k h^2 / 2 within a step
    (docs/hemisphere_plies.md, "The holder's bore"). With the wall the signed distance of
    such a point goes continuously through zero at the wall.
    """
    if not 0.0 < inner < outer:
        raise ValueError(f"holder_ring needs 0 < inner < outer, got {inner} and {outer}")
    if (edge is None) != (wall is None):
        raise ValueError(
            f"holder_ring takes its bore's edge and wall together, got edge={edge!r} and "
            f"wall={wall!r}"
        )
    round_off = 0.0 if edge is None else float(edge)
    height = 0.0 if wall is None else float(wall)
    if edge is not None and not (0.0 < round_off < outer - inner and height > 0.0):
        raise ValueError(
            f"holder_ring's bore needs 0 < edge < outer - inner and wall > 0 (mm), got "
            f"edge={edge!r} and wall={wall!r}"
        )
    face_from = inner + round_off
    if not 0.0 < width < outer - face_from:
        raise ValueError(f"holder_ring width must be in (0, {outer - face_from}), got {width}")
    radii = np.linspace(face_from, outer, max(1, round((outer - face_from) / width)) + 1)
    heights = np.zeros(len(radii))
    if edge is not None:
        # the profile from the wall's top down the wall and round the edge to the face, in
        # the order the rings are zipped (inside first: the face's normals stay down)
        top = np.linspace(round_off + height, round_off, max(1, round(height / width)) + 1)[:-1]
        turns = max(2, round(0.5 * np.pi * round_off / min(width, 0.25 * round_off)))
        angle = np.linspace(0.5 * np.pi, 0.0, turns + 1)[:-1]
        radii = np.r_[np.full(len(top), inner), face_from - round_off * np.sin(angle), radii]
        heights = np.r_[top, round_off - round_off * np.cos(angle), heights]
    points, angles = [], []
    for r, z in zip(radii, heights):
        count = max(6, round(2.0 * np.pi * r / width))
        angle = np.linspace(0.0, 2.0 * np.pi, count, endpoint=False)
        points.append(np.column_stack([r * np.cos(angle), r * np.sin(angle), np.full(count, z)]))
        angles.append(angle)
    starts = np.cumsum([0] + [len(a) for a in angles])
    triangles = []
    for ring in range(len(angles) - 1):
        triangles += _zip_rings(angles[ring], angles[ring + 1], starts[ring], starts[ring + 1])
    # _zip_rings winds counter-clockwise seen from +z (normals up): reverse for a holder.
    return Mesh(np.vstack(points), triangles=np.array(triangles)[:, ::-1])


def _zip_rings(inner: np.ndarray, outer: np.ndarray, first_inner: int, first_outer: int):
    """Triangles between two closed rings of points at the given angles (ascending from 0),
    walking both rings by angle; the inner ring may be the single pole point. Counter-
    clockwise seen from +z."""
    triangles = []
    i = j = 0
    n_in, n_out = len(inner), len(outer)
    while i < n_in or j < n_out:
        a, b = first_inner + i % n_in, first_outer + j % n_out
        next_in = inner[i + 1] if i + 1 < n_in else 2.0 * np.pi
        next_out = outer[j + 1] if j + 1 < n_out else 2.0 * np.pi
        if n_in > 1 and i < n_in and (j >= n_out or next_in <= next_out):
            triangles.append([a, b, first_inner + (i + 1) % n_in])
            i += 1
        else:
            triangles.append([a, b, first_outer + (j + 1) % n_out])
            j += 1
        if n_in == 1 and j >= n_out:
            break
    return triangles


def fibonacci_sphere(radius: float, points: int) -> Mesh:
    """A closed triangulated sphere of ``radius`` (mm) about the origin: the convex hull of a
    Fibonacci lattice of ``points`` points (2 points - 4 facets), normals outwards; a meshed
    tool whose exact analytic twin is elements.RigidSphere."""
    from scipy.spatial import ConvexHull

    k = np.arange(points) + 0.5
    polar = np.arccos(1.0 - 2.0 * k / points)
    azimuth = np.pi * (1.0 + 5.0**0.5) * k
    x = radius * np.column_stack(
        [np.sin(polar) * np.cos(azimuth), np.sin(polar) * np.sin(azimuth), np.cos(polar)]
    )
    triangles = ConvexHull(x).simplices
    a, b, c = (x[triangles[:, i]] for i in range(3))
    inward = np.sum(np.cross(b - a, c - a) * (a + b + c), axis=1) < 0
    triangles[inward] = triangles[inward][:, ::-1]
    return Mesh(x, triangles=triangles)
