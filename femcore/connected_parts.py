"""The connected parts of a compiled model: the sets of body nodes that its element blocks and
its interactions between body nodes join, each of which moves as a rigid body of its own when
nothing holds it (two strips of a mesh left unmerged, a cable beside a shell it shares no
node with).

What is decidable at the start is the graph of the cells and of the interactions' node groups
(``connectivity``): a ply contact or a grip joins the nodes it couples whatever their gap, a
tool's contact joins nothing (it holds each of its nodes against the ground alone, along what
its ``held_directions`` say: femcore.diagnostics). A part is so a body that nothing at the start
ties to another; a part that leans on another through a contact that may open later is counted
as joined to it, which never calls a held part unheld."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components

if TYPE_CHECKING:
    from femcore.compiled import CompiledModel

__all__ = ["body_nodes", "connected_parts", "described_part"]

#: How many node numbers a message lists before it abbreviates.
LISTED_NODES = 10


def body_nodes(model: CompiledModel) -> np.ndarray:
    """(n,) bool: the nodes with DOFs that belong to the body (a force-driven tool's own node
    is another body)."""
    body = model.dofs.active[:, 0].copy()
    body[model.rigid_nodes] = False
    return body


def connected_parts(model: CompiledModel) -> list[np.ndarray]:
    """The connected parts of the model's body, largest first: each the (k,) int ids of its
    nodes, increasing. One (every body node) for a model in one piece.

    Two body nodes are joined when a row of an element block's ``connectivity`` holds both, or
    a row of an interaction's that acts between body nodes (``n_tools`` 0: a ply contact, a
    grip, a bending patch). A tool's own node joins nothing."""
    n = model.n_nodes
    body = body_nodes(model)
    groups = [np.asarray(block.connectivity, dtype=np.int64) for block in model.blocks]
    groups += [
        np.asarray(block.connectivity, dtype=np.int64)
        for block in model.interactions
        if int(block.n_tools) == 0
    ]
    heads, tails = [np.zeros(0, np.int64)], [np.zeros(0, np.int64)]
    for rows in groups:
        rows = rows.reshape(len(rows), -1)
        if rows.shape[1] < 2:
            continue
        # each node of a row joined to the row's first node: a star spans the row
        first = np.repeat(rows[:, :1], rows.shape[1] - 1, axis=1).ravel()
        others = rows[:, 1:].ravel()
        kept = (first >= 0) & (others >= 0)  # a padded row (-1) joins nothing
        heads.append(first[kept])
        tails.append(others[kept])
    head, tail = np.concatenate(heads), np.concatenate(tails)
    inside = body[head] & body[tail]
    graph = coo_matrix(
        (np.ones(int(inside.sum())), (head[inside], tail[inside])), shape=(n, n)
    ).tocsr()
    _, labels = connected_components(graph, directed=False)
    nodes = np.flatnonzero(body)
    _, counts = np.unique(labels[nodes], return_counts=True)
    order = np.argsort(-counts, kind="stable")
    # the body's nodes grouped by part (a stable sort keeps each part's ids increasing)
    grouped = nodes[np.argsort(labels[nodes], kind="stable")]
    ends = np.cumsum(counts)
    return [grouped[ends[i] - counts[i] : ends[i]] for i in order]


def described_part(nodes: np.ndarray, parts: int) -> str:
    """A part (its node ids (k,), increasing) in words for a message: its node count and its
    first node numbers (0-based, the mesh's order), e.g. "the part of 15 nodes 15, 16, ...,
    29 (...; one of 2 parts that no element or interaction joins)"."""
    if len(nodes) <= LISTED_NODES:
        listed = ", ".join(str(int(i)) for i in nodes)
    else:
        head = ", ".join(str(int(i)) for i in nodes[: LISTED_NODES - 1])
        listed = f"{head}, ..., {int(nodes[-1])}"
    return (
        f"the part of {len(nodes)} node{'s' if len(nodes) != 1 else ''} {listed} (0-based in "
        f"the mesh's order; one of {parts} parts that no element or interaction joins)"
    )
