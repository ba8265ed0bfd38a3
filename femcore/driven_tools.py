"""The force-driven tools of a compiled model (a blank holder: elements/tools.py,
docs/theory.md §9.5): for each node carrying a tool's free translation, the tool rows it drives
(``CompiledModel.tool_forces`` order), its free axes, the force the tools press the body with
and the force prescribed on the node, so that a solver can set one beside the other.

A tool node's equation is m c'' = F(t) - sum_i f_i (+ m g): the prescribed force reaches the
body only where the tool's inertia and damping are small; the contact force sum_i f_i is what
the body feels.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np

from femcore.compiled_loads import evaluate

__all__ = ["DrivenTools"]


class DrivenTools:
    """The nodes of force-driven tools and what acts on them.

    Parameters
    ----------
    interactions : the compiled model's interaction blocks (``tool_nodes``: the node of each
        tool row, -1 for a tool without one).
    free : (n, 3) bool, the model's free translations.
    load_terms : the model's nodal loads, (kind, amplitude, (n, 3) vectors).
    gravity : (amplitude, (n, 3) nodal weights, N) of each gravity.

    Attributes
    ----------
    nodes : (k,) int, the tool nodes, each once, in the order of their first tool row.
    free : (k, 3) bool, the axes each is free along (its driven axes).
    rows : the tool rows (0-based, ``tool_forces`` order) each node drives, k tuples.
    """

    def __init__(
        self,
        interactions: Sequence[Any],
        free: np.ndarray,
        load_terms: Sequence[tuple[str, Any, np.ndarray]],
        gravity: Sequence[tuple[Any, np.ndarray]],
    ):
        owners = []  # (interaction index, row within it, global row, node)
        row = 0
        for index, interaction in enumerate(interactions):
            nodes = np.asarray(interaction.tool_nodes(), dtype=np.int64).reshape(-1)
            for within, node in enumerate(nodes):
                if node >= 0:
                    owners.append((index, within, row + within, int(node)))
            row += int(interaction.n_tools)
        self.nodes = np.array(list(dict.fromkeys(o[3] for o in owners)), dtype=np.int64)
        self.rows = tuple(tuple(o[2] for o in owners if o[3] == node) for node in self.nodes)
        self.free = np.asarray(free[self.nodes], dtype=bool).reshape(-1, 3)
        # (interaction index, row within, which node) per driven row: only these blocks are
        # asked for their tool forces (a step asks them every step)
        where = {int(node): k for k, node in enumerate(self.nodes)}
        self._owners = tuple((o[0], o[1], where[o[3]]) for o in owners)
        self._loads = [
            (amplitude, values[self.nodes]) for kind, amplitude, values in load_terms
            if kind == "force"
        ]  # fmt: skip
        self._loads += [(amplitude, weight[self.nodes]) for amplitude, weight in gravity]

    def __len__(self) -> int:
        return len(self.nodes)

    def interaction_of(self, k: int) -> int:
        """The index (in the model's interactions) of the first interaction whose tool node
        is node ``k`` of ``nodes``: the entry a message about that tool names."""
        return next(index for index, _, node in self._owners if node == k)

    def names(self) -> list[str]:
        """Each node's tools as ``summary.json`` and the history name them: "tool2", or
        "tool2+tool3" for a tool node two contacts share."""
        return ["+".join(f"tool{r + 1}" for r in rows) for rows in self.rows]

    def pushes(self, interactions: Sequence[Any], histories: Sequence[Any], state) -> np.ndarray:
        """(k, 3) the force (N) each node's tools press the body with (minus the force the
        body exerts on them, ``tool_forces``), summed over its contacts."""
        push = np.zeros((len(self.nodes), 3))
        for index, within, node in self._owners:
            force = interactions[index].tool_forces(state, histories[index])
            push[node] -= np.asarray(force, dtype=float).reshape(-1, 3)[within]
        return push

    def loads(self, tau: float) -> np.ndarray:
        """(k, 3) the force (N) prescribed on each node at ``tau`` (t / duration): its
        nodal loads (a tool's ``force`` or pressure) and its weight, the amplitudes' dynamic
        form (the explicit step's)."""
        load = np.zeros((len(self.nodes), 3))
        for amplitude, values in self._loads:
            load += evaluate(amplitude, tau, False) * values
        return load
