"""The supports, prescribed motions and loads of a compiled model: their masks and nodal terms,
built once by femcore.compiled.CompiledModel, and the amplitudes evaluated at each load.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from typing import TYPE_CHECKING

import numpy as np

from femcore.dofs import DOF_NAMES, dof_names
from femcore.entry_error import EntryError
from femcore.frame_branches import tilt_columns
from femcore.loads import Amplitude, Fix, NodalLoad, Prescribed

if TYPE_CHECKING:
    from femcore.mesh import Mesh
    from femcore.model import BlockEntry

__all__ = ["evaluate", "fixed_mask", "load_terms", "moment_takers", "prescribed_terms"]


def fixed_mask(
    fixes: list[Fix], active: np.ndarray, directors: np.ndarray | None = None
) -> np.ndarray:
    """The (n, 5) mask of the DOFs the fixes hold, a fix's ``tilt`` resolved to alpha or beta
    at each node from the reference ``directors`` (n, 3) (femcore.frame_branches
    ``tilt_columns``); ValueError for a fix of a DOF no element gives its node."""
    fixed = np.zeros_like(active)
    for index, fix in enumerate(fixes):
        node_active = active[fix.nodes].any(axis=1)
        if not node_active.any():
            raise EntryError(
                "fix",
                index,
                f"fix selects nodes {fix.nodes[:5].tolist()}... that no element "
                "uses: they carry no DOF",
            )
        if fix.tilt is not None:
            turning, columns = tilt_columns(fix, index, active, directors)
            fixed[turning, columns] = True
        nodes = fix.nodes[node_active]
        if fix.columns is None:
            fixed[nodes] |= active[nodes]
            continue
        lacking = ~active[np.ix_(nodes, fix.columns)]
        if lacking.any():
            row, col = np.argwhere(lacking)[0]
            raise EntryError(
                "fix",
                index,
                f"cannot fix {DOF_NAMES[fix.columns[col]]} at node {nodes[row]}: it carries "
                f"only {', '.join(dof_names(active[nodes[row]]))}",
            )
        fixed[np.ix_(nodes, fix.columns)] = True
    return fixed


def prescribed_terms(
    records: list[Prescribed], active: np.ndarray, fixed: np.ndarray | None = None
) -> tuple[np.ndarray, list[tuple[Amplitude, np.ndarray]]]:
    """(the (n, 5) mask of the prescribed translations, one (amplitude, (n, 3) displacements
    in mm) per record); EntryError (a ValueError) naming the record for a node no element
    uses, a component prescribed twice, or one the ``fixed`` mask (n, 5) already holds."""
    mask = np.zeros_like(active)
    terms = []
    for index, record in enumerate(records):
        inactive = ~active[record.nodes, 0]
        if inactive.any():
            raise EntryError(
                "displacement",
                index,
                f"cannot displace node {record.nodes[inactive][0]}: no element uses it",
            )
        given = np.isfinite(record.values)
        already = mask[record.nodes, :3] & given
        if already.any():
            row, col = np.argwhere(already)[0]
            raise EntryError(
                "displacement",
                index,
                f"{DOF_NAMES[col]} of node {record.nodes[row]} is prescribed twice",
            )
        if fixed is not None and (clash := fixed[record.nodes, :3] & given).any():
            row, col = np.argwhere(clash)[0]
            raise EntryError(
                "displacement",
                index,
                f"DOF {DOF_NAMES[col]} of node {record.nodes[row]} is both fixed and "
                "prescribed: a DOF takes one boundary condition (leave the node out of the "
                "fix, or fix only the other DOFs)",
            )
        mask[record.nodes, :3] |= given
        values = np.zeros((len(active), 3))
        values[record.nodes] = np.where(given, record.values, 0.0)
        terms.append((record.amplitude, values))
    return mask, terms


def moment_takers(blocks: Sequence[BlockEntry], mesh: Mesh) -> tuple[np.ndarray, list[str]]:
    """((n,) bool: the nodes used by a block whose rotational DOFs take a nodal moment (a
    Mindlin shell: ``ElementType.takes_moments``), the names of the element types with
    rotational DOFs that take none (the fibrous shell, whose directors are material normals
    and whose bending is rotation-free: docs/theory.md §4.5))."""
    takes = np.zeros(mesh.n_nodes, dtype=bool)
    others: list[str] = []
    for entry in blocks:
        element = entry.element
        if "alpha" not in element.dofs:
            continue
        if element.takes_moments:
            takes[np.asarray(mesh.cells(element.cell_type)[entry.cells]).ravel()] = True
        elif type(element).__name__ not in others:
            others.append(type(element).__name__)
    return takes, others


def load_terms(
    records: list[NodalLoad],
    active: np.ndarray,
    takers: tuple[np.ndarray, list[str]] | None = None,
) -> list[tuple[str, Amplitude, np.ndarray]]:
    """One (kind, amplitude, (n, 3) vectors: N or N mm) per nodal load; EntryError (a
    ValueError) naming the load for one on a node without the DOFs it acts on, or a moment
    on nodes whose rotational DOFs take none (``takers``: ``moment_takers``)."""
    terms = []
    for index, record in enumerate(records):
        column = 0 if record.kind == "force" else 3
        lacking = ~active[record.nodes, column]
        if lacking.any():
            node = record.nodes[lacking][0]
            if record.kind == "force":
                # Every element gives its nodes translations: a node without is one no cell
                # of an element block uses (a mesh's cells restricted to one part).
                message = (
                    f"force on node {node}, which no element uses: it carries no DOF; "
                    "expected a node of a cell of an element block"
                )
            else:
                message = (
                    f"moment on node {node}, which has no rotational DOFs; expected a node of "
                    "an element with rotational DOFs"
                )
            raise EntryError("load", index, message)
        if record.kind == "moment" and takers is not None:
            refused = record.nodes[~takers[0][record.nodes]]
            if refused.size:
                raise EntryError("load", index, _no_moment(refused, takers[1]))
        values = np.zeros((len(active), 3))
        values[record.nodes] = record.vector
        terms.append((record.kind, record.amplitude, values))
    return terms


def _no_moment(nodes: np.ndarray, names: list[str]) -> str:
    """Why a moment on ``nodes`` is refused, and what to do instead."""
    listed = ", ".join(str(int(node)) for node in nodes[:5]) + (", ..." if nodes.size > 5 else "")
    return (
        f"a moment on {nodes.size} node(s) ({listed}) that only {' and '.join(names)} cells "
        "use: their rotational DOFs turn the directors (material normals: the layers' "
        "slip), not the mid-surface, whose bending is rotation-free (docs/theory.md §4.5), "
        "so a nodal moment there would not bend the shell. Apply a force couple instead "
        "(two opposite forces a lever arm apart), or make those cells a Mindlin part"
    )


def evaluate(amplitude: Amplitude, tau: float, quasi_static: bool) -> float:
    """a(tau), or ValueError naming the amplitude and where it failed: a user amplitude that
    returns NaN or raises would otherwise surface as a diverged step, far from its cause."""
    function: Callable = amplitude.quasi_static if quasi_static else amplitude.dynamic
    try:
        value = float(function(tau))
    except Exception as exc:  # the user's function: report what it did and where
        what, where = amplitude_named(amplitude, function, tau, quasi_static)
        raise ValueError(f"the {what} failed at {where}: {exc}") from exc
    if not math.isfinite(value):
        what, where = amplitude_named(amplitude, function, tau, quasi_static)
        raise ValueError(
            f"the {what} returned {value!r} at {where}: an amplitude must return a finite "
            "number at every time and load factor"
        )
    return value


def amplitude_named(
    amplitude: Amplitude, function: Callable, tau: float, quasi_static: bool
) -> tuple[str, str]:
    """("amplitude 'user' (ramp)", "load factor 0.5") for a message: built only on failure,
    since amplitudes are evaluated at every step."""
    what = f"amplitude {amplitude.name!r}"
    if amplitude.name == "user":
        what += f" ({getattr(function, '__name__', repr(function))})"
    where = f"load factor {tau:.6g}" if quasi_static else f"tau = t / duration = {tau:.6g}"
    return what, where
