"""The last exact tangent of a Static solve, kept with the configuration it was assembled at
(docs/theory.md §6.5, "The stability of a converged state"), so that a tangent asked for again
at the same configuration is not assembled and factorised twice.

Where it pays: the stability of every converged state is read from the inertia of its own
tangent (``StaticRun.factor_at``), assembled and factorised after Newton's last update, and
the next increment's first Newton iteration starts from that very state (without a predictor)
and asks for the same tangent: the 2560-triangle Mindlin cantilever of
benchmarks/kratos_cantilever.py assembled 28 tangents and made 33 factorisations in its 5
increments, 4 of each twice over.

The tangent (K_ff, K_fp) of the element blocks is a function of the positions, the directors,
the nodal frames it is written in and the blocks' history; a viscous stabilisation adds its
increment's dashpots. The kept one is given back only where all of these are the same: the
arrays compared by value (a State's arrays may be changed in place), the history entry by
entry by identity (entries are never mutated, femcore.state.State; a block whose history a
commit renews, the fibrous shell's folds, is never given a kept tangent), and never with
dashpots. A model with interactions keeps nothing: their tangent depends on more than the
state (the tools a load factor places, and penalties that the load path changes in place
between attempts: the soft start of solvers/penalty_start.py gave the ply deck of
tests/test_static_penalty_start.py its softened tangent again at full penalty, and it stopped
at load factor 0.98). A compression-free tangent (solvers.newton, ``Tangent``) is not the
state's own and is neither kept nor given.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from femcore.dofs import Frames
from femcore.model import CompiledModel
from femcore.state import State

__all__ = ["REUSE", "KeptTangent"]

#: Whether a kept tangent is given again (False: every tangent assembled and factorised, the
#: solver before; benchmarks/kratos_cantilever.py's reference pass).
REUSE = True


class KeptTangent:
    """The last exact (K_ff, K_fp) assembled by a Static solve and where it was made (module
    docstring): ``keep`` after each exact assembly, ``at`` before the next."""

    def __init__(self, model: CompiledModel) -> None:
        self._never = bool(model.interactions)  # module docstring
        # (positions (n, 3) mm, directors (n, 3), the frames (V1, V2) or None, history, load
        # factor: not compared, the element blocks' tangent does not depend on it)
        self._where: tuple[np.ndarray, np.ndarray, Frames, tuple, float] | None = None
        self._matrices: tuple[Any, Any] | None = None

    def keep(self, state: State, frames: Frames, k_ff, k_fp, dashpots: object = None) -> None:
        """Keep (K_ff, K_fp), assembled exactly at ``state`` in ``frames`` ((V1, V2), each
        (n, 3), or None without directors); nothing is kept with ``dashpots`` (an
        increment's own diagonal is in K_ff)."""
        if dashpots is not None or self._never:
            self.forget()
            return
        self._where = (
            state.positions.copy(),
            state.directors.copy(),
            None if frames is None else (frames[0].copy(), frames[1].copy()),
            state.history,
            state.load_factor,
        )
        self._matrices = (k_ff, k_fp)

    def forget(self) -> None:
        """Keep nothing."""
        self._where, self._matrices = None, None

    def at(self, state: State, frames: Frames, dashpots: object = None) -> tuple[Any, Any] | None:
        """The kept (K_ff, K_fp) where it was assembled at this very configuration (module
        docstring), else None."""
        if not REUSE or self._where is None or self._matrices is None or dashpots is not None:
            return None
        positions, directors, kept_frames, history, _ = self._where
        if len(history) != len(state.history):
            return None
        if any(kept is not now for kept, now in zip(history, state.history)):
            return None
        if (kept_frames is None) != (frames is None):
            return None
        same = np.array_equal(positions, state.positions) and np.array_equal(
            directors, state.directors
        )
        if same and kept_frames is not None and frames is not None:
            same = np.array_equal(kept_frames[0], frames[0]) and np.array_equal(
                kept_frames[1], frames[1]
            )
        return self._matrices if same else None
