"""A meshed tool whose size is off the body's by orders of magnitude warns when the model is
compiled, naming both extents (elements/tool_scale.py): a table written in metres under a strip
in mm stopped Static at load factor 0.002 with advice about contacts and nothing about units.

Reference: the extents are the meshes' own: a 100 x 20 mm strip over a 0.3 x 0.2 table (the
300 x 200 mm table written in metres), 0.003 times the strip's largest extent."""

import warnings

import pytest

from elements import FibrousShell, RigidSurface
from femcore import Mesh, Model
from materials import Fabric

FABRIC = Fabric(thickness=1.0, areal_density=1.66e-9, tension=1000.0, shear=1.0, bending=0.833)


def strip_on(table_side: float, patch=None) -> Model:
    """A 100 x 20 mm strip 0.5 mm over a table of 1.5 x 1 table_side, centred under it; the
    contact on the nodes ``patch`` selects (all by default)."""
    model = Model(Mesh.rectangle(100.0, 20.0, nx=4, ny=1, origin=(0.0, 0.0, 0.5)))
    model.add(FibrousShell(FABRIC))
    model.fix("left")
    table = Mesh.rectangle(
        1.5 * table_side,
        table_side,
        nx=2,
        ny=2,
        origin=(50.0 - 0.75 * table_side, 10.0 - 0.5 * table_side, 0.0),
    )
    model.contact(RigidSurface(table), nodes=patch)
    return model


def test_a_tool_in_metres_beside_a_body_in_mm_warns_with_both_extents():
    with pytest.warns(UserWarning, match="the tool is 0.003 times the body's size") as said:
        strip_on(0.2).compile()
    message = next(str(w.message) for w in said if "times the body" in str(w.message))
    assert "spans 0.3 x 0.2 x 0 (largest 0.3)" in message
    assert "body's mesh 100 x 20 x 0 (largest 100)" in message
    assert "metres beside one in mm is 1000 times off" in message


def test_a_tool_of_the_body_s_order_of_size_is_not_warned_about():
    with warnings.catch_warnings(record=True) as said:
        warnings.simplefilter("always")
        strip_on(200.0).compile()
    assert not [w for w in said if "times the body" in str(w.message)]


def test_a_contact_limited_to_a_patch_is_measured_against_the_whole_body():
    """The strip's last 5 mm (x >= 95: its end nodes, a patch 0 x 20 mm) over a 3000 x 2000
    mm table in mm: the table is 30 times the strip (the meshes' largest extents, 3000 and
    100), within the factor 100, though 150 times the patch's 20 mm: no unit slip to warn of.
    """
    with warnings.catch_warnings(record=True) as said:
        warnings.simplefilter("always")
        strip_on(2000.0, patch=lambda x, y, z: x >= 95.0 - 1e-9).compile()
    assert not [w for w in said if "times the body" in str(w.message)]


def test_a_patch_contact_with_a_table_in_metres_still_warns_by_the_whole_body():
    """The same patch under the 300 x 200 mm table written in metres: 0.003 of the strip."""
    with pytest.warns(UserWarning, match="the tool is 0.003 times the body's size"):
        strip_on(0.2, patch=lambda x, y, z: x >= 95.0 - 1e-9).compile()
