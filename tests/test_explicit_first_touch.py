"""The explicit energy balance at a contact's first touch (docs/theory.md §6.1, "First
touch"): a tool moving at v onto a body at rest has its work counted over the half step before
the checked state, (1 - sigma) of it before its spring engaged, a deficit of 1/2 k (v dt)^2
sigma (1 - sigma) per touching node that the check does not count."""

from __future__ import annotations

import numpy as np
import pytest

from elements import MindlinShell, RigidPlane
from femcore import Mesh, Model
from materials import ElasticShell
from solvers.dynamics import EnergyAccount
from solvers.step import LumpedMasses, explicit_step

PENALTY = 1.0e3  # N/mm per node
DT = 1.0e-7  # s: within the penalty's 2 sqrt(m / k) = 3.3e-5 s and the cell's L / c = 4e-6 s
DURATION = 1.0e-3  # s
LIFT = 0.1  # mm over DURATION, "linear": v = 100 mm/s, v dt = 1e-5 mm


@pytest.mark.parametrize("sigma", [0.1, 0.3, 0.5, 0.9])
def test_a_plane_reaching_a_plate_at_rest_leaves_the_closed_form_deficit(sigma):
    """A 1-mm plate (one square cell, 4 nodes, no load) at rest above a plane that rises at
    v = 100 mm/s; the gap is set so that the plane reaches it a share sigma of the step before
    t(4). At t(4) the nodes have not moved (KE* = 0), each spring holds U = 1/2 k (sigma v
    dt)^2, and the tool's work counted is k sigma v dt x v dt / 2 per node: the balance is
    short by 4 x 1/2 k (v dt)^2 sigma (1 - sigma) (closed form, to round-off: 1e-9), 1 - sigma
    of the largest energy whatever dt is; with the tool's work over [t(4) - dt/2, t(4)] given
    as ``onset`` the check counts none of it."""
    touch_step = 4
    advance = LIFT / DURATION * DT
    gap = (touch_step - sigma) * advance
    flat = Mesh.rectangle(20.0, 20.0, nx=1, ny=1)
    model = Model(flat.with_points(flat.points + [0.0, 0.0, 0.5 + gap]))
    model.add(MindlinShell(ElasticShell(E=70e3, nu=0.3, thickness=1.0, density=2.7e-9)))
    model.contact(
        RigidPlane((0, 0, 0), (0, 0, 1), motion=(0, 0, LIFT), amplitude="linear"),
        penalty=PENALTY,
    )
    compiled = model.compile()
    state = compiled.initial_state()
    masses = LumpedMasses.of(compiled, state)
    account = EnergyAccount(thin=1)
    previous = 0.0
    for step in range(touch_step + 1):
        checking = step == touch_step
        outcome = explicit_step(
            compiled, state, DT, masses, dt_prev=previous, duration=DURATION, checking=checking
        )
        account.accept(*outcome.energy)
        if checking:
            break
        state, previous = compiled.commit(outcome.state), DT
    assert outcome.strain_energy is not None
    deficit = 4 * 0.5 * PENALTY * advance**2 * sigma * (1.0 - sigma)
    balance, _ = account.check(outcome.energy, outcome.strain_energy)
    assert balance * account.largest == pytest.approx(deficit, rel=1e-9)
    assert balance == pytest.approx(1.0 - sigma, rel=1e-9)
    tau = state.time / DURATION
    onset = compiled.tool_work(state, tau - 0.5 * DT / DURATION, tau)
    assert onset == pytest.approx(deficit / (1.0 - sigma), rel=1e-9)
    assert account.check(outcome.energy, outcome.strain_energy, 0.0, onset)[0] == 0.0


def test_an_energy_excess_is_judged_whatever_the_tools_work():
    """The onset's allowance covers a deficit only: the same terms with 1 N mm more strain
    energy than work show the excess in full."""
    account = EnergyAccount(thin=1)
    work = (0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 2.0, 0.0)  # 2 N mm of external work before t(i)
    account.accept(*work)
    balance, _ = account.check(work, 3.0, 0.0, onset=2.0)
    assert balance == pytest.approx(1.0 / 3.0)
    assert np.isclose(account.check(work, 1.0, 0.0, onset=2.0)[0], 0.0)
