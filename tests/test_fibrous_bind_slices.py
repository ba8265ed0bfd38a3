"""The fibrous block forms its reference geometry a slice of cells at a time at bind
(elements/fibrous/block.py ``REFERENCE_SLICE``): every table is a cell's own, so slices of
any size give the whole's bits. Checked on an uneven, bent sheet (cells of many shapes, the
nodal directors off the cells' normals), with nodal and element normals, slices of 7 cells
against one slice of all."""

import numpy as np
import pytest

from elements import FibrousShell
from elements.fibrous import block as fibrous_block
from femcore import Mesh, Model
from materials import presets

TABLES = (
    "reference_area",
    "reference_normal",
    "reference_length1",
    "reference_length2",
    "reference_shear",
    "reference_fold",
    "reference_coefficients",
)


def bent_sheet(thickness: str) -> Model:
    """A fibre-aligned sheet of uneven columns and rows, gently bent (slopes below the
    fibre-alignment tolerance of 1 degree): cells of many shapes and nodal normals that are
    not the cells'."""
    mesh = Mesh.rectangle(60.0, 40.0, nx=9, ny=6)
    points = np.array(mesh.points)
    rng = np.random.default_rng(3)
    columns = np.unique(points[:, 0])
    rows = np.unique(points[:, 1])
    new_x = columns + np.r_[0.0, rng.uniform(-2.0, 2.0, len(columns) - 2), 0.0]
    new_y = rows + np.r_[0.0, rng.uniform(-2.0, 2.0, len(rows) - 2), 0.0]
    points[:, 0] = new_x[np.searchsorted(columns, points[:, 0])]
    points[:, 1] = new_y[np.searchsorted(rows, points[:, 1])]
    points[:, 2] = 1.5e-4 * (points[:, 0] - 30.0) ** 2 + 1.0e-4 * (points[:, 1] - 20.0) ** 2
    model = Model(Mesh(points, mesh.triangles))
    model.add(FibrousShell(presets.g986_stack(), thickness=thickness))
    model.fix(model.mesh.nodes(lambda x, y, z: x <= 0.0))
    return model


@pytest.mark.parametrize("thickness", ["nodal", "element"])
def test_slices_of_cells_give_the_reference_tables_of_the_whole_to_the_bit(thickness, monkeypatch):
    whole = bent_sheet(thickness).compile().blocks[0]
    assert len(whole.connectivity) < fibrous_block.REFERENCE_SLICE  # one slice: all cells
    monkeypatch.setattr(fibrous_block, "REFERENCE_SLICE", 7)
    sliced = bent_sheet(thickness).compile().blocks[0]
    for name in TABLES:
        assert np.array_equal(getattr(sliced, name), getattr(whole, name)), name
    # the cells differ (a real check): lengths from the uneven columns, levels and shears
    # from the bend
    assert np.ptp(whole.reference_length1) > 0.5 and np.ptp(whole.reference_shear) > 1e-4
