"""The interaction conformance kit (femcore.interaction_checks) over the project's contact with
each rigid tool (a tilted moving plane, spheres and cylinders from outside and from inside, a
meshed tool) and over the two interactions a user wrote (tests/test_custom_interaction.py): the
force is the gradient of the energy, the tangent the derivative of the force, the normal force
k p, Coulomb's law, objectivity, energy and history; and the kit catches a block that breaks
each of them.

The body is a 3 x 3 grid of nodes over 4 x 4 mm, jittered by 0.3 mm about z = -0.4 so that some
nodes penetrate the tools (contact offset 0.5 mm, penalty 100 N/mm) and some do not; the tools
are at load factor 0.5. Tolerances: those of the kit (its module docstring): central
differences with a step of 1e-6 of the body's size, truncation O(step^2) = 1e-12 relative and
rounding O(eps |W| / step) = 1e-9 N, held to 1e-6 of the largest force or tangent entry; the
closed forms and the turned copies to 1e-9 of the largest force (rounding of the geometry).
"""

import dataclasses

import numpy as np
import pytest
from friction_histories import shifted_anchors
from scipy.spatial.transform import Rotation

from elements import RigidCylinder, RigidPlane, RigidSphere, RigidSurface
from elements.contact import Contact, FrictionHistory
from femcore import Body, Mesh
from femcore.interaction_checks import (
    check_added_force,
    check_energy,
    check_force_is_energy_gradient,
    check_friction,
    check_interaction,
    check_interaction_capabilities,
    check_normal_force,
    check_objectivity,
    check_tangent,
    placed_at_penetration,
)
from femcore.state import State
from tests.test_custom_interaction import PlaneContact, PlaneContactBlock, SpringTie

PENALTY, OFFSET, MU, LOAD_FACTOR = 100.0, 0.5, 0.4, 0.5
UNTURNED = np.eye(3)
TURN = Rotation.from_rotvec([0.3, -0.7, 0.5]).as_matrix()


def meshed_floor(turn: np.ndarray) -> Mesh:
    """A 12 x 12 mm plane z = 0.2 x + 0.1 y - 0.05 meshed with 32 triangles (normals up),
    turned by ``turn``."""
    floor = Mesh.rectangle(12.0, 12.0, nx=4, ny=4)
    x = floor.points - [6.0, 6.0, 0.0]
    x[:, 2] = 0.2 * x[:, 0] + 0.1 * x[:, 1] - 0.05
    return floor.with_points(x @ turn.T)


#: Each rigid tool, built turned by R (its points, axes and motion turned).
TOOLS = {
    "plane": lambda R: RigidPlane(
        R @ [0.0, 0.0, 0.0], R @ [0.2, 0.1, 1.0], motion=R @ [0.1, 0, 0.3]
    ),
    "sphere": lambda R: RigidSphere(R @ [0.0, 0.0, -20.0], 20.0, motion=R @ [0.0, 0.0, 0.1]),
    "sphere inside": lambda R: RigidSphere(R @ [0.0, 0.0, 5.7], 6.0, side="inside"),
    "cylinder": lambda R: RigidCylinder(R @ [0.0, 0.0, -20.0], R @ [1.0, 0.2, 0.0], 20.0),
    "cylinder inside": lambda R: RigidCylinder(
        R @ [0.0, 0.0, 6.0], R @ [0.0, 1.0, 0.0], 6.0, side="inside"
    ),
    "meshed": lambda R: RigidSurface(meshed_floor(R), motion=R @ [0.0, 0.0, 0.1]),
}


def body(turn: np.ndarray = UNTURNED) -> tuple[Mesh, State]:
    """The jittered grid (module docstring), turned: its mesh and its state."""
    rng = np.random.default_rng(3)
    mesh = Mesh.rectangle(4.0, 4.0, nx=2, ny=2)
    x = mesh.points + rng.normal(scale=0.3, size=mesh.points.shape) - [2.0, 2.0, -0.5]
    mesh = mesh.with_points(x @ turn.T)
    zero = np.zeros_like(x)
    state = State(mesh.points.copy(), zero, zero.copy(), zero.copy(), load_factor=LOAD_FACTOR)
    return mesh, state


def contact(name: str, turn: np.ndarray = UNTURNED, friction: float = 0.0):
    """(block, state, history) of the body against tool ``name``, all turned by ``turn``;
    with friction, anchors 0.01 mm (even nodes: they stick) or 0.3 mm (odd: they slip) off."""
    mesh, state = body(turn)
    tool = TOOLS[name](turn)
    nodes = np.arange(mesh.n_nodes)
    block = Contact(tool, nodes, OFFSET, PENALTY, friction).bind(Body.bare(mesh))
    history = None
    if friction:
        rng = np.random.default_rng(5)
        unturned = state.positions @ turn  # the anchors of the unturned body, then turned
        anchor = unturned - TOOLS[name](np.eye(3)).offset(LOAD_FACTOR)
        spread = np.where(np.arange(len(anchor)) % 2, 0.3, 0.01)[:, None]  # mm: slide, stick
        anchor = (anchor + spread * rng.normal(size=anchor.shape)) @ turn.T
        n = mesh.n_nodes
        history = FrictionHistory(anchor, np.zeros(n), np.full(n, 0.1), 1.0)
    return block, state, history


@pytest.mark.parametrize("name", TOOLS)
def test_contact_forces_are_the_energy_gradient(name):
    """Frictionless (a slip's friction force has no potential: its energy is the stick
    spring's, and the kit checks the force against the tangent instead)."""
    block, state, _ = contact(name)
    p, _, touching = block.touch(state)
    assert (p > 0).sum() >= 3 and (~touching).sum() >= 1  # touching and apart nodes
    check_force_is_energy_gradient(block, state)


@pytest.mark.parametrize("friction", [0.0, MU], ids=["frictionless", "friction"])
@pytest.mark.parametrize("name", TOOLS)
def test_the_contact_tangent_is_the_force_derivative_and_its_energies_are_sound(name, friction):
    block, state, history = contact(name, friction=friction)
    assert check_tangent(block, state, history)
    check_energy(block, state, history)
    check_added_force(block, state, history)  # the rows added in place (elements/node_rows.py)


@pytest.mark.parametrize("name", TOOLS)
def test_contact_pushes_a_node_at_penetration_p_by_k_p_along_the_normal(name):
    block, state, _ = contact(name)
    check_normal_force(block, placed_at_penetration(block, state))


@pytest.mark.parametrize("name", TOOLS)
def test_contact_friction_obeys_coulomb(name):
    block, state, history = contact(name, friction=MU)
    p, n, touching = block.touch(state)
    _, _, stuck, sliding = block.tangential(state, history, p, n, touching)
    assert stuck.sum() >= 1 and sliding.sum() >= 1
    check_friction(block, state, history)


@pytest.mark.parametrize("friction", [0.0, MU], ids=["frictionless", "friction"])
@pytest.mark.parametrize("name", TOOLS)
def test_contact_is_objective(name, friction):
    check_objectivity(lambda turn: contact(name, turn, friction), TURN)


@pytest.mark.parametrize("friction", [0.0, MU], ids=["frictionless", "friction"])
@pytest.mark.parametrize("name", TOOLS)
def test_contact_declares_its_capabilities_as_the_protocol_says(name, friction):
    """Friction, contact sets, soft start and facets (femcore/capability_checks.py); a meshed
    tool's facets recorded once Static's ``freeze`` has asked for them (read before the
    capability check, whose own probes, such as the initial history's distances that
    ``set_model`` is asked of, are recorded too)."""
    block, state, history = contact(name, friction=friction)
    frozen, _ = block.freeze(state, history)
    block.internal_force(state, frozen)
    facets = block.facet_record()
    assert (facets is not None) == (name == "meshed")
    if facets is not None:
        assert facets.record.shape == (len(block.connectivity), 1)
    check_interaction_capabilities(block, state, frozen)
    assert block.friction == friction


# ---------------------------------------------------------------------- a user's own
NORMAL = np.array([0.2, 0.1, 1.0]) / np.linalg.norm([0.2, 0.1, 1.0])


def floor(turn: np.ndarray = UNTURNED, block_type=None):
    """The user's PlaneContact (normal NORMAL through the origin) under the body, turned."""
    mesh, state = body(turn)
    state.positions = state.positions - 0.5 * turn[:, 2]  # the grid about z = 0 (no offset)
    block = PlaneContact(np.arange(mesh.n_nodes), 100.0, turn @ NORMAL).bind(Body.bare(mesh))
    if block_type is not None:
        block.__class__ = block_type
    history = np.linspace(0.0, 0.2, mesh.n_nodes)  # deepest penetrations so far
    return block, state, history


def tie(turn: np.ndarray = UNTURNED):
    """The user's SpringTie (20 N/mm) between nodes 0..3 and 5..8 of the jittered body."""
    mesh, state = body(turn)
    block = SpringTie([0, 1, 2, 3], [5, 6, 7, 8], 20.0).bind(Body.bare(mesh))
    reference = mesh.points.copy()
    state.positions = reference + (np.linspace(-0.3, 0.4, 27).reshape(9, 3) @ turn.T)
    return block, state, None


def test_a_user_floor_conforms():
    block, state, history = floor()
    assert (state.positions @ NORMAL < 0).sum() >= 3  # some nodes penetrate, some not
    check_interaction(block, state, history)

    def place(p):  # every node at penetration p below the plane, along its normal
        x = state.positions
        return State(x - (x @ NORMAL + p)[:, None] * NORMAL, *(np.zeros_like(x),) * 3)

    check_normal_force(block, place, normal=lambda s: np.broadcast_to(NORMAL, (9, 3)))
    check_objectivity(floor, TURN)


def test_a_user_tie_conforms():
    block, state, history = tie()
    check_interaction(block, state, history)
    check_objectivity(tie, TURN)


# ---------------------------------------------------------------------- the kit catches
def test_the_kit_names_a_force_that_is_not_the_energy_gradient():
    class HalfEnergy(PlaneContactBlock):
        def strain_energy(self, state, history=None):
            return 0.5 * super().strain_energy(state, history)

    block, state, history = floor(block_type=HalfEnergy)
    with pytest.raises(AssertionError, match="HalfEnergy: at node .* the force is"):
        check_force_is_energy_gradient(block, state, history)


def test_the_kit_names_forces_added_otherwise_than_internal_force_gives_them():
    """A block whose in-place sum (how the model sums its parts) is not its internal_force."""

    class TwiceAdded(PlaneContactBlock):
        def add_internal_force(self, state, history, force, moment):
            super().add_internal_force(state, history, force, moment)
            super().add_internal_force(state, history, force, moment)

    block, state, history = floor()
    check_added_force(block, state, history)  # the protocol's default
    block, state, history = floor(block_type=TwiceAdded)
    with pytest.raises(AssertionError, match="TwiceAdded.add_internal_force added the force"):
        check_added_force(block, state, history)


def test_the_kit_names_a_tangent_that_is_not_the_force_derivative():
    class DoubleTangent(PlaneContactBlock):
        def tangent(self, state, history=None):
            (part,) = super().tangent(state, history)
            return [part._replace(blocks=2.0 * part.blocks)]

    block, state, history = floor(block_type=DoubleTangent)
    with pytest.raises(AssertionError, match="DoubleTangent: d\\(load at node"):
        check_tangent(block, state, history)

    class NoTangent(PlaneContactBlock):
        def tangent(self, state, history=None):
            return None  # the solvers difference the forces: nothing to check

    assert not check_tangent(*floor(block_type=NoTangent))


def test_the_kit_names_a_normal_force_off_k_p_and_a_broken_coulomb_law():
    block, state, _ = contact("plane")
    block.stiffness = 1.01 * block.stiffness  # the force uses k; the check is told k / 1.01
    with pytest.raises(AssertionError, match="at penetration .* expected k p"):
        check_normal_force(
            block, placed_at_penetration(block, state), stiffness=block.stiffness / 1.01
        )
    block, state, history = contact("plane", friction=MU)
    p, n, touching = block.touch(state)
    _, _, stuck, _ = block.tangential(state, history, p, n, touching)
    with pytest.raises(AssertionError, match="sliding off the friction limit"):
        check_friction(block, state, history, stuck=stuck, sliding=stuck)


def test_the_kit_names_an_interaction_that_is_not_objective():
    class WorldFloor(PlaneContactBlock):
        def _gap(self, state):  # the world's z, whatever the normal it was given
            return np.minimum(state.positions[self.connectivity[:, 0], 2], 0.0)

    with pytest.raises(AssertionError, match="WorldFloor: the forces of the turned"):
        check_objectivity(lambda turn: floor(turn, WorldFloor), TURN)


def test_the_kit_names_a_history_mutated_in_place():
    class Forgetful(PlaneContactBlock):
        def update_history(self, state, history):
            np.maximum(history, -self._gap(state), out=history)
            return history

    block, state, history = floor(block_type=Forgetful)
    with pytest.raises(AssertionError, match="Forgetful.update_history changed the history"):
        check_energy(block, state, history)


# ---------------------------------------------------------------------- ply on ply
# elements/ply_contact.py: a 3 x 3-cell upper ply (3 x 3 mm) over a 2 x 2-cell lower ply
# (4 x 4 mm), both jittered by 0.1 mm, 0.5 mm apart, half thicknesses 0.25 mm (the faces
# touch in the mean), directors tilted by ~0.15 rad: about half the contact points penetrate.
# The contact acts on the directors too (offset faces): the kit checks the moments. Each rule
# of contact points, with the default smoothing, none, and a ramp of 0.05 mm that a good share
# of the penetrations (~0.1 mm) falls on.
def plies(
    turn: np.ndarray = UNTURNED,
    seed: int = 1,
    rule: str = "centroid",
    smoothing=None,
    friction: float = 0.0,
    separate: bool = False,
    points: str = "upper",
    lower_size: float = 4.0,
    stick: str = "penalty",
    static_law: str = "ramp",
):
    """(block, state, None) of PlyContact between the two jittered plies, turned (the lower
    ply ``lower_size`` mm square); with
    ``separate``, the upper ply's 18 triangles each with their own corners (every upper node
    then takes the force of one contact point of the centroid rule); ``points="lower"`` the
    mirrored pass, the lower ply's points against the upper ply's face."""
    from elements.ply_contact import PlyContact

    rng = np.random.default_rng(seed)
    lower = Mesh.rectangle(lower_size, lower_size, nx=2, ny=2)
    upper = Mesh.rectangle(3.0, 3.0, nx=3, ny=3)
    low = lower.points - [lower_size / 2, lower_size / 2, 0.0]
    low = low + rng.normal(scale=0.1, size=lower.points.shape)
    up = upper.points - [1.5, 1.5, -0.5] + rng.normal(scale=0.1, size=upper.points.shape)
    above = upper.triangles
    if separate:
        up, above = up[above].reshape(-1, 3), np.arange(above.size).reshape(-1, 3)
    coordinates = np.vstack([low, up])
    n = len(coordinates)
    mesh = Mesh(
        coordinates @ turn.T,
        triangles=np.vstack([lower.triangles, above + len(low)]),
        node_sets={"upper": np.arange(len(low), n)},
        element_sets={"lower": np.arange(len(lower.triangles))},
    )
    directors = [0.0, 0.0, 1.0] + rng.normal(scale=0.15, size=(n, 3))
    directors = (directors / np.linalg.norm(directors, axis=1)[:, None]) @ turn.T
    active = np.zeros((n, 6), dtype=bool)
    active[:, :5] = True
    contact = PlyContact(
        "upper",
        "lower",
        0.25,
        0.25,
        penalty=PENALTY,
        rule=rule,
        smoothing=smoothing,
        friction=friction,
        stick=stick,
        points=points,
        static_law=static_law,
    )
    block = contact.bind(Body(mesh, (), directors, active))
    zero = np.zeros((n, 3))
    return block, State(mesh.points.copy(), directors.copy(), zero, zero.copy()), None


@pytest.mark.parametrize(
    "rule, smoothing",
    [("centroid", None), ("gauss", None), ("vertices", None), ("gauss", 0.0), ("gauss", 0.05)],
)
def test_ply_contact_conforms(rule, smoothing):
    def build(turn=UNTURNED):
        return plies(turn, rule=rule, smoothing=smoothing)

    block, state, history = build()
    facing = block.facing(state)
    assert facing.touching.sum() >= 4 and (~facing.touching).sum() >= 4
    if smoothing:  # the ramp is exercised
        assert np.sum(facing.touching & (facing.gap > -smoothing)) >= 2
    check_interaction(block, state, history)  # gradient (forces and moments), tangent, energy
    check_objectivity(build, TURN)


@pytest.mark.parametrize("rule", ["centroid", "gauss"])
@pytest.mark.parametrize("points", ["upper", "lower"])
def test_ply_contact_with_a_frozen_active_set_conforms(rule, points):
    """The ply contact's law under Static as an active set (elements/ply_active_set.py): with
    a frozen set holding every other point of those that may touch, pressed ones and ones
    pulled apart alike (k/2 g^2 on each), the forces are the energy's gradient, the tangent
    their derivative, and they turn with the plies."""
    from elements.ply_active_set import FrozenSides

    def build(turn=UNTURNED):
        block, state, _ = plies(turn, rule=rule, points=points, static_law="active_set")
        sides = block.initial_history()
        held, reachable = block._reachable(state, sides)
        chosen = reachable & (np.arange(len(reachable)) % 2 == 0)
        pressure = np.zeros(len(chosen))
        history = FrozenSides(sides.sides, sides.faces, sides.corners, chosen, pressure)
        return block, state, history

    block, state, history = build()
    gap = np.asarray(block._held(state, history).gap)[history.active]
    assert (gap < 0).sum() >= 2 and (gap > 0).sum() >= 1
    check_interaction(block, state, history)
    check_objectivity(build, TURN)


@pytest.mark.parametrize("rule", ["centroid", "gauss", "vertices"])
@pytest.mark.parametrize("smoothing", [0.0, 0.002])
def test_flat_plies_pressed_by_p_carry_the_penalty_law_along_the_normal(rule, smoothing):
    """A flat upper ply pressed into a flat lower one by p (directors along the normal): every
    contact point carries dW/dg at g = -p along the normal (elements.ply_contact.penalty_law:
    k (p - delta / 2) past the ramp, k p^2 / (2 delta) on it, nothing apart), the points'
    penalties add up to the nodes' whatever the rule (the total is that law times the number
    of upper nodes), nothing acts across the normal or on the directors, and the lower ply
    takes the opposite."""
    from elements.ply_contact import PlyContact, penalty_law

    lower, upper = Mesh.rectangle(4.0, 4.0, nx=2, ny=2), Mesh.rectangle(3.0, 3.0, nx=3, ny=3)
    low, up = lower.points - [2.0, 2.0, 0.0], upper.points - [1.5, 1.5, -0.5]
    mesh = Mesh(
        np.vstack([low, up]),
        triangles=np.vstack([lower.triangles, upper.triangles + len(low)]),
        node_sets={"upper": np.arange(len(low), len(low) + len(up))},
        element_sets={"lower": np.arange(len(lower.triangles))},
    )
    n = mesh.n_nodes
    directors = np.tile([0.0, 0.0, 1.0], (n, 1))
    active = np.zeros((n, 6), dtype=bool)
    active[:, :5] = True
    contact = PlyContact(
        "upper", "lower", 0.25, 0.25, penalty=PENALTY, rule=rule, smoothing=smoothing
    )
    block = contact.bind(Body(mesh, (), directors, active))
    upper_nodes = np.arange(len(low), n)
    zero = np.zeros((n, 3))
    for p in (-0.01, 0.0, 0.001, 0.01, 0.1):
        positions = mesh.points.copy()
        positions[upper_nodes, 2] -= p
        force, moment = block.internal_force(State(positions, directors, zero, zero))
        law = penalty_law(np.array([-p]), np.array([PENALTY]), smoothing)[1][0]
        assert force[upper_nodes, 2].sum() == pytest.approx(len(up) * law, rel=1e-12, abs=1e-12)
        assert np.abs(force[:, :2]).max() <= 1e-12 * PENALTY
        assert np.abs(moment).max() <= 1e-12 * PENALTY
        assert np.abs(force.sum(axis=0)).max() <= 1e-12 * PENALTY


@pytest.mark.parametrize("rule", ["centroid", "vertices"])
def test_the_mirrored_ply_contact_conforms(rule):
    """The lower ply's points against the upper ply's face (``points="lower"``): the same
    kit, the moments through the swapped offsets included. The lower ply 3.2 mm square, its
    outline nodes 0.1 mm past the upper ply's (in barycentric units 0-0.2 with the jitter):
    several of them touch within the fade past the upper ply's outline (elements/ply_fade.py),
    whose gradient the force carries and whose second derivative the tangent does."""

    def build(turn=UNTURNED):
        return plies(turn, rule=rule, points="lower", lower_size=3.2)

    block, state, history = build()
    facing = block.facing(state)
    assert facing.touching.sum() >= 2 and (~facing.touching).sum() >= 2
    assert facing.fade is not None
    if rule == "vertices":  # the centroids of the lower ply's cells lie under the upper ply
        assert (facing.touching & (facing.fade > 0.0) & (facing.fade < 1.0)).sum() >= 2
    check_interaction(block, state, history)
    check_objectivity(build, TURN)


def plies_with_friction(
    turn: np.ndarray = UNTURNED,
    rule="gauss",
    smoothing=None,
    separate=False,
    points="upper",
    stick="penalty",
):
    """(block, state, history) of ``plies`` with friction MU: each touching point anchored on
    its facing triangle at its projection's barycentric coordinates moved by 0.002 (even
    points: ~4e-3 mm, they stick) or 0.2 (odd: ~0.4 mm, they slide); barycentric, so the
    history is the same whatever the turn. The mirrored pass's lower ply 3.2 mm square, as
    in ``test_the_mirrored_ply_contact_conforms``: its outline points touch in the fade."""
    block, state, _ = plies(
        turn,
        rule=rule,
        smoothing=smoothing,
        friction=MU,
        separate=separate,
        points=points,
        lower_size=3.2 if points == "lower" else 4.0,
        stick=stick,
    )
    return block, state, shifted_anchors(block.facing(state), 0.002, 0.2)


def test_the_ply_contact_says_which_of_its_points_touch():
    """``touching`` (the protocol's; Static compares it at an increment's start and at its
    first step's end, solvers/imposed_alone.py): the jittered plies laid face on face touch
    at some of their points and not at others (29 of 54); the upper ply lifted 1 mm, twice
    the sum of the faces' half thicknesses (0.25 + 0.25 mm), touches at none, and pushed 0.2
    mm into the lower one (the jitter is 0.1 mm), at every one."""
    block, state, history = plies_with_friction()
    touching = block.touching(state, history)
    assert touching.dtype == bool and touching.shape == (len(block.above),)
    assert 0 < touching.sum() < touching.size
    upper = np.arange(state.positions.shape[0]) >= 9  # after the lower ply's 3 x 3 nodes
    for lift, every in ((1.0, False), (-0.2, True)):
        moved = state.positions + np.where(upper[:, None], [0.0, 0.0, lift], 0.0)
        then = block.touching(dataclasses.replace(state, positions=moved), history)
        assert then.all() if every else not then.any()


@pytest.mark.parametrize(
    "rule, smoothing, points, stick",
    [
        ("centroid", None, "upper", "penalty"),
        ("gauss", None, "upper", "penalty"),
        ("vertices", None, "upper", "penalty"),
        ("gauss", 0.0, "upper", "penalty"),
        ("gauss", 0.05, "upper", "penalty"),
        ("vertices", None, "lower", "penalty"),
        # the stick spring of the normal law: 4 stuck points on the 0.05-mm ramp, and the
        # mirrored pass's points in the fade (its k_t = w W'')
        ("gauss", 0.05, "upper", "normal law"),
        ("vertices", None, "lower", "normal law"),
    ],
)
def test_ply_contact_with_friction_conforms(rule, smoothing, points, stick):
    """The return mapping's own tangent (exact: stick and slip, through the facing
    triangle's normal and the anchor's triangle), energies and history, objectivity; and an
    accepted step leaves every point at or within the limit with dissipation added; the
    mirrored pass (``points="lower"``) alike."""

    def build(turn=UNTURNED):
        return plies_with_friction(turn, rule=rule, smoothing=smoothing, points=points, stick=stick)

    block, state, history = build()
    sliding = block.friction_state(state, history)
    assert sliding.stuck.sum() >= 2 and sliding.sliding.sum() >= 2
    assert check_tangent(block, state, history)
    check_energy(block, state, history)
    check_objectivity(build, TURN)
    after = block.update_history(state, history)
    assert block.dissipated_energy(after) > block.dissipated_energy(history) == 1.0
    again = block.friction_state(state, after)
    limit = MU * again.pressing
    assert np.all(np.linalg.norm(again.force, axis=1) <= limit * (1 + 1e-9) + 1e-12)
    assert np.allclose(np.linalg.norm(again.force, axis=1)[sliding.sliding], limit[sliding.sliding])


def test_ply_contact_friction_obeys_coulomb():
    """check_friction at the upper nodes of a ply whose triangles have their own corners
    (centroid rule: each node carries N_j = 1/3 of one point's force), the facing normals;
    and the kit names a sliding point taken for stuck off the limit."""
    block, state, history = plies_with_friction(rule="centroid", separate=True)
    sliding = block.friction_state(state, history)
    assert sliding.stuck.sum() >= 2 and sliding.sliding.sum() >= 2
    nodes = block.above.ravel()  # one point per triangle, three nodes each
    normals = np.repeat(block.facing(state).normal, 3, axis=0)
    stuck, slides = np.repeat(sliding.stuck, 3), np.repeat(sliding.sliding, 3)
    check_friction(
        block, state, history, stuck=stuck, sliding=slides, normal=lambda s: normals, nodes=nodes
    )
    with pytest.raises(AssertionError, match="sliding off the friction limit"):
        check_friction(
            block, state, history, stuck=stuck, sliding=stuck, normal=lambda s: normals, nodes=nodes
        )


def test_frictionless_ply_contact_keeps_no_history_and_its_numbers():
    """friction=0 (default): no friction history, only each point's side of the lower face
    (elements/ply_sides.py), and a friction history handed in changes nothing."""
    from elements.ply_sides import PlySides

    block, state, _ = plies()
    kept = block.initial_history()
    assert isinstance(kept, PlySides) and block.dissipated_energy(kept) == 0.0
    assert isinstance(block.update_history(state, kept), PlySides)
    assert block.update_history(state, None) is None
    _, _, history = plies_with_friction(rule="centroid")
    force, moment = block.internal_force(state)
    again = block.internal_force(state, history)
    assert np.array_equal(force, again[0]) and np.array_equal(moment, again[1])
    assert block.strain_energy(state) == block.strain_energy(state, history)
    assert len(block.tangent(state, history)) == 1
