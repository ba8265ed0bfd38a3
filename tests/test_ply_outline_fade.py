"""A ply contact point sliding past the other ply's outline at a fixed depth behind its face.

What was left at the outline of the two-ply Mindlin [0/90] hemisphere (validation/studies/
hemisphere_plies.py, 10 cells, 20 N; validation/studies/hemisphere_plies_jumps.py): the bottom
ply's outline nodes of the mirrored pass, facing the top ply's outline triangles' growths,
switched into contact at gaps of -0.27 to -0.30 mm where their closest point came within the
plies' reach of the triangle (2-3 N mm a step), and their gaps flipped sign beside an outline
vertex (1-1.5 N mm): 18 steps of more than +1 N mm made with no work, +34.5 N mm in all.

Reference: the contact is a potential, its force the gradient of its energy, so along any
path the work of the force equals the change of the energy (trapezoidal rule per step), and
around a closed path the work is nil and the energy comes back. A lower ply of 2 x 2 cells of
1 mm, its middle node lifted 0.1 mm (the inner edges are folds: on a flat ply the outline
triangles' growths cover every side of an outline vertex), faces 0.1 mm from the
mid-surfaces; one upper triangle (its centroid the contact point, 0.02 mm across, moved
rigidly, the directors held along z) circles at 0.03 mm behind the lower face the outline
vertex (1, 0), where a triangle meets the outline at that vertex only (the wedge between the
outline triangles' growths), and the ply's corner (2, 0), half inside and half outside the
ply, 0.3 mm out.
"""

import numpy as np
import pytest

from elements.ply_contact import PlyContact
from femcore import Body, Mesh
from femcore.state import State

STEPS = 2000
PENALTY = 100.0  # N/mm
RADIUS = 0.3  # mm, beyond the plies' reach (0.2 mm: both faces' offsets) past the outline


def _pair(lower, low, start):
    """(block, points (n, 3), directors (n, 3)) of the lower ply ``lower`` (its nodes at
    ``low``) and the upper triangle, 0.02 mm across, its centroid at ``start`` (x, y) and its
    face p = x - 0.1 z 0.03 mm behind the lower face z = 0.1 (the plies' faces 0.1 mm from
    their mid-surfaces), bound as a ply contact of penalty PENALTY at the centroid."""
    side = 0.02
    tiny = np.array([[0.0, 0.0, 0.0], [side, 0.0, 0.0], [0.0, side, 0.0]])
    tiny -= tiny.mean(axis=0)
    height = 0.1 - 0.03 + 0.1
    points = np.vstack([low, tiny + [start[0], start[1], height]])
    n = len(points)
    mesh = Mesh(
        points,
        triangles=np.vstack([lower.triangles, [[9, 10, 11]]]),
        node_sets={"upper": np.array([9, 10, 11])},
        element_sets={"lower": np.arange(len(lower.triangles))},
    )
    directors = np.tile([0.0, 0.0, 1.0], (n, 1))
    active = np.zeros((n, 6), dtype=bool)
    active[:, :5] = True
    contact = PlyContact("upper", "lower", 0.1, 0.1, penalty=PENALTY, rule="centroid")
    return contact.bind(Body(mesh, (), directors, active)), points, directors


def _loop(centre, lift):
    """(block, positions (STEPS + 1, n, 3)) of the upper triangle circling ``centre``, the
    lower ply's middle node lifted by ``lift`` (mm)."""
    lower = Mesh.rectangle(2.0, 2.0, nx=2, ny=2)
    low = lower.points.copy()
    low[4, 2] = lift  # the middle node: the inner edges are folds
    block, points, directors = _pair(lower, low, centre)
    angle = np.linspace(0.0, 2.0 * np.pi, STEPS + 1)
    path = RADIUS * np.column_stack([np.cos(angle), np.sin(angle), np.zeros_like(angle)])
    positions = np.repeat(points[None], STEPS + 1, axis=0)
    positions[:, 9:] += path[:, None, :]
    return block, positions, directors


@pytest.mark.parametrize(
    "centre, lift, step_bound, loop_bound",
    [((1.0, 0.0), 0.1, 1e-2, 1e-2), ((2.0, 0.0), 0.1, 1e-2, 1e-2), ((1.0, 0.0), 0.0, 1e-4, 1e-12)],
    ids=["wedge vertex", "corner", "flat"],
)
def test_the_contact_force_works_what_its_energy_changes_round_the_outline(
    centre, lift, step_bound, loop_bound
):
    """Per step, |Delta E - work| within ``step_bound`` of the largest energy on the path and,
    around the loop, the work within ``loop_bound`` of it; the energy comes back. Folded
    (lift 0.1 mm): 1e-2 and 1e-2, measured 1.1e-3 and 2.6e-3 per step and around the loop,
    the trapezoidal rule's error where the facing triangle changes over a fold and the force
    turns (a kink of the energy, first order in the step); 0.25 of it in one step round the
    wedge vertex on the code before the fade, where the point's gap flipped from -0.03 to
    +0.03 mm past the outline (0.13 N mm). Flat: no kink, the rule's error O(step^3) per step
    (measured 2e-5) and nothing left around the loop but round-off (measured 2e-16; 1e-12
    allowed). Premises: the point touches on part of the loop and not on another (it is past
    the outline by 0.3 mm, beyond the fade; the code before the fade touched all round)."""
    block, positions, directors = _loop(centre, lift)
    zero = np.zeros_like(positions[0])
    energy, forces, touching = [], [], []
    for x in positions:
        state = State(x, directors, zero, zero)
        energy.append(block.strain_energy(state))
        forces.append(block.internal_force(state)[0])
        touching.append(bool(block.facing(state).touching.any()))
    energy = np.array(energy)
    forces = np.array(forces)
    # the contact's force is dE/dx, the work done on the contact's energy by moving x
    work = np.einsum("sni,sni->s", 0.5 * (forces[1:] + forces[:-1]), np.diff(positions, axis=0))
    largest = energy.max()
    assert largest > 0.01 and any(touching) and not all(touching)
    assert np.abs(np.diff(energy) - work).max() <= step_bound * largest
    assert abs(work.sum()) <= loop_bound * largest
    assert abs(energy[-1] - energy[0]) <= 1e-12 * largest  # sin(2 pi) is not 0


DEEP = 1.0  # mm behind the lower face: five times the plies' reach (0.2 mm)


def test_a_point_deeper_than_the_plies_crossing_from_a_growth_onto_the_face_works_its_energy():
    """The upper triangle's centroid 1 mm behind the lower face (deeper than both faces' half
    thicknesses, 0.2 mm) moves from 0.3 mm past the outline edge y = 0 of the flat lower ply
    (its projection held by the growth's plane, beyond the fade's 0.15) onto the face 0.3 mm
    inside, in 2000 steps, while the lower ply's nodes move too. What the two-ply Mindlin
    [0/90] hemisphere did (validation/studies/hemisphere_plies_jumps.py, 10 cells, 20 N): a
    mirrored-pass point 2.21 mm deep moved from a growth's plane, where it was beside the
    ply, onto the face of the same triangle and switched into contact at full depth, +169.8
    N mm in one step, and the run stopped on its energy balance. Reference: the contact is a
    potential (the work of its force equals the change of its energy, trapezoidal rule per
    step, on the upper triangle's and the lower ply's nodes): per step within 1e-4 of the
    largest energy (measured 1.9e-6, the rule's error; the code before made W(-1 mm) = 150
    N mm at the point's k_p = 300 N/mm, the whole energy, in one step at the outline).
    Premises: deeper than the plies all along, touching on the face and not beyond the
    fade."""
    block, positions, directors = _loop((1.5, 0.0), 0.0)
    count = 2000
    across = np.linspace(-0.3, 0.3, count + 1)
    # the lower ply's nodes move in its plane (a fold would hand the deep point to an inner
    # edge, where "Deeper than the plies" holds)
    wobble = 0.02 * np.random.default_rng(3).standard_normal(positions[0][:9].shape)
    wobble[:, 2] = 0.0
    # the upper face 1 mm behind the lower face z = 0.1: its mid-surface at 0.1 - 1 + 0.1
    lowered = positions[0].copy()
    lowered[9:, 2] -= DEEP - 0.03
    moved = np.repeat(lowered[None], count + 1, axis=0)
    moved[:, 9:, 0] -= 0.3  # the centroid from (1.8, y) to (1.5, y), over the edge's middle
    moved[:, 9:, 1] += across[:, None]
    s = np.linspace(0.0, 1.0, count + 1)
    moved[:, :9] += s[:, None, None] * wobble
    zero = np.zeros_like(moved[0])
    energy, forces, gaps, touching = [], [], [], []
    for x in moved:
        state = State(x, directors, zero, zero)
        energy.append(block.strain_energy(state))
        forces.append(block.internal_force(state)[0])
        facing = block.facing(state)
        gaps.append(float(facing.gap[0]))
        touching.append(bool(facing.touching[0]))
    energy, forces = np.array(energy), np.array(forces)
    work = np.einsum("sni,sni->s", 0.5 * (forces[1:] + forces[:-1]), np.diff(moved, axis=0))
    largest = energy.max()
    assert max(gaps) < -block.depth and touching[-1] and not touching[0]
    assert largest > 0.9 * 0.5 * float(block.stiffness[0]) * DEEP**2  # W(-1 mm) on the face
    assert np.abs(np.diff(energy) - work).max() <= 1e-4 * largest


def test_a_point_passing_from_one_growth_to_the_next_past_the_outline_works_its_energy():
    """The upper triangle's centroid 0.03 mm behind the lower face moves 0.04 mm past the flat lower
    ply's outline edge y = 0, from x = 0.5 to 1.5, while the lower ply's nodes move in its plane: it
    faces the growth of the outline triangle (0, 0), (1, 0), (0, 0.5) (0.5 mm high over the outline,
    its middle-left node lowered), then the growth of (1, 0), (2, 0), (1, 1) (1 mm high; before the
    growths' cuts from x = 1.08, the first growth's hypotenuse extended, the two growths' planes
    tied until there). The fade by the projection's barycentric overshoot (the code before) differed
    between the two growths (w 0.45 against 0.82 at 0.04 mm past the outline, 0.08 and 0.04 of their
    heights, before the nodes move), and the point's energy w W(g) jumped by the difference where
    its facing triangle changed, with no work (a suspect of the two-ply Mindlin [0/90] hemisphere's
    outline jumps, validation/studies/hemisphere_plies_jumps.py). The fade of the distance to
    the outline (elements/ply_fade.py) is the same function on both. Reference: the contact is a
    potential (trapezoidal work of its force on every node, the outline edge's ends
    included, equals the change of its energy per step): within 5e-3 of the largest energy
    per step, the rule's error where the energy kinks. The two growths are cut past the
    outline vertex (1, 0) (elements/ply_wedge.py), and the point now passes from the first to
    the second at x = 1.027, in the gap between their cuts, its closest point from one cut
    to the other: its force turns by the gap's angle seen from the point (about 20 deg, the
    gap 0.011 mm wide 0.048 mm from the vertex, the point 0.03 mm behind) in one step,
    measured 1.6e-3 there (8.0e-5 at x = 1, where the nearest outline edge changes and the
    distance to the wobbled outline kinks, the largest before the cuts; the code before the
    distance's fade 0.52 in the step where the facing triangle changed, w 0.38 -> 0.80).
    Premises: touching all along, the fade between 0 and 1, the facing triangle changes."""
    lower = Mesh.rectangle(2.0, 2.0, nx=2, ny=2)
    low = lower.points.copy()
    low[3, 1] = 0.5  # (0, 1) -> (0, 0.5): the first outline triangle 0.5 mm high
    block, points, directors = _pair(lower, low, (0.5, -0.04))
    count = 2000
    s = np.linspace(0.0, 1.0, count + 1)
    wobble = 0.005 * np.random.default_rng(5).standard_normal((9, 3))
    wobble[:, 2] = 0.0
    moved = np.repeat(points[None], count + 1, axis=0)
    moved[:, 9:, 0] += s[:, None]
    moved[:, :9] += s[:, None, None] * wobble
    zero = np.zeros_like(points)
    energy, forces, triangles, fades = [], [], [], []
    for x in moved:
        state = State(x, directors, zero, zero)
        facing = block.facing(state)
        assert facing.touching[0]
        energy.append(block.strain_energy(state))
        forces.append(block.internal_force(state)[0])
        triangles.append(int(facing.triangle[0]))
        fades.append(float(facing.fade[0]))
    energy, forces = np.array(energy), np.array(forces)
    work = np.einsum("sni,sni->s", 0.5 * (forces[1:] + forces[:-1]), np.diff(moved, axis=0))
    assert len(set(triangles)) == 2
    assert 0.0 < min(fades) and max(fades) < 1.0
    assert np.abs(np.diff(energy) - work).max() <= 5e-3 * energy.max()


@pytest.mark.parametrize(
    "p, ends",
    [
        # the nearest outline edge nearer than the face's plane (|p - q_o| < |g|): d^2 < 0 is
        # clamped to 0, w = 1 and flat there
        ([0.5, -0.01, -0.05], [[0.4, -0.01, -0.04], [0.6, -0.01, -0.04]]),
        # 0.05 mm past the outline edge y = 0, 0.05 mm behind the face: w inside (0, 1)
        ([0.5, -0.05, -0.05], [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0]]),
    ],
    ids=["clamped", "fading"],
)
def test_the_fades_gradient_is_the_derivative_of_the_fade(p, ends):
    """outline_fade's exact gradient over z = (p, y_1, y_2, y_3, a, b) against central
    differences of the fade itself (step 1e-7 mm, error ~1e-7 of the gradient's ~10 / mm
    scale for a smoothstep of 0.15 mm: 1e-5 / mm allowed), including where the distance
    to the outline is clamped (the fade 1 and flat: its gradient 0, where it was -3 / D^2
    times d(d^2) before)."""
    from elements.ply_fade import outline_fade

    corners = np.array([[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]])
    reach = np.array([[0.0, 0.0, 0.5]])  # the edge y = 0 (opposite corner 2) on the outline
    beside = np.array([False])
    length = 0.15
    z = np.vstack([[p], corners[0], ends])  # (6, 3)

    def fade(zz):
        return outline_fade(zz[None, 0], zz[None, 1:4], reach, beside, zz[None, 4:6], length)

    w, gradient = fade(z)
    step = 1e-7
    central = np.zeros((6, 3))
    for node in range(6):
        for axis in range(3):
            plus, minus = z.copy(), z.copy()
            plus[node, axis] += step
            minus[node, axis] -= step
            central[node, axis] = (fade(plus)[0][0] - fade(minus)[0][0]) / (2 * step)
    assert 0.0 < w[0] <= 1.0
    assert np.abs(gradient[0] - central).max() <= 1e-5
