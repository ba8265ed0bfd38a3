"""The explicit run's energy records (solvers/dynamics.py ``EnergyAccount``, docs/theory.md
§6.1 "The energy records"): "internal" is the energy the model stores, the internal forces'
work less the interactions' dissipation in "friction", so that kinetic + internal + damping +
friction = external_work, each dissipation counted once (an identity of the definitions: the
tests hold the records to the physics, Coulomb's dissipation and the stored strain energy)."""

from __future__ import annotations

import numpy as np
import pytest

from elements import MindlinShell
from elements.layup import Layup
from elements.tools import RigidPlane
from femcore import Mesh, Model
from materials import ElasticShell, Fabric
from solvers import CentralDifference
from solvers.dynamics import EnergyAccount

G = 9810.0  # mm/s^2
MU = 0.3
SETTLED = 0.2  # the share of the run over which gravity is brought on
PULL_START, PULL_RAMP = 0.25, 0.1  # the pull starts at 0.25 of the run, at full speed at 0.35


def _settle(tau):
    """Gravity brought on smoothly over the first SETTLED of the run (the plate does not
    bounce on the table), then held."""
    s = np.clip(np.asarray(tau, dtype=float) / SETTLED, 0.0, 1.0)
    return s * s * s * (10.0 - 15.0 * s + 6.0 * s * s)


def _steady_pull(tau):
    """0 until PULL_START, the speed ramped up over PULL_RAMP, then constant to 1 at the end:
    a steady pace over most of the drag."""
    u = np.clip(np.asarray(tau, dtype=float) - PULL_START, 0.0, None)
    travelled = np.where(u < PULL_RAMP, u * u / (2.0 * PULL_RAMP), 0.5 * PULL_RAMP + u - PULL_RAMP)
    return travelled / (0.5 * PULL_RAMP + 1.0 - PULL_START - PULL_RAMP)


def test_a_plate_dragged_over_a_table_dissipates_mu_n_d_and_stores_its_strain_energy():
    """A 20 x 20 x 1 mm aluminium plate (2 x 2 cells) on a flat rigid table with Coulomb
    friction mu = 0.3 under its weight N = m g, dragged 0.1 mm by one edge at a steady pace:
    Coulomb's law gives the dissipation mu N d (the kinetic friction force mu N over the
    sliding distance d, the plate's mean travel; measured 4e-5, asserted 1e-3: the normal
    force rings a little about m g). The internal record is the strain energy the final
    state holds (elements and contact springs), to 1e-4 of the dissipation (measured 7e-6:
    the stick anchors' springs, which a fresh history leaves out, and the half step between
    the work and the state); before, it held the dissipation too and was off by all of it."""
    thickness = 1.0
    flat = Mesh.rectangle(20.0, 20.0, nx=2, ny=2)
    model = Model(flat.with_points(flat.points + [0.0, 0.0, 0.5 * thickness]))
    model.add(MindlinShell(ElasticShell(E=70e3, nu=0.3, thickness=thickness, density=2.7e-9)))
    model.contact(RigidPlane((0.0, 0.0, 0.0), (0.0, 0.0, 1.0)), friction=MU)
    model.gravity((0.0, 0.0, -G), amplitude=_settle)
    model.displace("left", ux=0.1, amplitude=_steady_pull)
    compiled = model.compile()
    duration = 0.004
    run = CentralDifference(duration=duration, kinetic_bound=None, progress=False).solve(compiled)
    assert run.converged
    e = {key: np.asarray(values) for key, values in run.energies.items()}
    last = {key: float(values[-1]) for key, values in e.items()}
    weight = compiled.mass0.sum() * G
    travel = float(run.displacements[:, 0].mean())
    assert travel == pytest.approx(0.1, rel=1e-3)  # the plate slid as a whole
    assert last["friction"] == pytest.approx(MU * weight * travel, rel=1e-3)
    final = compiled.initial_state()
    final.positions, final.directors = run.positions, run.frames[-1].directors
    final.load_factor = 1.0
    strain = compiled.strain_energy(final)
    assert abs(last["internal"] - strain) <= 1e-4 * last["friction"]


PLY = Fabric(thickness=0.3, areal_density=2.85e-10, tension=60.0, shear=0.2, bending=0.375)


def test_plies_sliding_on_each_other_without_a_tool_record_their_friction():
    """Two plies (no rigid tool), the lower one held, the upper one pressed onto it by
    gravity (100 g, to press it) and pulled 0.5 mm along x: the friction record is the ply
    contact's dissipation, Coulomb's mu N d (measured 1.1 % below it, asserted 3 %: the
    stick spring follows the normal law's stiffness, so a lightly pressed point slips
    elastically first; it stayed 0 without a tool before, while the internal record held
    it)."""
    layup = Layup(PLY, (0.0, 90.0), 20.0, cells=2, friction=MU)
    model = layup.model()
    bottom, top = layup.ply_nodes
    model.fix(bottom)
    model.gravity((0.0, 0.0, -100.0 * G), amplitude=_settle)
    left = top[layup.mesh.points[top, 0] <= layup.mesh.points[top, 0].min() + 1e-9]
    model.displace(left, ux=0.5, amplitude=_steady_pull)
    compiled = model.compile()
    assert compiled.n_tools == 0
    run = CentralDifference(duration=0.002, kinetic_bound=None, progress=False).solve(compiled)
    assert run.converged
    e = {key: np.asarray(values) for key, values in run.energies.items()}
    pressed = compiled.mass0[top].sum() * 100.0 * G
    travel = float(run.displacements[top, 0].mean())
    assert e["friction"][-1] == pytest.approx(MU * pressed * travel, rel=0.03)


def test_the_friction_record_is_at_the_half_step_as_the_works_beside_it():
    """The works are midpoint sums to t(i+1/2); the dissipation is known at the states t(i+1):
    the record is the mean of the last two (the midpoint rule's value at t(i+1/2)), so that
    "internal" = W_int - D_f subtracts the dissipation at the time the work reached."""
    account = EnergyAccount(thin=1)
    account.dissipate(2.0)  # D_f(t1) = 2, from D_f(t0) = 0
    assert account.friction == 1.0
    account.dissipate(6.0)
    assert account.friction == 4.0
    account.internal = 10.0
    assert account.stored == 6.0
