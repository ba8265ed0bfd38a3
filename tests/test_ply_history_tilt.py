"""A sliding ply point's moved anchor is re-expressed on its facing triangle's plane by the
landing's rule (elements/ply_friction.py ``updated_history``, its compiled twins in
elements/ply_friction_kernels.py and ply_friction_pass.py; elements/ply_landing.py
``edge_crossing``; docs/theory.md §9.3a): along the gap's normal nu where |nu . n| > TILT,
a share (nu . n)^2 / TILT^2 of that move below, the rest of the height along n.

The check: an accepted step re-accepted at the same state moves nothing, so it must add no
slip and no dissipation where the rule is exact, and what it adds must not jump across TILT.
The pairs: tests/test_ply_landing.py's jittered plies (every touching point landing, friction
0.3), each landing row made a point facing an edge whose nu rises ``tilt`` over its
triangle's plane (along a direction in the plane; the facing consistent: the closest point q =
p - g nu on T's plane, g = h / tilt); for tilt < 0 (a fold sharper than a right angle, the gap
signed by the pseudonormal) the upper ply raised 0.2 mm so that its points lie over T's plane.

Measured with the re-expression before (the height along n wherever nu . n <= 0.1, whatever
the landing did): just below TILT the re-acceptances at rest dissipated 13.34, 13.12 and 12.94
N mm (the landing 6.87), at tilt -0.5 0.25, 0.15, 0.097 N mm (fails); now 2.6e-7 and 0.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from elements import ply_friction, ply_friction_kernels, ply_landing
from tests.test_ply_landing import landing_plies

UPDATES = {
    "numpy": ply_friction.updated_history,
    "compiled": ply_friction_kernels.updated_history,
}


def edge_pair(raised: float):
    """(block, state, history, facing_at): the jittered plies with the upper ply raised
    ``raised`` mm, and the facing at a tilt with the landing rows' gaps to an edge."""
    block, state, history = landing_plies(0.05, "normal law")
    if raised:
        positions = state.positions.copy()
        positions[np.unique(block.above), 2] += raised
        state = dataclasses.replace(state, positions=positions)
    facing = block.facing(state)
    _, y = block._faces(state)
    if raised:  # every point over T's plane: the edge rows every other point, touching
        flag = np.zeros(len(facing.gap), dtype=bool)
        flag[::2] = True
    else:
        flag = np.zeros(len(facing.gap), dtype=bool)
        flag[ply_landing.landing_rows(block, history, facing)] = True
    plane = facing.normal  # the flat faces' normals are their triangles'
    aside = np.cross(plane, [0.6, 0.0, 0.8])
    aside /= np.linalg.norm(aside, axis=1)[:, None]

    def facing_at(tilt: float):
        nu = np.sqrt(1.0 - tilt**2) * aside + tilt * plane
        gap = facing.gap / tilt
        closest = facing.face - gap[:, None] * nu
        weights = ply_landing.plane_places(y[facing.triangle], closest)[0]
        touching = flag if raised else facing.touching
        return dataclasses.replace(
            facing,
            on_edge=flag,
            touching=touching,
            normal=np.where(flag[:, None], nu, plane),
            gap=np.where(flag, gap, facing.gap),
            weights=np.where(flag[:, None], weights, facing.weights),
        )

    return block, state, history, facing_at


def rest_dissipation(tilt: float, update, raised: float = 0.0) -> tuple[float, np.ndarray]:
    """(the landing step's dissipation, the dissipation each of three re-acceptances at the
    same state adds), N mm."""
    block, state, history, facing_at = edge_pair(raised)
    facing = facing_at(tilt)
    found = ply_landing.landing(block, state, history, facing)
    assert found is not None and found.edge is not None and found.edge.any()
    accepted = update(block, state, ply_landing.landed(block, state, history, facing, found),
                      facing, history.sides)  # fmt: skip
    records = [accepted.dissipated]
    for _ in range(3):
        accepted = update(block, state, accepted, facing, accepted.sides)
        records.append(accepted.dissipated)
    return records[0], np.diff(records)


@pytest.mark.parametrize("kind", sorted(UPDATES))
@pytest.mark.parametrize("tilt", [0.3, 0.1 + 1e-9, 0.1 - 1e-9], ids=["steep", "above", "below"])
def test_a_landed_edge_point_re_accepted_at_rest_dissipates_nothing_more(tilt, kind):
    """Where the re-expression is the landing's exact move along nu, and just below TILT
    where the blend is within (1 - tilt^2 / TILT^2) = 2e-8 of it: nothing more than 1e-6 of
    the landing's own dissipation (5.7-6.9 N mm; round-off 1e-15; the blend's share just
    below TILT 2.6e-7 N mm). Before: 13.3 N mm a re-acceptance just below TILT (fails)."""
    assert ply_landing.TILT == 0.1  # the tilts above straddle it
    landed, rest = rest_dissipation(tilt, UPDATES[kind])
    assert landed > 1.0
    assert np.abs(rest).max() <= 1e-6 * landed


@pytest.mark.parametrize("kind", sorted(UPDATES))
@pytest.mark.parametrize("tilt", [-0.5, -0.2])
def test_a_point_facing_an_edge_below_its_plane_re_accepted_at_rest_dissipates_nothing(tilt, kind):
    """nu below T's plane (nu . n < -TILT): the landing moves the anchor along nu, and so
    must the re-expression. Before (the height along n for every nu . n <= 0.1): 0.25, 0.15,
    0.097 N mm per re-acceptance at tilt -0.5, 0.061, 0.056 at -0.2 (fails); now round-off
    (1e-12 N mm: the slips are ~0.1 mm, the forces ~10 N)."""
    _, rest = rest_dissipation(tilt, UPDATES[kind], raised=0.2)
    assert np.abs(rest).max() <= 1e-12


def test_the_compiled_re_expression_is_numpys_on_both_sides_of_tilt():
    """The compiled history (fused pass) and numpy's: the same dissipation records, every bit,
    in and out of the blend (tilt 0.05, 0.3)."""
    for tilt in (0.05, 0.3):
        numpy = rest_dissipation(tilt, UPDATES["numpy"])
        compiled = rest_dissipation(tilt, UPDATES["compiled"])
        assert numpy[0] == compiled[0] and numpy[1].tobytes() == compiled[1].tobytes()
