"""The augmented Lagrangian of the rigid-tool contact under Static (elements/augmented_contact.py):
the Uzawa passes remove the penalty's penetration and the stick spring's elastic slip, so the
results no longer depend on the penalty.

References, closed forms:

* A plate resting on a flat rigid table under a dead force F_i per node normal to it: with a
  penalty k per node each node sinks p = F_i / k (the spring's own law); a rigid table lets
  it sink by nothing, and the contact force at each node is F_i (statics).
* The same plate also pushed along the table by T_i per node with |T_i| < mu F_i: Coulomb
  friction sticks it, so it does not move along the table; the stick spring k_t lets each
  node creep by T_i / k_t.
* The capstan of tests/test_capstan.py (the chain's T2 / T1 there, discrete_capstan): the
  nodes of the wrap lie on the cylinder (radius R), not R - F / k inside it, and where the
  weight ends up does not depend on k.
"""

from dataclasses import replace

import numpy as np
import pytest

import solvers
from elements import Contact, MindlinShell, RigidPlane
from femcore import Body, Mesh, Model
from femcore.interaction_checks import (
    check_energy,
    check_force_is_energy_gradient,
    check_friction,
    check_tangent,
)
from materials import ElasticShell
from solvers import Static
from tests import test_interaction_conformance as kit
from tests.test_capstan import RADIUS, T1, capstan, discrete_capstan, pulled_tension

THICKNESS, PENALTY, LOAD = 0.5, 100.0, 1.0  # mm, N/mm per node, N per node


def plate(augmented: bool, friction: float = 0.0, push=(0.0, 0.0)) -> Model:
    """A 40 x 40 mm Mindlin plate (4 x 4 cells) resting on the table z = 0, LOAD N per node
    pressing it down and ``push`` (N per node) along the table; frictionless, the nodes are
    held in the table's plane (ux, uy), which the plane does not hold."""
    mesh = Mesh.rectangle(40.0, 40.0, nx=4, ny=4, origin=(0.0, 0.0, 0.5 * THICKNESS))
    model = Model(mesh)
    model.add(MindlinShell(ElasticShell(E=1e4, nu=0.3, thickness=THICKNESS, density=1e-9)))
    every = np.arange(mesh.n_nodes)
    if friction == 0.0:
        model.fix(every, ("ux", "uy"))
    model.contact(
        RigidPlane((0.0, 0.0, 0.0), (0.0, 0.0, 1.0)),
        friction=friction,
        penalty=PENALTY,
        augmented=augmented,
    )
    model.force(every, (push[0], push[1], -LOAD))
    return model


def sink(result) -> float:
    """The deepest node's penetration below the contact surface h / 2 above the table, mm."""
    return float(0.5 * THICKNESS - result.positions[:, 2].min())


def test_the_penalty_lets_a_pressed_plate_sink_by_the_force_over_the_penalty():
    """Pure penalty (the reference the augmentation removes): every node sinks F / k = 0.01 mm
    to 1e-9 (the plate moves rigidly: its bending carries nothing)."""
    result = Static(increments=2, progress=False).solve(plate(False))
    assert sink(result) == pytest.approx(LOAD / PENALTY, rel=1e-9)
    assert result.info["augmentations"] == []


def test_a_plate_pressed_on_a_table_does_not_sink_with_the_augmented_lagrangian():
    """Augmented: the penetration is within the default tolerance (1e-3 h = 5e-4 mm; measured
    6e-17) where the penalty alone gives 1e-2 mm, the table carries the load at every node to
    1e-9, one Uzawa pass per increment (two Newton iterations in all, one per pass)."""
    result = Static(increments=2, progress=False).solve(plate(True))
    assert sink(result) < 1e-3 * THICKNESS
    assert max(result.info["augmented_penetration"]) < 1e-3 * THICKNESS
    np.testing.assert_allclose(result.field("contact_force"), LOAD, rtol=1e-9)
    assert result.info["augmentations"] == [1, 1]
    assert result.info["iterations_per_increment"] == [2, 2]


@pytest.mark.parametrize("augmented", [False, True])
def test_a_plate_pushed_below_the_friction_limit_sticks(augmented):
    """mu = 0.3, pushed along the table by 0.2236 N per node (0.75 of mu F): stuck, the table's
    friction carries the push at every node (to 1e-9). The penalty's stick spring (k_t = k)
    lets each node creep |T| / k_t = 2.2e-3 mm (to 1e-9); the augmented contact removes that
    creep to its tolerance (5e-4 mm; measured 1e-15) and the sinking with it."""
    push = (0.2, 0.1)
    result = Static(increments=2, progress=False).solve(plate(augmented, 0.3, push))
    creep = np.linalg.norm(result.positions[:, :2] - result.mesh.points[:, :2], axis=1)
    np.testing.assert_allclose(result.field("friction_force"), np.hypot(*push), rtol=1e-9)
    if augmented:
        assert creep.max() < 1e-3 * THICKNESS
        assert sink(result) < 1e-3 * THICKNESS
        assert max(result.info["augmented_slip"]) < 1e-3 * THICKNESS
    else:
        np.testing.assert_allclose(creep, np.hypot(*push) / PENALTY, rtol=1e-9)


def capstan_run(penalty: float, augmented: bool, mu: float):
    """The capstan (tests/test_capstan.py) hung and pulled in 10 + 10 increments; augmented
    to 1e-6 mm; the stick spring at 1e-2 of the penalty with friction."""
    model = capstan(
        mu,
        1e-2 if mu else None,
        penalty=penalty,
        augmented=augmented,
        tolerance=1e-6 if augmented else None,
    )
    return Static(increments=10, step_loads_first=True, progress=False).solve(model)


def weight_rise(result) -> float:
    """How far the weight rose, mm."""
    return float(result.positions[-1, 2] - result.mesh.points[-1, 2])


def deepest_on_the_wrap(result) -> float:
    """R less the least distance of a wrapped node from the cylinder's axis, mm."""
    x = result.positions
    on_wrap = x[:, 2] > 0.5
    return float(RADIUS - np.hypot(x[on_wrap, 0], x[on_wrap, 2]).min())


@pytest.mark.parametrize("mu", [0.0, 0.2])
def test_the_augmented_capstan_does_not_depend_on_the_penalty(mu):
    """Penalties 1e3 and 1e4 N/mm per node: with the augmented Lagrangian (tolerance 1e-6 mm)
    the weight ends at the same height to 1e-5 mm (measured 2e-8 mm frictionless, 3e-10 mm
    with mu = 0.2) and the wrapped nodes on the cylinder within 1e-6 mm (measured 7.9e-7 mm
    frictionless at k = 1e3, 3e-8 mm or less otherwise); with the penalty alone the heights
    differ by more than 1e-3 mm (measured 2.7e-3 mm frictionless, 3.8e-3 mm with mu = 0.2: the
    nodes sink 1e-4 to 1.8e-3 mm into the cylinder), so that the first assertion fails without
    the augmentation. T2 / T1 is the chain's (discrete_capstan, the Euler-Eytelwein law on the
    discrete wrap) to 1e-5 (measured 1.4e-7) at both penalties. Uzawa passes per increment: 1
    at k = 1e4; at 1e3, 1 frictionless (2 at two pulling increments), 3 hanging and 2 pulling
    with friction. Newton iterations per increment (all passes): 4-12 frictionless (2-9 with
    the penalty alone), 4-20 with friction (2-10)."""
    runs = [capstan_run(k, True, mu) for k in (1e3, 1e4)]
    rises = [weight_rise(r) for r in runs]
    assert abs(rises[0] - rises[1]) < 1e-5
    for result in runs:
        assert result.converged
        assert abs(deepest_on_the_wrap(result)) < 1e-6
        assert pulled_tension(result)[-1] / T1 == pytest.approx(discrete_capstan(mu), rel=1e-5)
        assert 1 <= max(result.info["augmentations"]) <= 3
        assert not result.info["augmentations_short"]
        assert max(result.info["iterations_per_increment"]) <= 25
    plain = [weight_rise(capstan_run(k, False, mu)) for k in (1e3, 1e4)]
    assert abs(plain[0] - plain[1]) > 1e-3  # the penalty alone: its dependence


def test_an_increment_short_of_its_uzawa_passes_is_kept_and_warned_about():
    """With no pass allowed (augmentations=0) the penalty's penetration stays (1e-2 mm, 20 x
    the tolerance): the increments are accepted, listed and warned about."""
    with pytest.warns(UserWarning, match="above its tolerance after 0 Uzawa passes"):
        result = Static(increments=2, augmentations=0, progress=False).solve(plate(True))
    assert sink(result) == pytest.approx(LOAD / PENALTY, rel=1e-9)
    assert [load for load, _ in result.info["augmentations_short"]] == [0.5, 1.0]


def augmented_contact(name: str, friction: float = 0.0):
    """(block, state, history): the interaction kit's body against tool ``name``
    (tests/test_interaction_conformance.py) with an augmented contact whose nodes carry normal
    multipliers of 0-20 N (surfaces moved out by up to 0.2 mm at k = 100 N/mm) and tractions
    of about 2 N; the kit's anchors with friction."""
    _, state, history = kit.contact(name, friction=friction)
    mesh, _ = kit.body()
    nodes = np.arange(mesh.n_nodes)
    contact = Contact(kit.TOOLS[name](kit.UNTURNED), nodes, kit.OFFSET, kit.PENALTY, friction,
                      augmented=True)  # fmt: skip
    block = contact.bind(Body.bare(mesh))
    rng = np.random.default_rng(11)
    base = block.initial_history() if history is None else history
    history = replace(
        base,
        multiplier=rng.uniform(0.0, 20.0, mesh.n_nodes),
        traction=rng.normal(scale=2.0, size=(mesh.n_nodes, 3)),
    )
    return block, state, history


@pytest.mark.parametrize("name", kit.TOOLS)
def test_the_augmented_contact_conforms_with_its_multipliers(name):
    """The interaction kit's checks (femcore/interaction_checks.py, its tolerances) with non-zero
    multipliers: frictionless, the force is the energy's gradient and the tangent the force's
    derivative; with friction (mu = 0.4, stuck and sliding nodes), the tangent, Coulomb's law
    and the energies."""
    block, state, history = augmented_contact(name)
    p, _, touching = block.touch(state, history)
    assert (p > 0).sum() >= 3 and (~touching).sum() >= 1
    check_force_is_energy_gradient(block, state, history)
    assert check_tangent(block, state, history)
    block, state, history = augmented_contact(name, kit.MU)
    p, n, touching = block.touch(state, history)
    _, _, stuck, sliding = block.tangential(state, history, p, n, touching)
    assert stuck.sum() >= 1 and sliding.sum() >= 1
    assert check_tangent(block, state, history)
    check_friction(block, state, history, stuck=stuck, sliding=sliding)  # the moved surfaces'
    check_energy(block, state, history)


def test_bad_augmentation_options_are_refused():
    tool = RigidPlane((0.0, 0.0, 0.0), (0.0, 0.0, 1.0))
    with pytest.raises(ValueError, match="augmented must be True or False"):
        Contact(tool, augmented="yes")
    with pytest.raises(ValueError, match="without augmented=True"):
        Contact(tool, augmented_tolerance=1e-3)
    with pytest.raises(ValueError, match="augmented_tolerance must be a length > 0"):
        Contact(tool, augmented=True, augmented_tolerance=-1.0)
    with pytest.raises(ValueError, match="augmentations"):
        Static(augmentations=-1)
    with pytest.raises(ValueError, match="needs path='load'"):
        Static(path="arc_length", progress=False).solve(plate(True))


def test_a_contact_table_turns_the_augmented_lagrangian_on(tmp_path):
    """``augmented = true`` (and ``augmented_tolerance``) in a ``[[contact]]`` table: the
    contact of the Python option; a tolerance without it is refused, naming the key."""
    from fibreshell.case import CaseError, load_case
    from tests.test_case_files import CANTILEVER, CONTACT, write

    on = CONTACT.replace("friction = 0.2", "friction = 0.2\naugmented = true")
    case = load_case(write(tmp_path, CANTILEVER + on))
    assert case.model().interactions[-1].augmented
    given = on.replace("augmented = true", "augmented = true\naugmented_tolerance = 1e-4")
    block = load_case(write(tmp_path, CANTILEVER + given, "b.toml")).model().compile()
    assert block.interactions[-1].augmented_tolerance == 1e-4
    plain = load_case(write(tmp_path, CANTILEVER + CONTACT, "c.toml")).model()
    assert not plain.interactions[-1].augmented
    alone = CONTACT.replace("friction = 0.2", "friction = 0.2\naugmented_tolerance = 1e-4")
    with pytest.raises(CaseError, match=r"\[contact\[0\].augmented_tolerance\]"):
        load_case(write(tmp_path, CANTILEVER + alone, "d.toml"))


def plate_above_a_table(augmented: bool) -> Model:
    """The plate of ``plate`` at rest 1 mm above the table, unloaded: nothing to solve."""
    mesh = Mesh.rectangle(40.0, 40.0, nx=4, ny=4, origin=(0.0, 0.0, 0.5 * THICKNESS + 1.0))
    model = Model(mesh)
    model.add(MindlinShell(ElasticShell(E=1e4, nu=0.3, thickness=THICKNESS, density=1e-9)))
    model.fix(np.arange(mesh.n_nodes))
    model.contact(RigidPlane((0.0, 0.0, 0.0), (0.0, 0.0, 1.0)), augmented=augmented)
    return model


DYNAMIC = {
    "DynamicRelaxation": {"increments": 1},
    "CentralDifference": {"duration": 1e-6, "kinetic_bound": None},
}


@pytest.mark.parametrize("solver", list(DYNAMIC))
def test_a_dynamic_solver_says_it_runs_an_augmented_contact_as_its_penalty(solver):
    """Only Static updates the multipliers: the dynamic solvers run the plain penalty, and
    say so rather than let a user believe the penetration was removed."""
    make = getattr(solvers, solver)
    with pytest.warns(UserWarning, match="augmented contact .* as its plain penalty"):
        make(progress=False, **DYNAMIC[solver]).solve(plate_above_a_table(augmented=True))


@pytest.mark.parametrize("solver", list(DYNAMIC))
def test_a_dynamic_solver_is_silent_on_a_penalty_contact(solver, recwarn):
    make = getattr(solvers, solver)
    make(progress=False, **DYNAMIC[solver]).solve(plate_above_a_table(augmented=False))
    assert not [w for w in recwarn if "plain penalty" in str(w.message)]
