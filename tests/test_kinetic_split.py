"""The explicit solver's kinetic energy split: ``result.energies["kinetic_rotational"]`` is
the directors' part of ``result.energies["kinetic"]`` (docs/theory.md §6.3), the rest the
nodes' translations."""

from __future__ import annotations

import numpy as np
import pytest

from elements import MindlinShell
from femcore import Mesh, Model
from materials import ElasticShell
from solvers import CentralDifference

DENSITY, THICKNESS = 1e-9, 2.0  # t/mm^3, mm


def test_the_kinetic_energy_is_the_translations_and_the_rotational_record():
    """A 40 x 30 mm Mindlin plate clamped along x = 0 and swung by a step moment about y at
    x = 40: at the last record (every step is one in this short run, the last at the final
    frame) the kinetic energy less its rotational record is 1/2 sum m |v|^2 over the final
    frame's velocities, m the closed-form lumped mass rho h A / 3 at each corner of each
    triangle (docs/theory.md §1.6), to round-off (1e-12 relative: sums of some tens of
    positive terms). The directors' share is not small here (a plate bent by end moments
    turns its directors with the surface), so a record of zero would fail."""
    mesh = Mesh.rectangle(40.0, 30.0, nx=4, ny=3)
    model = Model(mesh)
    model.add(MindlinShell(ElasticShell(1000.0, 0.3, THICKNESS, DENSITY)))
    model.fix("left")
    model.moment("right", (0.0, 50.0, 0.0))
    result = CentralDifference(duration=2e-4, progress=False, output_interval=1e-4).solve(model)
    energies = result.energies
    assert result.steps < 4000  # one record per step: the last is the final frame's
    assert energies["time"][-1] == pytest.approx(result.frames[-1].time, rel=1e-12)
    corners = mesh.points[mesh.triangles]
    area = 0.5 * np.linalg.norm(
        np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0]), axis=1
    )
    mass = np.bincount(
        mesh.triangles.ravel(), np.repeat(DENSITY * THICKNESS * area / 3.0, 3), mesh.n_nodes
    )
    velocities = result.frames[-1].velocities[: mesh.n_nodes]
    translation = 0.5 * float(np.sum(mass * np.sum(velocities**2, axis=1)))
    rotation = energies["kinetic_rotational"][-1]
    assert energies["kinetic"][-1] - rotation == pytest.approx(translation, rel=1e-12)
    assert rotation > 0.01 * energies["kinetic"][-1]
    assert len(energies["kinetic_rotational"]) == len(energies["kinetic"])
    assert energies["kinetic_rotational"][0] == 0.0  # at rest


def test_an_account_restored_without_the_rotational_record_gets_zeros_before_it():
    """An energy account from a checkpoint written before the rotational record was kept
    (its ``records`` without the key) gives zeros for its earlier records, then the values:
    the record lists stay as long as the others."""
    from solvers.dynamics import EnergyAccount

    account = EnergyAccount(thin=1)
    account.record(1, 1e-3)
    del account.records[EnergyAccount.ROTATIONAL]  # as restored from the older checkpoint
    account.record(2, 2e-3, lambda: 0.5)
    account.record(3, 3e-3, lambda: 0.25)
    assert account.records[EnergyAccount.ROTATIONAL] == [0.0, 0.0, 0.5, 0.25]
    assert all(len(values) == 4 for values in account.records.values())
