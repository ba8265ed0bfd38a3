"""The conformance checks of the capabilities a block declares through its protocol
(femcore/element.py ``ElementBlock``, femcore/interaction.py ``InteractionBlock``): the
members the solvers call beyond forces, energies and tangents (a compression-free tangent,
fibre edges and strains, friction, active sets, a soft start, a meshed tool's facets).

Each member has a default on the protocol's base class, the behaviour the solvers assume of a
block that lacks the capability; a block that declares one (sets the attribute, overrides the
method) is held here to the member's type and to what the solvers do with it, and a member
overridden while its declaration says the solvers never ask for it is named too (a dead
override hides a missing declaration). ``check_element_capabilities`` runs in the element kit
(femcore.testing ``element_checks``), ``check_interaction_capabilities`` in the interaction
kit (femcore.interaction_checks ``check_interaction``).
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np

from femcore.assembly import CellTangent, SparseTangent
from femcore.element import ElementBlock, are_node_pairs
from femcore.interaction import OPENING_LAWS, FacetRecord, InteractionBlock, is_friction
from femcore.state import State

__all__ = [
    "FIBRE_STRAIN_ROUND_OFF",
    "check_element_capabilities",
    "check_interaction_capabilities",
    "overrides",
]

#: The fibre strains of the reference state, which is unstrained by definition: a sum of a few
#: products of reference edges (round-off, seen 1e-16; the strains are dimensionless).
FIBRE_STRAIN_ROUND_OFF = 1e-12
#: The softened penalty's share the check asks for: any in (0, 1) (solvers/penalty_start.py).
SOFT_SHARE = 0.25


def overrides(block: object, name: str, base: type) -> bool:
    """Whether ``block``'s class gives its own ``name`` instead of the protocol ``base``'s."""
    return getattr(type(block), name) is not getattr(base, name)


def _flag(block: object, name: str) -> bool:
    value = getattr(block, name)
    if not isinstance(value, (bool, np.bool_)):
        raise AssertionError(
            f"{type(block).__name__}.{name} is {value!r}: True or False expected "
            "(a capability the solvers test)"
        )
    return bool(value)


def _is_parts(parts: Any) -> bool:
    return isinstance(parts, Sequence) and all(
        isinstance(p, (CellTangent, SparseTangent)) for p in parts
    )


# ---------------------------------------------------------------------- elements
def check_element_capabilities(
    block: ElementBlock, reference: State, deformed: State, history: Any = None
) -> None:
    """The element capabilities ``block`` declares, at the model's ``reference`` state and a
    ``deformed`` one (``history``: the block's entry of the state's history):

    * ``compression_free_tangent`` a bool; True: ``tangent_compression_free`` its own,
      tangent parts at ``deformed``; False: the default (the solvers never ask for it);
    * ``has_fibre_strains`` a bool; True: ``fibre_strains`` its own, (m, p) finite floats
      with p >= 1 for its m cells, zero in the reference (to FIBRE_STRAIN_ROUND_OFF: it is
      unstrained), ``fibre_strain_gradient`` a tuple and ``fibre_strain_range()`` a
      (lower, upper) pair of (p,) floats, lower < 0 < upper; False: none overridden;
    * ``fibre_edges()`` (k, 2) integer pairs of two distinct nodes of the block's cells.

    Raises
    ------
    AssertionError
        Naming the member and what was wrong.
    """
    name = type(block).__name__
    if _flag(block, "compression_free_tangent"):
        if not overrides(block, "tangent_compression_free", ElementBlock):
            raise AssertionError(
                f"{name} declares compression_free_tangent without its own tangent_compression_free"
            )
        parts = block.tangent_compression_free(deformed, history)
        if not _is_parts(parts):
            raise AssertionError(
                f"{name}.tangent_compression_free gave {type(parts).__name__}: a sequence of "
                "CellTangent or SparseTangent parts expected"
            )
    elif overrides(block, "tangent_compression_free", ElementBlock):
        raise AssertionError(
            f"{name} gives tangent_compression_free with compression_free_tangent False: "
            "the static solver never asks for it"
        )
    gives = ("fibre_strains", "fibre_strain_gradient", "fibre_strain_range")
    own = [overrides(block, member, ElementBlock) for member in gives]
    if _flag(block, "has_fibre_strains"):
        if not all(own):
            raise AssertionError(
                f"{name} declares has_fibre_strains without its own fibre_strains, "
                "fibre_strain_gradient and fibre_strain_range"
            )
        strains = np.asarray(block.fibre_strains(reference))
        m = len(block.connectivity)
        if strains.ndim != 2 or strains.shape[0] != m or strains.shape[1] < 1:
            raise AssertionError(
                f"{name}.fibre_strains gave shape {strains.shape}: (m, p) expected, m = {m} "
                "cells, p >= 1"
            )
        largest = float(np.max(np.abs(strains)))
        if strains.dtype.kind != "f" or not largest <= FIBRE_STRAIN_ROUND_OFF:
            raise AssertionError(
                f"{name}.fibre_strains of the reference state reach {largest!r}: the reference "
                f"is unstrained (zero to {FIBRE_STRAIN_ROUND_OFF}, round-off)"
            )
        if not np.isfinite(np.asarray(block.fibre_strains(deformed))).all():
            raise AssertionError(f"{name}.fibre_strains of the deformed state are not finite")
        _check_strain_range(name, block.fibre_strain_range(), strains.shape)
        gradient = block.fibre_strain_gradient(deformed)
        if not isinstance(gradient, tuple):
            raise AssertionError(
                f"{name}.fibre_strain_gradient gave {type(gradient).__name__}: a tuple expected"
            )
    elif any(own):
        raise AssertionError(
            f"{name} gives fibre_strains, fibre_strain_gradient or fibre_strain_range with "
            "has_fibre_strains "
            "False: the static solver never asks for them"
        )
    edges = block.fibre_edges()
    nodes = np.unique(block.connectivity)
    if not are_node_pairs(edges):
        raise AssertionError(f"{name}.fibre_edges() gave {edges!r}: a (k, 2) int array expected")
    if not np.isin(edges, nodes).all() or (edges[:, 0] == edges[:, 1]).any():
        raise AssertionError(
            f"{name}.fibre_edges() has a pair that is not two distinct nodes of its cells"
        )


def _check_strain_range(name: str, bounds: Any, shape: tuple[int, ...]) -> None:
    """``fibre_strain_range()``: two (p,) or (m, p) float arrays, lower < 0 < upper (the
    unstrained reference lies inside the laws' range), (m, p) the shape of ``fibre_strains``."""
    columns = shape[1]
    if not (isinstance(bounds, tuple) and len(bounds) == 2):
        raise AssertionError(
            f"{name}.fibre_strain_range() gave {type(bounds).__name__}: a (lower, upper) pair "
            "expected"
        )
    lower, upper = (np.asarray(bound) for bound in bounds)
    if lower.shape not in ((columns,), shape) or upper.shape not in ((columns,), shape):
        raise AssertionError(
            f"{name}.fibre_strain_range() gave shapes {lower.shape} and {upper.shape}: "
            f"({columns},) or {shape} each expected, one bound per column of fibre_strains "
            "(or per cell and column)"
        )
    if (
        lower.dtype.kind != "f"
        or upper.dtype.kind != "f"
        or not ((lower < 0.0).all() and (upper > 0.0).all())
    ):
        raise AssertionError(
            f"{name}.fibre_strain_range() gave lower {lower!r} and upper {upper!r}: floats "
            "with lower < 0 < upper expected (the unstrained reference is in the laws' range)"
        )


# ---------------------------------------------------------------------- interactions
def check_interaction_capabilities(
    block: InteractionBlock, state: State, history: Any = None
) -> None:
    """The interaction capabilities ``block`` declares, at ``state`` with ``history``:

    * ``friction`` a finite real >= 0; ``unilateral_fallback`` a bool, False only for a block
      that keeps contact sets (its own ``freeze``);
    * ``opening_law`` one of OPENING_LAWS; "ramp" only with its own ``released`` and
      ``freeze``;
    * ``gaps_decide(None)`` True (no history: the gaps alone decide the loads, as the static
      solver assumes) and ``gaps_decide(history)`` a bool;
    * ``set_model`` its own only with its own ``with_set`` and ``freeze``, and None for the
      block's initial history (no set frozen there);
    * ``softened_penalty(SOFT_SHARE)`` yields a bool; the forces at ``state`` after it are
      those before to the last bit (restored), and those inside too where it yields False;
    * ``facet_record()`` None or a ``FacetRecord``: record (k, c) ints in [-1, f), corners
      (f, 3, 3), normals (f, 3) of unit length (to 1e-12);
    * ``clearance(state, history)`` None, or (n,) floats, none NaN, with springs
      (``springs_at(state)`` not None) that the relaxation's masses take where it is small;
    * ``tool_penetrations(state, history)`` and ``tool_facing(state, history)`` one entry per
      tool (``n_tools``), each None or, for the first, a dict whose ``deepest_mm`` is finite
      and >= 0, for the second (s, 3) normals of unit length (to 1e-9).

    Raises
    ------
    AssertionError
        Naming the member and what was wrong.
    """
    name = type(block).__name__
    friction = block.friction
    if not is_friction(friction):
        raise AssertionError(f"{name}.friction is {friction!r}: a finite real >= 0 expected")
    keeps_sets = block.keeps_contact_sets
    if not _flag(block, "unilateral_fallback") and not keeps_sets:
        raise AssertionError(
            f"{name}.unilateral_fallback is False on a block that keeps no contact set "
            "(no freeze of its own): the solvers never read it there"
        )
    law = block.opening_law
    if law not in OPENING_LAWS:
        raise AssertionError(f"{name}.opening_law is {law!r}: one of {OPENING_LAWS} expected")
    if law == "ramp" and not (overrides(block, "released", InteractionBlock) and keeps_sets):
        raise AssertionError(f"{name}.opening_law is 'ramp' without its own released and freeze")
    if block.gaps_decide(None) is not True:
        raise AssertionError(
            f"{name}.gaps_decide(None) is not True: without a history the gaps alone decide "
            "the loads (solvers/newton.py curves_with_contact)"
        )
    if not isinstance(block.gaps_decide(history), (bool, np.bool_)):
        raise AssertionError(f"{name}.gaps_decide(history) is not a bool")
    if overrides(block, "set_model", InteractionBlock):
        if not (overrides(block, "with_set", InteractionBlock) and keeps_sets):
            raise AssertionError(f"{name} gives set_model without its own with_set and freeze")
        if block.set_model(state, block.initial_history(), None, None) is not None:
            raise AssertionError(
                f"{name}.set_model of its initial history is not None: no set is frozen there"
            )
    before, _ = block.internal_force(state, history)
    with block.softened_penalty(SOFT_SHARE) as soft:
        if not isinstance(soft, (bool, np.bool_)):
            raise AssertionError(f"{name}.softened_penalty yielded {soft!r}: a bool expected")
        inside, _ = block.internal_force(state, history)
    after, _ = block.internal_force(state, history)
    if not np.array_equal(after, before) or (not soft and not np.array_equal(inside, before)):
        raise AssertionError(
            f"{name}.softened_penalty changed the forces "
            + ("after its block" if soft else "though it yielded False")
            + ": the penalty restored to the last bit expected"
        )
    facets = block.facet_record()
    if facets is not None:
        _check_facets(name, facets)
    clearance = block.clearance(state, history)
    if clearance is not None:
        clearance = np.asarray(clearance)
        if clearance.shape != (len(state.positions),) or np.isnan(clearance).any():
            raise AssertionError(
                f"{name}.clearance() gave shape {clearance.shape} or NaN: (n,) floats expected"
            )
        if block.springs_at(state) is None:
            raise AssertionError(f"{name}.clearance() is given without springs (springs_at)")
    _check_tool_reports(name, block, state, history)


def _check_tool_reports(name: str, block: InteractionBlock, state: State, history: Any) -> None:
    """``tool_penetrations`` and ``tool_facing``: one entry per tool, each None or sound
    (what solvers/tool_penetration.py and solvers/driven_tool_checks.py read);
    ``tool_displacements`` (n_tools, 3) finite (what dynamic relaxation reads to tell a
    moving tool, solvers/relaxation_cuts.py ``more_increments``)."""
    tools = int(block.n_tools)
    moved = np.asarray(block.tool_displacements(state, history))
    if moved.shape != (tools, 3) or not np.isfinite(moved).all():
        raise AssertionError(
            f"{name}.tool_displacements gave shape {moved.shape}: ({tools}, 3) finite mm "
            "expected, one translation per tool"
        )
    depths = block.tool_penetrations(state, history, 0.25)
    if len(depths) != tools:
        raise AssertionError(
            f"{name}.tool_penetrations gave {len(depths)} entries: {tools} expected"
        )
    for entry in depths:
        if entry is not None and not (
            np.isfinite(entry.get("deepest_mm", np.nan)) and entry["deepest_mm"] >= 0.0
        ):
            raise AssertionError(
                f"{name}.tool_penetrations gave deepest_mm {entry.get('deepest_mm')!r}: a "
                "finite depth >= 0 (mm) expected"
            )
    facing = block.tool_facing(state, history)
    if len(facing) != tools:
        raise AssertionError(f"{name}.tool_facing gave {len(facing)} entries: {tools} expected")
    for normals in facing:
        if normals is None:
            continue
        normals = np.asarray(normals, dtype=float)
        if (
            normals.ndim != 2
            or normals.shape[1] != 3
            or not np.allclose(np.linalg.norm(normals, axis=1), 1.0, rtol=0.0, atol=1e-9)
        ):
            raise AssertionError(
                f"{name}.tool_facing gave normals that are not (s, 3) unit vectors"
            )


def _check_facets(name: str, facets: FacetRecord) -> None:
    record, corners = np.asarray(facets.record), np.asarray(facets.corners)
    normals = np.asarray(facets.normals)
    f = len(corners)
    if (
        record.ndim != 2
        or record.dtype.kind not in "iu"
        or corners.shape != (f, 3, 3)
        or normals.shape != (f, 3)
    ):
        raise AssertionError(
            f"{name}.facet_record() shapes {record.shape}, {corners.shape}, {normals.shape}: "
            "(k, c) ints, (f, 3, 3) and (f, 3) expected"
        )
    if record.size and not ((record >= -1) & (record < f)).all():
        raise AssertionError(f"{name}.facet_record() names a facet outside [-1, {f})")
    if not np.allclose(np.linalg.norm(normals, axis=1), 1.0, rtol=0.0, atol=1e-12):
        raise AssertionError(f"{name}.facet_record() normals are not of unit length")
