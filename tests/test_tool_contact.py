"""The compiled contact pass of the analytic tools (elements/tool_contact.py) gives the forces
of ContactBlock's numpy formulas: to 1e-12 of the largest force at every node, penetrating or
not, for a punch (a sphere, outside), a bowl (inside), a moving plane, a moving ring (a
holder's face with its bore) and a plane driven along
its free axis by its own node; and it is taken only where those formulas are the frictionless
undamped ones."""

import pickle

import numpy as np
import pytest

from elements import RigidAnnulus, RigidCylinder, RigidPlane, RigidSphere, tool_contact
from elements.contact import Contact, ContactBlock
from femcore import Body, Mesh
from femcore.state import State

TOOLS = [
    RigidSphere((0.3, -0.2, 4.0), 4.2, motion=(0.0, 0.0, -0.5), amplitude="smooth"),
    RigidSphere((0.0, 0.0, 6.0), 7.0, side="inside"),
    RigidPlane((0.0, 0.0, -1.2), (0.2, 0.1, 1.0), motion=(0.0, 0.0, 0.3)),
    # a ring whose bore (1.5 mm) takes in some of the nodes, touching its edge or not
    RigidAnnulus((0.0, 0.0, -0.8), (0.1, 0.0, -1.0), 1.5, motion=(0.0, 0.0, 0.2)),
]


def _state(mesh: Mesh, seed: int, load_factor: float = 0.5) -> State:
    rng = np.random.default_rng(seed)
    x = mesh.points + rng.normal(scale=0.3, size=mesh.points.shape) - [2.0, 2.0, 0.4]
    zero = np.zeros_like(x)
    state = State(positions=x, directors=zero, velocities=zero, angular_velocities=zero)
    state.load_factor = load_factor
    return state


@pytest.mark.parametrize("tool", TOOLS)
def test_the_compiled_pass_gives_the_numpy_forces_of_an_analytic_tool(tool):
    mesh = Mesh.rectangle(4.0, 4.0, nx=6, ny=6)
    contact = Contact(tool, np.arange(mesh.n_nodes), offset=0.5, penalty=100.0)
    fast = contact.bind(Body.bare(mesh))
    assert type(fast) is ContactBlock and fast.compiled_forces is tool_contact.contact_forces
    reference = ContactBlock(
        contact, np.arange(mesh.n_nodes), np.full(mesh.n_nodes, 0.5), mesh.n_nodes,
        mesh.points, np.zeros(mesh.n_nodes),
    )  # fmt: skip
    reference.stiffness = fast.stiffness.copy()
    for seed in range(3):
        state = _state(mesh, seed)
        p, _, _ = reference.touch(state)
        assert (p > 0).sum() >= 3 and (p == 0).sum() >= 3  # some touch, some do not
        expected = reference.contact_forces(state)
        scale = np.abs(expected).max()
        np.testing.assert_allclose(fast.contact_forces(state), expected, rtol=0, atol=1e-12 * scale)
        f_fast, _ = fast.internal_force(state)
        f_ref, _ = reference.internal_force(state)
        np.testing.assert_allclose(f_fast, f_ref, rtol=0, atol=1e-12 * scale)
        np.testing.assert_allclose(
            fast.tool_work(state, None, 0.2, 0.5),
            reference.tool_work(state, None, 0.2, 0.5),
            rtol=1e-12,
        )


def test_a_driven_plane_takes_the_compiled_pass_with_its_node_and_its_reaction():
    """A holder: the contact sees the nodes less the tool node's translation, and the tool
    node takes the sum of the reactions."""
    mesh = Mesh.rectangle(4.0, 4.0, nx=6, ny=6)
    tool_node = mesh.n_nodes - 1
    nodes = np.arange(mesh.n_nodes - 1)
    holder = RigidPlane((0.0, 0.0, 0.5), (0.0, 0.1, -1.0), free="z", force=(0, 0, -5.0), mass=1.0)
    contact = Contact(holder, nodes, offset=0.5, penalty=100.0, tool_node=tool_node)
    fast = contact.bind(Body.bare(mesh))
    assert type(fast) is ContactBlock and fast.compiled_forces is tool_contact.contact_forces
    reference = ContactBlock(
        contact, nodes, np.full(len(nodes), 0.5), mesh.n_nodes, mesh.points,
        np.zeros(mesh.n_nodes), tool_node,
    )  # fmt: skip
    reference.stiffness = fast.stiffness.copy()
    state = _state(mesh, 4)
    state.positions[tool_node] = mesh.points[tool_node] + [0.0, 0.0, -0.7]
    expected, _ = reference.internal_force(state)
    assert np.abs(expected[tool_node]).max() > 0.0
    got, _ = fast.internal_force(state)
    np.testing.assert_allclose(got, expected, rtol=0, atol=1e-12 * np.abs(expected).max())
    # The tool node moved, the contact nodes did not: not the last answer.
    state.positions[tool_node, 2] -= 0.2
    np.testing.assert_allclose(
        fast.internal_force(state)[0], reference.internal_force(state)[0], rtol=0,
        atol=1e-12 * np.abs(expected).max(),
    )  # fmt: skip


@pytest.mark.parametrize(
    "options",
    [{"friction": 0.2}, {"damping": 0.5}, {"augmented": True}],
)
def test_contacts_with_other_formulas_keep_the_numpy_path(options):
    mesh = Mesh.rectangle(4.0, 4.0, nx=2, ny=2)
    block = Contact(TOOLS[0], np.arange(mesh.n_nodes), penalty=1.0, **options).bind(Body.bare(mesh))
    assert getattr(block, "compiled_forces", None) is None
    cylinder = RigidCylinder((0.0, 0.0, -20.0), (1.0, 0.2, 0.0), 20.0)
    block = Contact(cylinder, np.arange(mesh.n_nodes), penalty=1.0).bind(Body.bare(mesh))
    assert block.compiled_forces is None


def _die_and_blank():
    """A small forming die (a bowl of 10 mm with a 2-mm round and a flange out to 17 mm, 8
    rings) and a 30-mm blank over it: the blank's corners reach past the flange's edge."""
    from elements import RigidSurface
    from validation.specimens import hemisphere_die

    mesh = Mesh.rectangle(30.0, 30.0, nx=10, ny=10, origin=(-15.0, -15.0, 0.0))
    return RigidSurface(hemisphere_die(10.0, 17.0, rings=8, rim=2.0)), mesh


def _pressed(mesh: Mesh, call: int, seed: int) -> State:
    """The blank drawn into the die by 0.05 mm a call towards the axis and sunk into the bowl
    (half of it past the contact offset), with some nodes lifted far off the flange, some
    corners pushed below the flange's plane past its outer edge, and a jitter."""
    rng = np.random.default_rng(seed)
    r0 = np.linalg.norm(mesh.points[:, :2], axis=1)
    r = np.maximum(r0 - 0.05 * call, 0.0)
    angle = np.arctan2(mesh.points[:, 1], mesh.points[:, 0])
    z = np.where(r < 9.7, -np.sqrt(np.maximum(9.7**2 - r**2, 0.0)), 0.1)
    x = np.column_stack([r * np.cos(angle), r * np.sin(angle), z])
    x += rng.normal(scale=0.05, size=x.shape)
    x[::7, 2] += 6.0  # beyond the search distance
    x[r0 > 19.0, 2] = -0.4  # behind the flange's facets, beside its open edge
    zero = np.zeros_like(x)
    state = State(positions=x, directors=zero, velocities=zero, angular_velocities=zero)
    state.load_factor = 0.5
    return state


def test_the_compiled_pass_gives_the_numpy_forces_of_a_meshed_die_on_a_moving_blank():
    """Two dies, each with its own candidate lists and kept facets: the compiled pass and
    ContactBlock's numpy formulas over 40 calls on a blank sliding into the bowl (its lists
    searched again on the way), nodes pressed, nodes off the die, nodes beyond the search
    distance and nodes beside the flange's open edge: the same forces to the last bit (the
    same operations in the same order; the far nodes, whose distance numpy's norm may sum in
    another order, press nothing). The compiled pass keeps no facet record until the
    contact is frozen (Static's stop diagnosis reads it)."""
    fast_die, mesh = _die_and_blank()
    numpy_die, _ = _die_and_blank()
    nodes = np.arange(mesh.n_nodes)
    fast = Contact(fast_die, nodes, offset=0.15, penalty=100.0).bind(Body.bare(mesh))
    assert fast.compiled_forces is tool_contact.contact_forces
    reference = Contact(numpy_die, nodes, offset=0.15, penalty=100.0).bind(Body.bare(mesh))
    reference.compiled_forces = None
    searched = []
    for call in range(40):
        state = _pressed(mesh, call, seed=call)
        d, _ = numpy_die.distance(state.positions, state.load_factor)
        expected = reference.contact_forces(state)
        if call == 0:
            assert (d < 0.15).sum() >= 10 and (d > 0.15).sum() >= 10  # pressed and not
            assert numpy_die._cache.far.sum() >= 10
            below = np.linalg.norm(mesh.points[:, :2], axis=1) > 19.0  # lowered past the edge
            assert below.sum() >= 4 and (d[below] > 0.0).all()  # beside the die, not in it
        searched.append(fast_die._cache.points.copy() if fast_die._cache is not None else None)
        np.testing.assert_array_equal(fast.contact_forces(state), expected)
        np.testing.assert_array_equal(
            fast.internal_force(state)[0], reference.internal_force(state)[0]
        )
    assert not np.array_equal(searched[1], searched[-1])  # the lists were searched again
    assert fast_die.facet_record().shape[1] == 0
    fast.freeze(state)
    fast.contact_forces(_pressed(mesh, 41, seed=41))
    assert fast_die.facet_record().shape == (mesh.n_nodes, 1)


def test_a_tool_offset_follows_a_new_motion_or_amplitude_and_is_the_callers_own():
    """The offset kept per load factor is the amplitude times the motion, the same bits,
    computed anew when the tool is given another motion or amplitude; the array returned is
    the caller's (changing it changes nothing kept), and the motion cannot be changed in
    place."""
    from femcore.loads import smooth_step

    tool = RigidSphere((0.0, 0.0, 10.0), 5.0, motion=(0.0, 0.0, -3.0), amplitude="smooth")
    for tau in (0.3, 0.7, 0.3, 1.0, 0.0, 0.3):
        assert np.array_equal(tool.offset(tau), float(smooth_step(tau)) * np.array([0, 0, -3.0]))
    given = tool.offset(0.3)
    given += 100.0
    assert np.array_equal(tool.offset(0.3), float(smooth_step(0.3)) * np.array([0, 0, -3.0]))
    with pytest.raises(ValueError):
        tool.motion[2] = 1.0
    tool.motion = np.array([1.0, 0.0, 0.0])
    assert tool.moves and np.array_equal(tool.offset(0.3), float(smooth_step(0.3)) * tool.motion)
    tool.amplitude = lambda tau: 0.5
    assert np.array_equal(tool.offset(0.3), [0.5, 0.0, 0.0])
    tool.motion = np.zeros(3)
    assert not tool.moves and np.array_equal(tool.offset(0.3), np.zeros(3))
    # a restored tool (a pickled or deep-copied one) refuses an edit of its motion in place
    # as the tool built does (femcore/read_only_state.py), and follows a new motion given
    tool = RigidSphere((0.0, 0.0, 10.0), 5.0, motion=(0.0, 0.0, -3.0), amplitude="linear")
    assert np.array_equal(tool.offset(0.5), [0.0, 0.0, -1.5])
    restored = pickle.loads(pickle.dumps(tool))
    with pytest.raises(ValueError, match="read-only"):
        restored.motion[2] = -10.0
    restored.motion = np.array([0.0, 0.0, -10.0])
    assert np.array_equal(restored.offset(0.5), [0.0, 0.0, -5.0])
