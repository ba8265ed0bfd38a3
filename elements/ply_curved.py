"""The curved faces of a ply contact (``PlyContact(surface="curved")``, elements/ply_contact.py
"Curved faces"): each contact point projected on the Phong surface over the facet the flat
search picked, and the contact's loads as the exact gradient of its energy over that surface,
the nodal normals' dependence on the positions included (the surface itself and its
derivatives: elements/ply_surface.py).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from elements import ply_surface
from elements.ply_projection import MARGIN, Facing, penalty_law
from femcore.state import State

if TYPE_CHECKING:
    from elements.ply_block import PlyContactBlock

__all__ = ["curved_facing", "curved_loads"]


def curved_facing(
    block: PlyContactBlock, state: State, p: np.ndarray, y: np.ndarray, flat: Facing
) -> Facing:
    """Each point's facing on the curved surface over the facet the flat search picked
    (``flat``): p (P, 3) the points, y (m, 3, 3) the lower triangles' offset corners, mm."""
    # the curved surface over the facet the flat search picked (elements/ply_surface.py)
    normals = ply_surface.nodal_normals(state.positions, block._own_triangles, block.n_nodes)[0]
    lam, _, normal, gap, _, _ = ply_surface.project(
        p, y[flat.triangle], normals[block.cells[flat.triangle]], flat.weights
    )
    overshoot = np.maximum(0.0, -lam.min(axis=1))
    return Facing(
        triangle=flat.triangle,
        gap=gap,
        normal=normal,
        weights=lam,
        gradients=flat.gradients,
        touching=(gap <= block.tolerance) & (overshoot <= MARGIN),
        face=p,
    )


def curved_loads(
    block: PlyContactBlock, state: State, facing: Facing
) -> tuple[np.ndarray, np.ndarray]:
    """The exact gradient of sum W over the curved surface (elements/ply_surface.py):
    forces (n, 3), N, and moments (n, 3), N mm, the nodal normals' dependence on the
    positions carried back to the plies' nodes."""
    on = np.flatnonzero(facing.touching)
    law = penalty_law(facing.gap[on], block.stiffness[on], block.smoothing)
    x = state.positions
    normals, lengths = ply_surface.nodal_normals(x, block._own_triangles, block.n_nodes)
    d = normals if block.along_normals else state.directors
    rows = facing.triangle[on]
    tri = block.cells[rows]
    y = x[tri] + block.corner_offset[rows][:, :, None] * d[tri]
    lam = facing.weights[on]
    _, _, q, e = ply_surface.surface_point(y, normals[tri], lam)
    on_y, on_n = ply_surface.gap_gradients(y, normals[tri], lam, facing.normal[on], q, e)
    slope = law[1][:, None, None]
    # p on the upper triangle's curved face: dW/dp = W' nu carried to its corners
    above = block.above[on]
    z = x[above] - block.upper_offset[on][:, :, None] * d[above]
    _, _, q_up, e_up = ply_surface.surface_point(z, normals[above], block.shape[on])
    on_z, on_n_up = ply_surface.pullback(
        z, normals[above], block.shape[on], q_up, e_up, law[1][:, None] * facing.normal[on]
    )
    nodes = np.column_stack([above, tri])  # (t, 6)
    # dW/dz at the upper corners' and the lower corners' face points
    forces = np.concatenate([on_z, slope * on_y], axis=1)
    offset = np.column_stack([-block.upper_offset[on], block.corner_offset[rows]])
    flat = nodes.ravel()

    def gathered(values: np.ndarray, at: np.ndarray) -> np.ndarray:
        # float even when no point touches (bincount of no weights is integer)
        return np.column_stack(
            [np.bincount(at, values[..., k].ravel(), block.n_nodes) for k in range(3)]
        ).astype(float)

    force = gathered(forces, flat)
    on_normals = gathered(np.concatenate([on_n_up, slope * on_n], axis=1), flat)
    if block.along_normals:  # z = x + c n: dW/dn = c dW/dz
        on_normals += gathered(offset[:, :, None] * forces, flat)
        moment = np.zeros((block.n_nodes, 3))
    else:
        moment = gathered(offset[:, :, None] * np.cross(d[nodes], forces), flat)
    force += ply_surface.normal_pullback(x, block._own_triangles, normals, lengths, on_normals)
    return force, moment
