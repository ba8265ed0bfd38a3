"""State: everything that changes during a solve, kept apart from the fixed Model."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["State"]


@dataclass
class State:
    """Configuration and rates at one instant.

    positions : (n, 3) float, current nodal coordinates (length unit of the mesh, e.g. mm).
    directors : (n, 3) float, unit material directors at nodes with rotational DOFs; zero rows
        at nodes without a director (cable nodes).
    velocities : (n, 3) float, nodal velocities (mm/s).
    angular_velocities : (n, 3) float, nodal angular-velocity vectors, perpendicular to the
        director (rad/s; docs/theory.md §1.3 stores omega as a vector so that a change of nodal
        frame
        between steps is harmless).
    time : float, s (explicit dynamics) or the pseudo-time of a quasi-static solve.
    load_factor : float, the fraction of the loads applied (1 at the end of the step).
    history : tuple, one entry per part of the compiled model, the element blocks then the
        interactions (``history[i]`` belongs to ``CompiledModel.parts[i]``; None for a part
        without history variables). Entries are never mutated: a part's ``update_history``
        returns a new one, and the solver makes a new State with it
        (femcore.compiled.CompiledModel.commit).
    """

    positions: np.ndarray
    directors: np.ndarray
    velocities: np.ndarray
    angular_velocities: np.ndarray
    time: float = 0.0
    load_factor: float = 0.0
    history: tuple = ()

    @property
    def n_nodes(self) -> int:
        return self.positions.shape[0]

    def copy(self) -> State:
        """A deep copy (arrays copied), for keeping a last good state."""
        return State(
            self.positions.copy(),
            self.directors.copy(),
            self.velocities.copy(),
            self.angular_velocities.copy(),
            self.time,
            self.load_factor,
            self.history,  # entries are immutable by contract: shared, not copied
        )
