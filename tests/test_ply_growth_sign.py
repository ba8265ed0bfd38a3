"""A ply contact point going round a sharp ridge of the other ply's face past its outline.

What was left at the outline of the two-ply Mindlin [0/90] hemisphere (validation/studies/
hemisphere_plies.py, 8 and 10 cells, 20 N; validation/studies/hemisphere_plies_jumps.py): the
mirrored pass's points past the top ply's wrinkled outline flipped the sign of their gap
where their closest point passed from one outline triangle's growth onto the extension of
the edge it shares with its neighbour, whose growth holds that extension too, signed there by
the facing triangle's own normal (elements/ply_projection.py, "Growths joined").

Reference: the contact is a potential, its force the gradient of its energy, so along any
path the work of the force equals the change of the energy (trapezoidal rule per step), and
around a closed path the work is nil. The lower ply: two outline triangles A, B sharing the
edge from w = (0, -1) to the outline vertex v = (0, 0), folded along it into a ridge whose
sides fall by 2 mm a mm (normals 127 deg apart, a fold sharper than a right angle, as a
wrinkle's crest), with two triangles beside them so that each of A and B has one outline
edge (y = 0); faces 0.1 mm from the mid-surfaces. One upper triangle (its centroid the
contact point, 0.02 mm across, moved rigidly, the directors held along z) circles the
ridge's extension 0.05 mm past the outline (within the fade's band) at 0.08 mm: past its
sides inside the ridge it touches, outside it does not.
"""

import numpy as np
import pytest
from ply_point_loops import point_round, walk

STEPS = 1000
PENALTY = 100.0  # N/mm
SLOPE = 2.0  # mm a mm: the ridge's sides (a valley's when negative)
RADIUS = 0.08  # mm, round the ridge's extension
PAST = 0.05  # mm past the outline y = 0


def _ridge(slope: float = SLOPE):
    """(block, positions (STEPS + 1, n, 3), directors (n, 3)): the ridge of the module
    docstring and the upper triangle's path round it, bound as a ply contact of penalty
    PENALTY at the centroid; its sides fall by ``slope`` mm a mm (rise where negative)."""
    low = np.array(
        [
            [-1.0, 0.0, -slope],  # 0 v1
            [0.0, 0.0, 0.0],  # 1 v, the outline vertex on the ridge
            [1.0, 0.0, -slope],  # 2 v3
            [0.0, -1.0, 0.0],  # 3 w, the ridge's inner end
            [-1.0, -1.0, -slope],  # 4
            [1.0, -1.0, -slope],  # 5
        ]
    )
    # counter-clockwise about +z; A = (v1, w, v) and B = (w, v3, v) share the ridge w-v
    lower = np.array([[0, 3, 1], [3, 2, 1], [0, 4, 3], [3, 5, 2]])
    return point_round(low, lower, steps=STEPS, penalty=PENALTY, radius=RADIUS, past=PAST)


@pytest.mark.parametrize("slope", [SLOPE, -SLOPE], ids=["ridge", "valley"])
def test_a_point_round_a_ridge_past_the_outline_keeps_its_sign_and_works_its_energy(slope):
    """Per step |Delta E - work| within 0.05 of the largest energy on the path, and around
    the loop the work within 0.05 of it: the trapezoidal rule's error in the one step where
    the point, inside the ridge, passes from A's plane to B's at the bisector and its force
    turns by 127 deg (first order in the step: measured 0.025 in that step and 0.025 round
    the loop at 1000 steps, 2.5e-14 elsewhere per step). The code before, which signed the gap
    on the ridge's extension by the facing triangle's own normal: 1.00 of it in one step (the
    point outside the ridge at -0.080 mm, touching on A's growth's edge, then +0.080 mm on
    B's plane) and -0.99 round the loop. Every gap of a point outside the ridge (above both
    sides' planes) is positive. Premises: the point touches on part of the loop and not on
    another, its closest point lies on the ridge's extension (joined) on part of it, the
    fade is below 1 (past the outline) and above 0. The valley (the sides rising by 2 mm a
    mm): the points on the extension, joined, are inside it and touch, so their force is
    the one whose work is checked (on the ridge the joined points are outside, at no
    energy)."""
    block, positions, directors = _ridge(slope)
    walked = walk(block, positions, directors)
    energy, work, touching, joined = (walked[k] for k in ("energy", "work", "touching", "joined"))
    gaps, fades = walked["gap"], walked["fade"]
    # the contact point on the upper face, above both sides' planes through the offset ridge
    # z = 0.1 + 0: outside the ridge
    p = positions[:, -3:].mean(axis=1) - [0.0, 0.0, 0.1]
    outside = p[:, 2] - 0.1 > -slope * np.abs(p[:, 0])
    largest = energy.max()
    assert largest > 1e-3 and any(touching) and not all(touching)
    assert 0.0 < min(fades) and max(fades) < 1.0
    assert np.abs(np.diff(energy) - work).max() <= 0.05 * largest
    assert abs(work.sum()) <= 0.05 * largest
    assert (gaps[outside] > 0.0).all()
    assert any(joined)
    if slope < 0.0:  # the joined points touch: their force does work
        assert any(t and j for t, j in zip(touching, joined, strict=True))
