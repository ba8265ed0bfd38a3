"""The explicit step's bound of the interactions' penalty springs, per node (femcore/compiled.py
``penalty_frequency_squared``; docs/theory.md §6.2, "The penalty springs"): omega_max^2 of the
assembled K + springs against the lumped M is at most the elements' bound plus the largest over
the nodes of sum k / m, the sum over every spring of every interaction at the node.

Reference: the exact critical step 2 / omega_max of the assembled free system (dense
eigenvalues of the finite-difference stiffness of the elements and the interactions at a state
where the springs press, the lumped masses and rotary inertias: ``exact_stable_step``). The
solver's step at safety 1 (no damping) must not exceed it, on models whose penalties are stiff
enough against the elements (10 to 500 times their omega^2) that the springs set the step, so
that a bound which leaves out a spring's share is caught: the largest single interaction's k / m
at a node, without the sums over the interactions that touch the same node, exceeds the exact
step in each of the models below that pinches a node.
"""

import numpy as np
import pytest

from elements import MindlinShell, RigidPlane
from elements.layup import Layup
from femcore import Mesh, Model
from femcore.testing import exact_stable_step
from materials import ElasticShell, Fabric
from solvers import CentralDifference

# The tools press into the bodies from the start on purpose (the springs they bound are the
# pressed ones): the start-overlap warning (elements/contact_start.py) is expected here.
pytestmark = pytest.mark.filterwarnings("ignore::femcore.entry_error.EntryWarning")

ALUMINIUM = ElasticShell(70000.0, 0.3, 1.0, 2.7e-9)  # E (MPa), nu, h (mm), rho (t/mm^3)
PLY = Fabric(thickness=0.3, areal_density=2.85e-10, tension=60.0, shear=0.2, bending=0.375)
INTO = 0.001  # mm, how far each tool starts inside the contact offset: its springs press


def _steps(compiled, state):
    """(the solver's critical step, the exact 2 / omega_max, the step a bound without the sums
    over interactions would give: the elements' bound plus the largest k / m of any single
    interaction at any node), s."""
    mass, inertia = compiled.lumped_mass(state)
    solver = CentralDifference(1.0, safety=1.0)
    step = solver._step_size(compiled, state, None, mass, inertia)
    elements = min(compiled.stable_dt(state), compiled.assembled_stable_dt(state, mass, inertia))
    single = 0.0
    for interaction in compiled.interactions:
        nodes, stiffness = interaction.springs_at(state)
        single = max(single, float(np.max(stiffness / mass[nodes])))
    unsummed = 2.0 / np.sqrt((2.0 / elements) ** 2 + single)
    return step, exact_stable_step(compiled, state), unsummed


def _pinched(die_nodes, holder_nodes):
    """A free 20-mm aluminium plate (4 x 4 cells, 1 mm) between a die under it and a holder on
    it, each pressing the given nodes with 1e7 N/mm (k / m 4.7 times the elements' omega^2 at
    an inner node)."""
    mesh = Mesh.rectangle(20.0, 20.0, nx=4, ny=4)
    model = Model(mesh.with_points(mesh.points + [0.0, 0.0, 0.5]))
    model.add(MindlinShell(ALUMINIUM))
    model.fix([0], ["ux", "uy"])
    model.fix([4], ["uy"])
    die = RigidPlane((0.0, 0.0, INTO), (0.0, 0.0, 1.0))
    holder = RigidPlane((0.0, 0.0, 1.0 - INTO), (0.0, 0.0, -1.0))
    model.contact(die, nodes=die_nodes, penalty=1e7)
    model.contact(holder, nodes=holder_nodes, penalty=1e7)
    return model.compile()


def test_a_node_pinched_by_two_tools_takes_both_springs():
    """The centre node between the die and the holder: the step is 0.95 of the exact one (the
    two springs add along z at the node, nearly exactly the bound); without the sum over the
    two tools it would be 1.29 times the exact step, unstable."""
    compiled = _pinched([12], [12])
    step, exact, unsummed = _steps(compiled, compiled.initial_state())
    assert step <= exact
    assert unsummed > 1.2 * exact


def test_two_tools_on_two_nodes_take_the_larger_spring_not_the_sum():
    """The die on the centre node, the holder on another: the springs sit on different nodes,
    and the step is 0.91 of the exact one, where the sum over the tools of each one's largest
    k / m (the bound before) gave 0.68."""
    compiled = _pinched([12], [6])
    step, exact, _ = _steps(compiled, compiled.initial_state())
    assert step <= exact
    assert step > 0.85 * exact


def _stack(angles, kinematics, penalty, tool_penalty, shift=0.0):
    """Two 20-mm plies (2 cells across) at ``angles``, both ply contact passes (the upper ply's
    Gauss points, the lower ply's nodes) with ``penalty`` N/mm per node, a die under the bottom
    ply and a holder on the top one with ``tool_penalty``; the top ply sunk 0.05 mm into the
    bottom one and moved ``shift`` mm along x (its points then past the bottom ply's outline,
    in the fade's band). Returns the compiled model and the state."""
    layup = Layup(
        PLY, angles, 20.0, cells=2, kinematics=kinematics, rule="gauss",
        lower_rule="vertices", penalty=penalty,
    )  # fmt: skip
    model = layup.model()
    sink = 0.05
    bottom = layup.heights[0] - 0.5 * PLY.thickness
    top = layup.heights[-1] + 0.5 * PLY.thickness - sink
    model.contact(RigidPlane((0, 0, bottom + INTO), (0, 0, 1.0)), "ply_1", penalty=tool_penalty)
    model.contact(RigidPlane((0, 0, top - INTO), (0, 0, -1.0)), "ply_2", penalty=tool_penalty)
    compiled = model.compile()
    state = compiled.initial_state()
    state.positions[layup.ply_nodes[1], 2] -= sink
    state.positions[layup.ply_nodes[1], 0] += shift
    return compiled, state


@pytest.mark.parametrize("kinematics", ["mindlin-elastic", "fibrous"])
@pytest.mark.parametrize("angles", [(0.0, 90.0), (0.0, 45.0)], ids=["0-90", "0-45"])
def test_a_pressed_ply_stack_between_two_tools(angles, kinematics):
    """Every node of the stack in three interactions at once (the die or the holder, and the
    two ply passes, a node being a point of one and a face's corner in the other): the step
    is at most the exact one. On these 2-cell plies every node lies on or beside the outline,
    where the ply springs take the fade's beside figure (3 + 3 A x + 3 x^2) it may reach
    before the next evaluation (elements/ply_springs.py): 0.69-0.83 of the exact step,
    measured (0.43 at SIDEWAYS = 0.5, the figure 12 + ...)."""
    compiled, state = _stack(angles, kinematics, 1000.0, 3000.0)
    step, exact, _ = _steps(compiled, state)
    assert 0.35 * exact < step <= exact


@pytest.mark.parametrize("kinematics", ["mindlin-elastic", "fibrous"])
def test_a_stack_with_points_in_the_fade_band(kinematics):
    """[0/0] plies, the top one moved 18 mm along x: its points over the bottom ply's outline
    strip are in the fade's band (``springs_at`` takes their c_p > 12). The step stays at most
    the exact one."""
    compiled, state = _stack((0.0, 0.0), kinematics, 1000.0, 1000.0, shift=18.0)
    block = compiled.interactions[0]
    nodes, at = block.springs_at(state)
    plain = block.springs()[1]
    assert np.max(at / plain) > 12.0  # the premise: points in the band
    step, exact, _ = _steps(compiled, state)
    assert step <= exact
