"""The checks of what a Model's element blocks and interactions bind to, as
femcore.compiled.CompiledModel builds: a bound block is of its protocol, declares its reach,
takes its history, and acts on nodes that carry its DOFs; and the median element edge, the
scale of the residual checks.
"""

from __future__ import annotations

import inspect
import warnings
from collections.abc import Callable

import numpy as np

from femcore.dofs import dof_columns, dof_names
from femcore.element import ElementBlock, ElementType
from femcore.entry_error import EntryError, EntryWarning, OptionError
from femcore.interaction import OPENING_LAWS, Body, Interaction, InteractionBlock, is_friction
from femcore.mesh import Mesh

__all__ = [
    "Part",
    "bound_block",
    "bound_interaction",
    "check_block",
    "check_bound",
    "supported_block",
    "median_edge",
    "used_nodes",
]

#: A part of the compiled model: what contributes forces, energies and tangents.
Part = ElementBlock | InteractionBlock


def bound_block(
    element: ElementType, mesh: Mesh, cells: np.ndarray, directors: np.ndarray, index: int
) -> ElementBlock:
    """``element.bind(mesh, cells, directors)``; its ValueErrors (an unknown node set among
    its options, ...) name the block (``model.blocks[index]``), an ``OptionError`` its option
    as the key (``options.<option>``: fractional ``clamped`` node ids), as
    ``supported_block``'s do."""
    try:
        return element.bind(mesh, cells, directors)
    except EntryError:
        raise
    except ValueError as error:
        raise block_entry_error(element, index, error) from None


def supported_block(
    element: ElementType, block: ElementBlock, constrained: np.ndarray, index: int
) -> None:
    """``block.apply_supports(held, constrained)`` with ``held`` the nodes where every DOF
    of ``constrained`` (n, dofs) bool is; its ValueErrors name the block
    (``model.blocks[index]``), an ``OptionError`` its option as the key
    (``options.<option>``) with the message in a case file's terms."""
    try:
        block.apply_supports(np.asarray(constrained.all(axis=1)), constrained)
    except EntryError:
        raise
    except ValueError as error:
        raise block_entry_error(element, index, error) from None


def block_entry_error(element: ElementType, index: int, error: ValueError) -> EntryError:
    """``error`` (a ValueError of ``model.blocks[index]``'s bind or supports) as an EntryError
    naming the block; an ``OptionError`` also names its option as the key
    (``options.<option>``) with its message in a case file's terms."""
    where = f"block {index} ({type(element).__name__}): "
    if isinstance(error, OptionError):
        key = f"options.{error.option}"
        return EntryError("block", index, str(error), where, key, error.case_reason)
    return EntryError("block", index, str(error), where)


def bound_interaction(
    interaction: Interaction, body: Body, index: int, tool: int
) -> InteractionBlock:
    """``interaction.bind(body)``, checked as ``check_block`` checks an element block, and
    its ``check_start``; their ValueErrors (a body that starts inside a tool) name the
    interaction (``model.interactions[index]``) and the tool number ``tool`` it has (the
    ``tool1`` ... of the histories) when it acts against a tool; so do the warnings of its
    ``check_start`` (a body that starts overlapping its tool)."""
    against = f", tool {tool}" if getattr(interaction, "tool", None) is not None else ""
    where = f"interaction {index} ({type(interaction).__name__}{against})"
    try:
        block = interaction.bind(body)
    except ValueError as error:
        raise EntryError("interaction", index, str(error), f"{where}: ") from None
    check_bound(
        type(interaction).__name__,
        block,
        InteractionBlock,
        ("internal_force", "strain_energy", "tangent", "node_fields"),
        interaction.dofs,
        body.active,
    )
    n_tools = getattr(block, "n_tools", None)
    if isinstance(n_tools, bool) or not isinstance(n_tools, (int, np.integer)) or n_tools < 0:
        raise ValueError(f"{type(block).__name__}.n_tools is {n_tools!r}: expected an int >= 0")
    friction = block.friction
    if not is_friction(friction):
        raise ValueError(
            f"{type(block).__name__}.friction is {friction!r}: expected a finite number >= 0 "
            "(the Coulomb coefficient the static solver reads)"
        )
    _check_flags(block, ("unilateral_fallback",))
    if block.opening_law not in OPENING_LAWS:
        raise ValueError(
            f"{type(block).__name__}.opening_law is {block.opening_law!r}: expected one of "
            f"{OPENING_LAWS}"
        )
    with warnings.catch_warnings(record=True) as said:
        warnings.simplefilter("always")
        try:
            block.check_start()
        except ValueError as error:
            raise EntryError("interaction", index, str(error), f"{where}: ") from None
    for warning in said:  # said again, naming the interaction and its tool
        if issubclass(warning.category, UserWarning):
            said_again = EntryWarning("interaction", index, str(warning.message), f"{where}: ")
            warnings.warn(said_again, stacklevel=4)
        else:
            warnings.warn(warning.message, warning.category, stacklevel=4)
    return block


def check_block(element: ElementType, block: ElementBlock, active: np.ndarray) -> None:
    """A bound block must be an ElementBlock that declares its reach, with a (m, k) node
    connectivity whose nodes carry the DOFs it needs."""
    check_bound(
        type(element).__name__,
        block,
        ElementBlock,
        ("internal_force", "strain_energy", "tangent", "cell_fields", "node_fields"),
        element.dofs,
        active,
    )
    _check_flags(block, ("compression_free_tangent", "has_fibre_strains"))
    cell_ids = getattr(block, "cell_ids", None)
    rows = len(np.asarray(block.connectivity))
    if cell_ids is None or np.shape(cell_ids) != (rows,):
        raise ValueError(
            f"{type(block).__name__}.cell_ids is "
            f"{'missing' if cell_ids is None else f'of shape {np.shape(cell_ids)}'}: a block "
            f"keeps the mesh ids of its cells, ({rows},) int in the order of its connectivity "
            "(bind's cell_ids: the outputs and the static solver place its cells by them)"
        )


def _check_flags(block: Part, names: tuple[str, ...]) -> None:
    """The capability flags ``names`` of ``block`` (femcore.element, femcore.interaction) are
    True or False: the solvers branch on them."""
    for name in names:
        value = getattr(block, name)
        if not isinstance(value, (bool, np.bool_)):
            raise ValueError(
                f"{type(block).__name__}.{name} is {value!r}: expected True or False (a "
                "capability of the protocol the solvers test)"
            )


def check_bound(
    name: str,
    block: Part,
    protocol: type,
    methods: tuple[str, ...],
    dofs: tuple[str, ...],
    active: np.ndarray,
) -> None:
    """What ``name.bind`` returned is a ``protocol`` block (ElementBlock, InteractionBlock)
    that declares its reach, whose ``methods`` take (state, history), and whose
    connectivity's nodes carry ``dofs``."""
    if not isinstance(block, protocol):
        raise ValueError(
            f"{name}.bind returned {type(block).__name__}: expected an {protocol.__name__} "
            f"({protocol.__module__})"
        )
    reach = getattr(block, "reach", None)
    if isinstance(reach, bool) or not isinstance(reach, (int, np.integer)) or reach < 1:
        raise ValueError(
            f"{type(block).__name__}.reach is {reach!r}: every block declares how many cell-hops "
            "its forces reach (1: cell-local, 2: bending patches over neighbours)"
        )
    for method in methods:
        if not takes_history(getattr(block, method)):
            raise ValueError(
                f"{type(block).__name__}.{method} must take (state, history=None): the model "
                "passes each part its history variables"
            )
    connectivity = np.asarray(block.connectivity)
    if connectivity.ndim != 2 or not np.issubdtype(connectivity.dtype, np.integer):
        raise ValueError(
            f"{type(block).__name__}.connectivity must be an (m, k) integer array of node ids"
        )
    if connectivity.size:
        if connectivity.min() < 0 or connectivity.max() >= len(active):
            raise ValueError(
                f"{type(block).__name__}.connectivity refers to nodes outside 0..{len(active) - 1}"
            )
        nodes = used_nodes(connectivity, len(active))
        lacking = ~active[np.ix_(nodes, dof_columns(dofs))]
        if lacking.any():
            node = nodes[np.argwhere(lacking)[0, 0]]
            raise ValueError(
                f"{name} acts on node {node}, which carries only "
                f"{', '.join(dof_names(active[node])) or 'no DOF'}: it needs nodes of an "
                "element with the DOFs it uses"
            )


def used_nodes(connectivity: np.ndarray, n_nodes: int) -> np.ndarray:
    """The nodes (increasing) that the cells (m, k) use: np.unique by a count, without the
    sort (a tenth of its time at 400k triangles)."""
    return np.flatnonzero(np.bincount(np.asarray(connectivity).ravel(), minlength=n_nodes))


def takes_history(method: Callable) -> bool:
    """Whether a bound method accepts two positional arguments (state, history)."""
    try:
        parameters = list(inspect.signature(method).parameters.values())
    except (TypeError, ValueError):  # no signature to read (a C function): trust it
        return True
    positional = [p for p in parameters if p.kind in (p.POSITIONAL_ONLY, p.POSITIONAL_OR_KEYWORD)]
    variadic = any(p.kind is p.VAR_POSITIONAL for p in parameters)
    return variadic or len(positional) >= 2


def median_edge(mesh: Mesh, entries, cells_of) -> float:
    """Median length of the element edges (mesh length unit): the scale that turns a force
    into a moment in residual checks."""
    lengths = []
    for entry in entries:
        cells = mesh.points[cells_of(entry)]
        for k in range(cells.shape[1]):
            lengths.append(np.linalg.norm(cells[:, k] - cells[:, k - 1], axis=1))
    return float(np.median(np.concatenate(lengths)))
