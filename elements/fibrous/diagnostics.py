"""Model-level views of the fibrous shell's tables, for checks and post-processing without
reaching into the blocks: arrays over the mesh's triangles, as ``CompiledModel.fields`` spreads
the cell fields (NaN, -1 or False where no FibrousShell covers a triangle).

The three corners of a triangle are in the block's fibre order (local node 0 the fibre
corner, Eq. 9), given by ``connectivity``; side s is opposite corner s.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from elements.fibrous.block import FibrousShellBlock

if TYPE_CHECKING:
    from femcore.model import CompiledModel

__all__ = ["side_tables", "thickness_along_directors"]


def _blocks(model: CompiledModel) -> list[FibrousShellBlock]:
    """The model's FibrousShell blocks; ValueError when it has none."""
    blocks = [block for block in model.blocks if isinstance(block, FibrousShellBlock)]
    if not blocks:
        raise ValueError("the model has no FibrousShell block")
    return blocks


def _spread(model: CompiledModel, tables: list[tuple[np.ndarray, dict]], fill: dict) -> dict:
    """Per-block arrays (cells of the block first) over all the mesh's triangles: ``tables``
    the (cell_ids, {name: values}) of each block, ``fill`` the value of each name elsewhere."""
    count = len(model.mesh.cells("triangle"))
    out: dict[str, np.ndarray] = {}
    for cell_ids, values in tables:
        for name, value in values.items():
            value = np.asarray(value)
            full = out.setdefault(
                name, np.full((count,) + value.shape[1:], fill[name], dtype=value.dtype)
            )
            full[cell_ids] = value
    return out


def thickness_along_directors(
    model: CompiledModel, positions: np.ndarray, directors: np.ndarray
) -> dict[str, np.ndarray]:
    """The thickness along the directors at the corners of every triangle of the model's
    FibrousShell blocks (Bai Eq. 10, 14; with ``thickness="element"`` Eq. 15), as
    ``FibrousShellBlock.thickness_along_directors`` gives it per block.

    Parameters
    ----------
    model : femcore.CompiledModel with at least one FibrousShell block.
    positions, directors : (n, 3) float
        A configuration (mm; unit directors), e.g. a result's ``positions`` and ``directors``.

    Returns
    -------
    dict
        Over the mesh's triangles (t of them): ``connectivity`` (t, 3) int, the node of each
        corner (-1 off the blocks); ``cosine`` (t, 3): V . n; ``thickness`` (t, 3), mm:
        h_m = h / max(V . n, guard), so h_m V . n = h where the guard did not act (NaN off
        the blocks); ``guarded`` (t, 3) bool: the corners where the guard acted.

    Raises ValueError when the model has no FibrousShell block.
    """
    tables = []
    for block in _blocks(model):
        values = block.thickness_along_directors(positions, directors)
        tables.append((block.cell_ids, {"connectivity": block.connectivity, **values}))
    fill = {"connectivity": -1, "cosine": np.nan, "thickness": np.nan, "guarded": False}
    return _spread(model, tables, fill)


def side_tables(model: CompiledModel) -> dict[str, np.ndarray]:
    """The sides of every triangle of the model's FibrousShell blocks: which couple two cells
    in the rotation-free bending and which bend against a clamped wall (docs/theory.md §4.5,
    with the supports applied at compile).

    Parameters
    ----------
    model : femcore.CompiledModel with at least one FibrousShell block.

    Returns
    -------
    dict
        Over the mesh's triangles (t of them), side s opposite corner s of ``connectivity``
        (t, 3) int (-1 off the blocks): ``neighbour`` (t, 3) int, the triangle across the
        side in the same block (-1 on its free edges and off the blocks); ``interior_side``
        (t, 3) bool, the side couples the two cells; ``clamped_side`` (t, 3) bool, the side
        bends against a wall: of the reference plane, or on a symmetry plane
        (``mirror_side`` (t, 3) bool, FibrousShell ``symmetric``) the wall through the side
        perpendicular to the plane, as against its cell's mirror image; ``held_cell`` (t,)
        bool, all three nodes held (no bending).

    Raises ValueError when the model has no FibrousShell block.
    """
    tables = []
    for block in _blocks(model):
        neighbour = np.where(block.neighbour >= 0, block.cell_ids[block.neighbour], -1)
        values = {
            "connectivity": block.connectivity,
            "neighbour": neighbour,
            "interior_side": block.interior_side,
            "clamped_side": block.clamped_side,
            "mirror_side": np.any(block.mirror_normal != 0.0, axis=-1),
            "held_cell": block.held_cell,
        }
        tables.append((block.cell_ids, values))
    fill = {
        "connectivity": -1,
        "neighbour": -1,
        "interior_side": False,
        "clamped_side": False,
        "mirror_side": False,
        "held_cell": False,
    }
    return _spread(model, tables, fill)
