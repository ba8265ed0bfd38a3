"""A ply contact point carried round a feature of the lower ply's face past its outline: the
set-up shared by tests/test_ply_growth_sign.py, tests/test_ply_wedge.py and
tests/test_ply_fade_hessian.py, and the contact's tangent assembled dense over the translations.

One upper triangle 0.02 mm across (its centroid the contact point, moved rigidly, the
directors held along z) circles (0, ``past``, 0.2) at ``radius`` in the x-z plane: its face
p = x - 0.1 z circles (0, ``past``, 0.1), the lower face's point above the origin (faces 0.1
mm from the mid-surfaces). The lower ply's outline runs along y = 0 through the origin.
"""

import numpy as np

from elements.ply_contact import PlyContact
from femcore import Body, Mesh
from femcore.state import State


def point_round(
    low: np.ndarray,
    lower: np.ndarray,
    *,
    steps: int,
    penalty: float,
    radius: float,
    past: float,
    bound_at: np.ndarray | None = None,
):
    """(block, positions (steps + 1, n, 3), directors (n, 3)): the lower ply's nodes ``low``
    (l, 3) and triangles ``lower`` (t, 3) with the upper triangle of the module docstring
    (nodes l, l + 1, l + 2), bound as a ply contact of ``penalty`` N/mm at the centroid, and
    the path of ``steps`` steps round the circle of ``radius`` mm ``past`` mm past the
    outline. ``bound_at`` (l, 3): the lower ply's nodes when the contact is bound (its
    reference state), ``low`` when None; the path is walked with them at ``low``."""
    side = 0.02
    tiny = np.array([[0.0, 0.0, 0.0], [side, 0.0, 0.0], [0.0, side, 0.0]])
    tiny -= tiny.mean(axis=0)
    points = np.vstack([low, tiny])
    first = len(low)
    upper = np.arange(first, first + 3)
    reference = points if bound_at is None else np.vstack([bound_at, tiny])
    mesh = Mesh(
        reference,
        triangles=np.vstack([lower, upper[None]]),
        node_sets={"upper": upper},
        element_sets={"lower": np.arange(len(lower))},
    )
    n = len(points)
    directors = np.tile([0.0, 0.0, 1.0], (n, 1))
    active = np.zeros((n, 6), dtype=bool)
    active[:, :5] = True
    contact = PlyContact("upper", "lower", 0.1, 0.1, penalty=penalty, rule="centroid")
    block = contact.bind(Body(mesh, (), directors, active))
    angle = np.linspace(0.0, 2.0 * np.pi, steps + 1)
    centre = np.array([0.0, past, 0.1 + 0.1])
    path = centre + radius * np.column_stack([np.cos(angle), np.zeros_like(angle), np.sin(angle)])
    positions = np.repeat(points[None], steps + 1, axis=0)
    positions[:, first:] += path[:, None, :]
    return block, positions, directors


def walk(block, positions: np.ndarray, directors: np.ndarray) -> dict[str, np.ndarray]:
    """Along the path: energy (s + 1,) N mm, work (s,) N mm of each step by the trapezoidal
    rule, and the point's facing fields touching, joined (False where the facing carries no
    such field), gap (mm) and fade, each (s + 1,)."""
    zero = np.zeros_like(positions[0])
    energy, forces, touching, joined, gaps, fades = [], [], [], [], [], []
    for x in positions:
        state = State(x, directors, zero, zero)
        facing = block.facing(state)
        energy.append(block.strain_energy(state))
        forces.append(block.internal_force(state)[0])
        touching.append(bool(facing.touching[0]))
        on_joined = getattr(facing, "joined", None)
        joined.append(bool(on_joined is not None and on_joined[0]))
        gaps.append(float(facing.gap[0]))
        fades.append(float(facing.fade[0]))
    forces_ = np.array(forces)
    work = np.einsum("sni,sni->s", 0.5 * (forces_[1:] + forces_[:-1]), np.diff(positions, axis=0))
    return {
        "energy": np.array(energy),
        "work": work,
        "touching": np.array(touching),
        "joined": np.array(joined),
        "gap": np.array(gaps),
        "fade": np.array(fades),
    }


def translational_tangent(block, state: State) -> np.ndarray:
    """The contact block's tangent at ``state`` assembled dense over the nodes' translations
    (3n, 3n), N/mm: each part's (row, i, :3, j, :3) blocks summed at nodes (a, b)."""
    size = state.positions.size
    tangent = np.zeros((size, size))
    for part in block.tangent(state):
        for row in range(len(part.nodes)):
            for i, a in enumerate(part.nodes[row]):
                for j, b in enumerate(part.nodes[row]):
                    tangent[3 * a : 3 * a + 3, 3 * b : 3 * b + 3] += part.blocks[row, i, :3, j, :3]
    return tangent
