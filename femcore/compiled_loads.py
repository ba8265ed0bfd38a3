"""The supports, prescribed motions and loads of a compiled model: their masks and nodal terms,
built once by femcore.compiled.CompiledModel, and the amplitudes evaluated at each load.
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np

from femcore.dofs import DOF_NAMES, dof_names
from femcore.loads import Amplitude, Fix, NodalLoad, Prescribed

__all__ = ["evaluate", "fixed_mask", "load_terms", "prescribed_terms"]


def fixed_mask(fixes: list[Fix], active: np.ndarray) -> np.ndarray:
    """The (n, 5) mask of the DOFs the fixes hold; ValueError for a fix of a DOF no element
    gives its node."""
    fixed = np.zeros_like(active)
    for fix in fixes:
        node_active = active[fix.nodes].any(axis=1)
        if not node_active.any():
            raise ValueError(
                f"fix selects nodes {fix.nodes[:5].tolist()}... that no element "
                "uses: they carry no DOF"
            )
        nodes = fix.nodes[node_active]
        if fix.columns is None:
            fixed[nodes] |= active[nodes]
            continue
        lacking = ~active[np.ix_(nodes, fix.columns)]
        if lacking.any():
            row, col = np.argwhere(lacking)[0]
            raise ValueError(
                f"cannot fix {DOF_NAMES[fix.columns[col]]} at node {nodes[row]}: it carries "
                f"only {', '.join(dof_names(active[nodes[row]]))}"
            )
        fixed[np.ix_(nodes, fix.columns)] = True
    return fixed


def prescribed_terms(
    records: list[Prescribed], active: np.ndarray
) -> tuple[np.ndarray, list[tuple[Amplitude, np.ndarray]]]:
    """(the (n, 5) mask of the prescribed translations, one (amplitude, (n, 3) displacements
    in mm) per record); ValueError for a node no element uses or a component prescribed
    twice."""
    mask = np.zeros_like(active)
    terms = []
    for record in records:
        inactive = ~active[record.nodes, 0]
        if inactive.any():
            raise ValueError(
                f"cannot displace node {record.nodes[inactive][0]}: no element uses it"
            )
        given = np.isfinite(record.values)
        already = mask[record.nodes, :3] & given
        if already.any():
            row, col = np.argwhere(already)[0]
            raise ValueError(f"{DOF_NAMES[col]} of node {record.nodes[row]} is prescribed twice")
        mask[record.nodes, :3] |= given
        values = np.zeros((len(active), 3))
        values[record.nodes] = np.where(given, record.values, 0.0)
        terms.append((record.amplitude, values))
    return mask, terms


def load_terms(
    records: list[NodalLoad], active: np.ndarray
) -> list[tuple[str, Amplitude, np.ndarray]]:
    """One (kind, amplitude, (n, 3) vectors: N or N mm) per nodal load; ValueError for a load
    on a node without the DOFs it acts on."""
    terms = []
    for record in records:
        column = 0 if record.kind == "force" else 3
        lacking = ~active[record.nodes, column]
        if lacking.any():
            node = record.nodes[lacking][0]
            if record.kind == "force":
                # Every element gives its nodes translations: a node without is one no cell
                # of an element block uses (a mesh's cells restricted to one part).
                raise ValueError(
                    f"force on node {node}, which no element uses: it carries no DOF; "
                    "expected a node of a cell of an element block"
                )
            raise ValueError(
                f"moment on node {node}, which has no rotational DOFs; expected a node of "
                "an element with rotational DOFs"
            )
        values = np.zeros((len(active), 3))
        values[record.nodes] = record.vector
        terms.append((record.kind, record.amplitude, values))
    return terms


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
