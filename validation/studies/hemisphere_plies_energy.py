"""The two-ply hemisphere's kinetic energy split between the plies and the blank holder
(validation/studies/hemisphere_plies.py, "Whose kinetic energy"): the run's KE / W check
counts every mass of the model, the holder's rigid node among them, so a holder thrown up by
the flange fails it while the plies themselves move slowly. ``kinetic_shares`` says which.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from elements.layup import Layup

__all__ = ["kinetic_shares", "ply_masses"]


def ply_masses(layup: Layup) -> np.ndarray:
    """(n,) the plies' lumped nodal masses, t: a third of each cell's rho_A A0 at each corner
    (the lumped mass of both kinematics, docs/theory.md §1.6), the reference areas A0 of the
    layup's mesh."""
    points, triangles = layup.mesh.points, layup.mesh.triangles
    edges = points[triangles[:, 1:]] - points[triangles[:, :1]]
    area = 0.5 * np.linalg.norm(np.cross(edges[:, 0], edges[:, 1]), axis=1)
    share = np.repeat(layup.fabric.areal_density * area / 3.0, 3)
    return np.bincount(triangles.ravel(), weights=share, minlength=layup.mesh.n_nodes)


def kinetic_shares(
    layup: Layup, result: Any, holder_mass: float, holder: int = 0
) -> dict[str, np.ndarray]:
    """The translational kinetic energies of each ply and of the holder at each frame.

    Parameters
    ----------
    layup : Layup
        The layup (its mesh's nodes first in the model, the tools' rigid nodes after them).
    result : femcore.results.Result
        The run's frames (``velocities`` (N, 3), mm/s, N >= the mesh's nodes).
    holder_mass : float
        The holder's mass, t.
    holder : int
        The holder's index among the model's rigid nodes (0: the first force-driven tool).

    Returns
    -------
    dict
        "time" (f,) s; "plies" (f, plies) N mm, 1/2 sum m v^2 over each ply's nodes (the
        directors' rotary part left out); "holder" (f,) N mm, 1/2 m_h v_h^2.
    """
    mass = ply_masses(layup)
    n = layup.mesh.n_nodes
    times, plies, lifted = [], [], []
    for frame in result.frames:
        v = np.asarray(frame.velocities)
        energy = 0.5 * mass * np.sum(v[:n] ** 2, axis=1)
        plies.append([float(energy[nodes].sum()) for nodes in layup.ply_nodes])
        lifted.append(0.5 * holder_mass * float(np.sum(v[n + holder] ** 2)))
        times.append(frame.time)
    return {"time": np.array(times), "plies": np.array(plies), "holder": np.array(lifted)}
