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
from elements.ply_projection import Facing, choose, facets, penalty_law
from femcore.state import State

if TYPE_CHECKING:
    from elements.ply_block import PlyContactBlock

__all__ = ["MARGIN_CURVED", "curved_facing", "curved_loads"]

#: How far past its patch's edges (in barycentric units) a point still touches the curved
#: face. The flat facet's plane carries a point half a cell past its edges (``MARGIN``); the
#: quadratic patch extrapolated so far, over the one-sided normals of a ply's free edge, is
#: no surface: measured on the coarse [0/45] hemisphere (mirrored pass, the bottom ply's
#: outline nodes 0.3-0.5 past the top ply's edge triangles), gaps jumping from +0.06 to -0.66
#: mm in a step and the contact's energy off the work of its force by 32 N mm, past the 5 %
#: energy balance. The wedges over a fold that no patch holds are a few 1e-3 wide.
MARGIN_CURVED = 0.05
#: Only the candidates whose flat facet's projection lies within this many barycentric units
#: of the facet are projected on their curved patch (and each point's nearest flat facet):
#: a patch's curved projection is off its facet's flat one by the patch's rise over the
#: facet (at most s^2 / (8 R)) times the tilt of its normals (~ s / (2 R)), 0.016 at the
#: hemisphere's coarsest 25-mm cells on its 50-mm punch, so a patch that holds its curved
#: projection is among these. Measured in benchmarks/plies.py (``--curved``).
NEAR = 0.2


def curved_facing(
    block: PlyContactBlock,
    state: State,
    p: np.ndarray,
    y: np.ndarray,
    near: np.ndarray,
    every: bool = False,
) -> Facing:
    """Each point's facing on the curved surface: p (P, 3) the points, y (m, 3, 3) the lower
    triangles' offset corners, mm, near (P, K) each point's candidate triangles (rows of y).

    The candidates' curved patches are projected on (from the flat facet's projection; those
    ``NEAR`` their flat facets, or ``every`` one), and
    the patch is chosen by its curved projection (``choose``: the one holding it that the
    point penetrates most, else the nearest). Chosen by the flat facets' projections, as it
    was, a point passed from one patch to the next where its flat projection crossed the
    facets' edge, not where its curved one crossed the patches' edge (the two differ by the
    chord's sag times the facet's tilt), and its gap and energy jumped there: measured on a
    [0/45] pair on a 50-mm sphere turned by one cell, 10-mm cells, k = 100 N/mm, the energy
    off the work of the force by 0.016-0.02 N mm in a step where a point changed patch
    (whatever the step) against 1e-8 elsewhere; chosen so, by 3e-3 and 8e-4 N mm at steps of
    1/1000 and 1/4000 of the turn, the kink's share, and continuous at the switches to 1e-6
    N mm (tests/test_ply_surface.py). Among patches that hold the projection the nearest
    (the shallowest penetration), not the deepest: a patch enters the choice with its
    projection on its edge, a point of the other patch too, no nearer than that patch's own
    projection, so the least distance does not jump (the deepest did).
    """
    count, k = near.shape
    _, area2, gradients, flat_gap, weights = facets(p, y[near])
    normals = ply_surface.nodal_normals(state.positions, block._own_triangles, block.n_nodes)[0]
    # the patches worth projecting on (``NEAR``), each point's nearest flat facet among them
    chosen = np.ones((count, k), dtype=bool) if every else weights.min(axis=-1) >= -NEAR
    chosen[np.arange(count), choose(flat_gap, weights, area2)] = True
    at_point, column = np.nonzero(chosen)
    rows = near[at_point, column]
    found, _, found_normal, found_gap, _, _ = ply_surface.project(
        p[at_point], y[rows], normals[block.cells[rows]], weights[at_point, column]
    )
    lam = np.full((count, k, 3), np.nan)
    gap = np.full((count, k), np.nan)
    normal = np.zeros((count, k, 3))
    lam[at_point, column], gap[at_point, column] = found, found_gap
    normal[at_point, column] = found_normal
    # a candidate's patch not projected on, or whose projection did not converge (far past
    # its edges, where the quadratic patch folds; or a point some mm off a patch tilted by
    # its cell's angle, where ITERATIONS Gauss-Newton steps do not settle), is out of the
    # choice, its normal zero: a point with no converged patch touches nothing and must not
    # carry the failed projection's NaN normal into the friction's slip (its energy was NaN:
    # Mindlin [0/45] on the hemisphere at 61 % of the stroke, docs/hemisphere_plies.md)
    bad = ~(np.isfinite(gap) & np.isfinite(lam).all(axis=-1))
    gap = np.where(bad, np.inf, gap)
    lam = np.where(bad[..., None], -np.inf, lam)
    normal = np.where(bad[..., None], 0.0, normal)
    best = choose(gap, lam, area2, deepest=False)
    at = np.arange(count)
    lam, gap = lam[at, best], gap[at, best]
    overshoot = np.maximum(0.0, -lam.min(axis=1))
    return Facing(
        triangle=near[at, best],
        gap=gap,
        normal=normal[at, best],
        weights=lam,
        gradients=gradients[at, best],
        touching=(gap <= block.tolerance) & (overshoot <= MARGIN_CURVED),
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
