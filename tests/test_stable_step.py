"""The automatic time step is safe on the meshes that broke it: cells of aspect 10 and 20,
sliver triangles, fibrous directors tilted far from the normal (h_m = h / cos(tilt) grows).

The reference is the exact critical step 2 / omega_max of the assembled free system, K phi =
omega^2 M phi with K the finite-difference stiffness and M the lumped masses and rotary
inertias (dense eigenvalues, tests/test_conformance.py). The element bound must not exceed it
(that would be an unstable step) and should not be far below it (a needlessly small one):
within a factor 2, as for the conformance cases. The explicit runs check the same thing the
way a user meets it: at the default safety 0.9 the energy balance holds.
"""

import numpy as np
import pytest
from shell_helpers import fabric

from elements import FibrousShell, MindlinShell
from femcore import Mesh, Model
from femcore.rotation import rotate_about
from femcore.testing import exact_stable_step
from materials import ElasticShell, presets
from solvers import CentralDifference

ALUMINIUM = ElasticShell(70000.0, 0.3, 1.0, 2.7e-9)  # E (MPa), nu, h (mm), rho (t/mm^3)


def strip(aspect: int) -> Model:
    """A 20 mm strip of 20 x 2 cells 1 mm by ``aspect`` mm, clamped at x = 0."""
    model = Model(Mesh.rectangle(20.0, 2.0 * aspect, nx=20, ny=2))
    model.add(MindlinShell(ALUMINIUM))
    model.fix("left")
    return model


def slivers(offset: float) -> Model:
    """A 10 mm square split into four triangles around a node ``offset`` mm from its bottom
    edge: two slivers with an angle of about 2 offset / 10 rad at the bottom corners."""
    points = np.array(
        [[0.0, 0.0, 0.0], [10.0, 0.0, 0.0], [10.0, 10.0, 0.0], [0.0, 10.0, 0.0], [5.0, offset, 0]]
    )
    triangles = np.array([[0, 1, 4], [1, 2, 4], [2, 3, 4], [3, 0, 4]])
    model = Model(Mesh(points, triangles))
    model.add(MindlinShell(ALUMINIUM))
    model.fix([0, 3])
    return model


def bounds_and_exact(model: Model, state=None):
    """(the cells' bound, the solver's: the smaller of it and the assembly's Gershgorin bound,
    the exact critical step)."""
    compiled = model.compile()
    state = state if state is not None else compiled.initial_state()
    cells = compiled.stable_dt(state)
    assembled = compiled.assembled_stable_dt(state, *compiled.lumped_mass(state))
    return cells, min(cells, assembled), exact_stable_step(compiled, state)


@pytest.mark.parametrize("aspect", [1, 10, 20])
def test_mindlin_step_is_safe_on_stretched_cells(aspect):
    cells, step, exact = bounds_and_exact(strip(aspect))
    assert cells <= exact  # each element's eigenvalue bounds the assembly's
    assert 0.5 * exact <= step <= exact


@pytest.mark.parametrize("offset", [1.0, 0.2, 0.05])
def test_mindlin_step_is_safe_on_slivers(offset):
    """The cells' bound stays safe but falls to 0.14-0.03 of the exact step here (a sliver's
    share of its nodes' mass is tiny); the solver takes it, the smaller bound."""
    cells, step, exact = bounds_and_exact(slivers(offset))
    assert cells <= exact
    assert step <= exact


@pytest.mark.parametrize("tilt", [0.5, 1.0, 1.2, 1.3, 1.4])
def test_fibrous_step_is_safe_with_directors_far_from_the_normal(tilt):
    """Directors turned by ``tilt`` rad about y: h_m = h / cos(tilt), up to 3.7 h, and past
    the guard (cos(1.4) = 0.17 < 0.2) 5 h. A rotation moves the fibre levels by h_m / cos(tilt)
    (h_m turns with the director), and the rotary inertia m (h_m / cos(tilt))^2 / 4 follows
    that lever (docs/theory.md §6.2 A2): with m h_m^2 / 4 the cells' bound was 1.32 times the
    exact step at 1.2 rad (69 deg), the tilt at which a formed blank's corner went unstable."""
    model = Model(Mesh.rectangle(30.0, 20.0, nx=3, ny=2))
    model.add(FibrousShell(fabric()))
    model.fix("left")
    compiled = model.compile()
    state = compiled.initial_state()
    turn = np.tile([0.0, tilt, 0.0], (compiled.n_nodes, 1))
    state.directors = rotate_about(state.directors, turn)
    cells, step, exact = bounds_and_exact(model, state)
    assert cells <= exact
    assert 0.5 * exact <= step <= exact


@pytest.mark.parametrize("aspect", [10, 20])
def test_stretched_mindlin_strip_runs_undamped_at_the_default_safety(aspect):
    """Gravity as a step load on the strip: before the element eigenvalue bound it diverged
    within 2-7 steps on such cells. 3000 steps: the shortest modes have made hundreds of
    oscillations, an unstable one would have grown by orders of magnitude."""
    model = strip(aspect)
    model.gravity((0.0, 0.0, -9810.0))
    dt = model.compile().stable_dt(model.compile().initial_state())
    result = CentralDifference(duration=3000 * 0.9 * dt, progress=False).solve(model)
    assert result.converged
    assert result.info["energy_balance_error"] < 1e-3


def test_the_readme_laminate_strip_falls_undamped_at_the_default_safety():
    """The README's G1151 strip (200 x 60 mm, 8 x 2 cells, clamped) under gravity applied at
    once, undamped, with the automatic step: it diverged at t = 0.18 s (the last frame with a
    director through the surface) before the energy checks and the assembled step bound. Past
    that time, it runs with its energy balance at 1e-3 of the largest energy (the fibrous
    shell's nonlinearity; 5e-2 stops a run)."""
    model = Model(Mesh.rectangle(200.0, 60.0, nx=8, ny=2))
    model.add(FibrousShell(presets.g1151_laminate(), clamped="left"))
    model.fix("left")
    model.gravity((0.0, 0.0, -9810.0))
    result = CentralDifference(duration=0.2, progress=False).solve(model)
    assert result.converged
    assert result.info["energy_balance_error"] < 5e-3
    assert np.all(result.thickness >= 15.0 * (1.0 - 1e-9))  # h_m >= h: no director inverted


def test_the_step_is_the_safety_times_the_smaller_of_the_cells_and_the_assembly_bounds():
    """On square Mindlin cells the assembly's Gershgorin bound (1.04e-7 s) is below the
    cells' (1.18e-7 s; exact 1.20e-7 s): the solver takes the smaller, where it took the
    larger, which put a fibrous forming blank past its exact critical step."""
    model = strip(1)
    model.gravity((0.0, 0.0, -9810.0))
    compiled = model.compile()
    state = compiled.initial_state()
    cells = compiled.stable_dt(state)
    assembled = compiled.assembled_stable_dt(state, *compiled.lumped_mass(state))
    assert assembled < cells
    result = CentralDifference(duration=20 * cells, progress=False).solve(compiled)
    assert result.info["dt"] == pytest.approx(0.9 * assembled, rel=1e-12)


@pytest.mark.slow
def test_the_coarse_hemisphere_forming_blank_runs_at_the_default_safety():
    """The hemisphere forming case's fibrous blank (12 x 12 squares, punch and meshed die,
    without its holder, about 16000 steps, 30-70 s on one thread) at the default safety
    0.9: before the rotary inertia followed the lever of a tilted director its free corners'
    directors went unstable late in the stroke (the case ran at safety 0.5). Measured on the
    sharp die: energy balance within 0.75 % of the largest energy, the step 0.64 of the exact
    critical step of the assembly with the contact springs at the end; it passes on the die's
    10-mm entry radius too (151 s wall at load 7)."""
    from validation.cases import hemisphere_forming as case

    _, model = case.model(12, "fibrous", holder_force=0.0, rim=case.DIE_RIM)  # corners free
    solver = CentralDifference(
        duration=case.DURATION, damping=case.DAMPING, progress=False, kinetic_bound=None
    )
    result = solver.solve(model)
    assert result.converged
    assert result.info["energy_balance_error"] < 0.02


@pytest.mark.parametrize("kind", ["mindlin", "fibrous"])
def test_the_assembled_bound_is_gershgorins_on_the_free_dofs_and_never_above_the_exact_step(kind):
    """assembled_stable_dt is 2 / sqrt(max_i sum_j |K_ij| / sqrt(M_i M_j)) over the free DOFs
    (the tangent sliced to them, to rounding) and, Gershgorin's circles holding every
    eigenvalue, at most the exact 2 / omega_max of the assembly: a clamped, jittered sheet
    with directors tilted 0.4 rad (fibrous)."""
    mesh = Mesh.rectangle(30.0, 20.0, nx=3, ny=2)
    model = Model(mesh)
    model.add(FibrousShell(fabric()) if kind == "fibrous" else MindlinShell(ALUMINIUM))
    model.fix("left")
    compiled = model.compile()
    state = compiled.initial_state()
    rng = np.random.default_rng(2)
    state.positions = state.positions + rng.normal(scale=0.3, size=state.positions.shape)
    state.directors = rotate_about(state.directors, rng.normal(scale=0.4, size=(mesh.n_nodes, 3)))
    mass, inertia = compiled.lumped_mass(state)
    bound = compiled.assembled_stable_dt(state, mass, inertia)

    free = compiled.dofs.free_slots
    diagonal = np.column_stack([mass, mass, mass, inertia, inertia]).ravel()[free]
    sliced = abs(compiled.stiffness(state, "element").tocsr()[free][:, free]).toarray()
    scale = 1.0 / np.sqrt(diagonal)
    gershgorin = 2.0 / np.sqrt(float((sliced @ scale * scale).max()))
    assert bound == pytest.approx(gershgorin, rel=1e-12)
    assert bound <= exact_stable_step(compiled, state)


@pytest.mark.parametrize(
    "drift, evaluated", [(0.0, [0, 100, 200]), (0.003, [0, 40, 80, 120, 160, 200, 240])]
)
def test_the_assembled_bound_waits_for_the_cells_bound_to_move_or_the_longest_interval(
    monkeypatch, drift, evaluated
):
    """The assembled bound costs a tangent: looked at every ASSEMBLED_DT_EVERY steps (here
    20), it is evaluated again only when the cells' bound (evaluated every 10 steps) has moved
    by more than ASSEMBLED_DT_STEADY (1 %) since the last evaluation, and at least every
    ASSEMBLED_DT_MAX steps (here 100): 250 steps of a resting strip whose cells' bound does
    not move, and of the same with that bound made to shrink by ``drift`` at each of its
    evaluations (past 1 % after 4, 40 steps)."""
    from solvers import explicit, explicit_step_size

    monkeypatch.setattr(explicit, "ASSEMBLED_DT_EVERY", 20)
    monkeypatch.setattr(explicit_step_size, "ASSEMBLED_DT_MAX", 100)
    compiled = strip(1).compile()
    evaluate, cells = compiled.assembled_stable_dt, compiled.cell_stable_dt
    calls, steps = [], []

    def drifting(state):  # the solver asks at its start and then every 10 steps
        calls.append(state.time)
        return [dt * (1.0 - drift * (len(calls) - 1)) for dt in cells(state)]

    def counted(state, mass, inertia):
        steps.append(10 * (len(calls) - 1))
        return evaluate(state, mass, inertia)

    monkeypatch.setattr(compiled, "cell_stable_dt", drifting)
    monkeypatch.setattr(compiled, "assembled_stable_dt", counted)
    step = 0.9 * evaluate(compiled.initial_state(), *compiled.lumped_mass(compiled.initial_state()))
    CentralDifference(duration=249.5 * step, progress=False).solve(compiled)
    assert steps == evaluated


def test_where_the_cells_bound_governs_with_room_the_assembled_bound_waits_for_half_of_it():
    """The assembled bound 1.4 times the cells' when last evaluated (room 0.4): evaluated
    again once the cells' bound has moved by more than half that room (20 %), not at 1 %;
    with no room, at 1 %; and in any case after ASSEMBLED_DT_MAX steps."""
    from solvers import explicit_step_size

    solver = CentralDifference(duration=1.0)
    solver._assembled = (1.4e-6, 1.0e-6, 0)
    assert not solver._assembled_due(0.85e-6, 100)
    assert not solver._assembled_due(1.15e-6, 100)
    assert solver._assembled_due(0.79e-6, 100)
    assert solver._assembled_due(1.0e-6, explicit_step_size.ASSEMBLED_DT_MAX)
    solver._assembled = (0.9e-6, 1.0e-6, 0)  # the assembled bound governs: 1 %
    assert not solver._assembled_due(0.995e-6, 100)
    assert solver._assembled_due(0.985e-6, 100)


def plate_on_a_die(holder_mass: float | None = None, penalty: float | None = None) -> Model:
    """A 20 mm Mindlin plate of 10 x 10 cells resting on a die plane (its mid-surface h / 2
    above it: every node touching), in-plane motion held; with ``holder_mass`` (t) a holder
    plane on its top face, free along z, pushed down by 1 N. The die's ``penalty`` N/mm
    (None: automatic, as the holder's)."""
    from elements import RigidPlane

    flat = Mesh.rectangle(20.0, 20.0, nx=10, ny=10)
    model = Model(flat.with_points(flat.points + [0.0, 0.0, 0.5]))
    model.add(MindlinShell(ALUMINIUM))
    model.fix(lambda x, y, z: np.ones_like(x, dtype=bool), ["ux", "uy"])
    model.contact(RigidPlane((0.0, 0.0, 0.0), (0.0, 0.0, 1.0)), penalty=penalty)
    if holder_mass is not None:
        holder = RigidPlane(
            (0.0, 0.0, 1.0), (0.0, 0.0, -1.0), free="z", force=(0, 0, -1.0), mass=holder_mass
        )
        model.contact(holder)
    return model


def test_the_assembled_bound_is_the_element_blocks_alone_the_contact_springs_added_apart():
    """The contact springs enter the step once, through penalty_frequency_squared: the
    Gershgorin bound of a plate touching a die at every node is that of the plate alone (it
    also took the contact's tangent, counting the springs twice: with a stiff penalty the
    bound was 0.54 of the plate's)."""
    touching = plate_on_a_die(penalty=1e6).compile()
    alone_model = Model(touching.mesh)
    alone_model.add(MindlinShell(ALUMINIUM))
    alone_model.fix(lambda x, y, z: np.ones_like(x, dtype=bool), ["ux", "uy"])
    alone = alone_model.compile()
    state = touching.initial_state()
    assert touching.interactions[0].touch(state)[2].all()  # every node touches
    mass, inertia = touching.lumped_mass(state)
    assert touching.assembled_stable_dt(state, mass, inertia) == alone.assembled_stable_dt(
        alone.initial_state(), mass, inertia
    )


def test_a_driven_holders_springs_are_bounded_by_max_k_over_m_plus_their_sum_over_its_mass():
    """A holder as heavy as the plate it presses (121 nodes), every spring pressed: the
    largest eigenvalue of its springs' mass-scaled stiffness (dense, numpy) is max k / m +
    sum k / m_t, here exactly (the automatic penalty makes k / m the same at every node), and
    the bound the step takes (penalty_frequency_squared) is that to rounding. Gershgorin's row
    sums, taken before, gave the tool's node sum k (1 + sqrt(m_t / m)) / m_t: 5.9 times it."""
    plate_mass = 20.0 * 20.0 * ALUMINIUM.thickness * ALUMINIUM.density
    model = plate_on_a_die(holder_mass=plate_mass)
    compiled = model.compile()
    holder = compiled.interactions[1]
    state = compiled.initial_state()
    tool_node = holder.tool_node
    state.positions[tool_node, 2] -= 0.01  # the holder pressed into the plate
    assert holder.touch(state)[0].min() > 0.0
    mass, _ = compiled.lumped_mass(state)
    (part,) = holder.tangent(state)
    nodes = part.nodes
    size = 3 * compiled.n_nodes
    stiffness = np.zeros((size, size))
    for row, pair in zip(nodes, part.blocks):
        slots = (3 * row[:, None] + np.arange(3)).ravel()
        stiffness[np.ix_(slots, slots)] += pair.reshape(6, 6)
    scale = 1.0 / np.sqrt(np.repeat(mass, 3))
    exact = np.linalg.eigvalsh(scale[:, None] * stiffness * scale[None, :]).max()
    k = holder.stiffness
    on_nodes = mass[nodes[:, 0]]
    assert exact == pytest.approx((k / on_nodes).max() + k.sum() / mass[tool_node], rel=1e-9)
    springs = holder.springs()
    bound = float(np.max(springs[1] / mass[springs[0]]))
    assert exact * (1.0 - 1e-12) <= bound <= exact * (1.0 + 1e-9)


@pytest.mark.parametrize("angle", [30.0, 60.0, 80.0])
def test_mindlin_step_follows_a_sheared_blank_as_its_strains_do(angle):
    """A fabric's Mindlin calibration (ElasticShell.equivalent) sheared as a net shears,
    fibre lengths kept (x, y) -> (x + y sin g, y cos g): the elements' strains are Green's, so
    their stiffness follows the stretch (at most 1 + sin g squared), not the current altitudes,
    which fall as cos g. Against the exact step of the sheared sheet the cells' bound stays
    safe and within a factor 2 (the conformance cases' band); one following the altitudes was
    0.32 of the exact step at 80 deg (the Mindlin hemisphere blank's folded cells took its
    step down 7-fold, docs/theory.md §6.2 B5)."""
    model = Model(Mesh.rectangle(40.0, 40.0, nx=4, ny=4))
    model.add(MindlinShell(ElasticShell.equivalent(fabric())))
    model.fix("left")
    compiled = model.compile()
    state = compiled.initial_state()
    x, y = state.positions[:, 0].copy(), state.positions[:, 1].copy()
    g = np.radians(angle)
    state.positions[:, 0] = x + y * np.sin(g)
    state.positions[:, 1] = y * np.cos(g)
    cells, step, exact = bounds_and_exact(model, state)
    assert cells <= exact
    assert 0.5 * exact <= cells


@pytest.mark.parametrize("stretch", [1.05, 1.2])
def test_mindlin_step_is_safe_on_a_stretched_sheet(stretch):
    """Stretched in its plane by ``stretch`` both ways, the sheet's Green-Lagrange stiffness
    grows as the squared stretch: the cells' bound must shorten, where one following the
    current altitudes lengthened and was 1.13 times the exact step at 1.2 (an unstable step;
    docs/theory.md §6.2 B5)."""
    model = Model(Mesh.rectangle(40.0, 40.0, nx=4, ny=4))
    model.add(MindlinShell(ALUMINIUM))
    model.fix("left")
    state = model.compile().initial_state()
    state.positions[:, :2] *= stretch
    cells, step, exact = bounds_and_exact(model, state)
    assert 0.5 * exact <= cells <= exact
