"""Where two plies start against each other (elements/ply_start.py): plies laid on each
other start silently, a visible overlap is reported, an upper ply whose mid-surface starts
beyond the lower one's (the plies given in the wrong order, or stacked through each other) is
refused with a message that says so. Two G986 plies of 0.3 mm (``g986_stack(2)``), 2 x 2
cells a ply, their faces a + b = 0.3 mm apart at touch."""

import warnings

import pytest

from elements.plies import PlyStack
from elements.ply_contact import PlyContact
from femcore import Mesh
from materials import presets

PLY = presets.g986_stack(2).thickness / 2  # mm, a + b


def _stack(shift: float = 0.0) -> PlyStack:
    """The two plies, the upper one moved ``shift`` mm along z (its directors' side)."""
    stack = PlyStack(Mesh.rectangle(20.0, 20.0, nx=2, ny=2), presets.g986_stack(2), 2)
    mesh = stack.mesh
    points = mesh.points.copy()
    points[stack.ply_nodes[1], 2] += shift
    stack.mesh = Mesh(
        points,
        triangles=mesh.triangles,
        node_sets=mesh.node_sets,
        element_sets=mesh.cell_sets("triangle"),
    )
    return stack


def _compile_saying(model) -> list[str]:
    with warnings.catch_warnings(record=True) as said:
        warnings.simplefilter("always")
        model.compile()
    return [str(warning.message) for warning in said]


def test_plies_laid_on_each_other_start_silently():
    """PlyStack lays them a + b apart: no overlap beyond round-off."""
    assert _compile_saying(_stack().model()) == []


def test_an_overlap_below_a_thousandth_of_the_plies_thickness_is_not_reported():
    """The report's share (elements.contact_start.OVERCLOSURE_SHARE, 1e-3 of a + b): 1e-4
    of it is a stack laid on to round-off."""
    assert _compile_saying(_stack(-1e-4 * PLY).model()) == []


@pytest.mark.parametrize("share", [0.01, 0.5, 0.99])
def test_a_visible_overlap_is_reported_with_its_depth(share):
    """The upper ply moved share x (a + b) into the lower one: every point overlaps by that
    much (the faces are flat and parallel), which the warning states."""
    said = _compile_saying(_stack(-share * PLY).model())
    assert len(said) == 1
    assert "the plies start overlapping: 8 of 8 contact points" in said[0]
    assert f"up to {share * PLY:.3g} mm into the lower ply" in said[0]


def test_an_upper_ply_beyond_the_lower_ones_mid_surface_is_refused():
    """1.5 (a + b) into the lower ply: the upper ply's mid-surface lies below the lower
    one's, which the penalty would push further through."""
    with pytest.raises(ValueError, match=r"start through each other.*0\.45 mm into the lower"):
        _stack(-1.5 * PLY).model().compile()


def test_plies_given_in_the_wrong_order_are_refused():
    """``upper`` the ply below: its lower face is a ply thickness plus a + b below the upper
    ply's top face."""
    stack = _stack()
    model = stack.model()
    model.interact(PlyContact("ply_1", "ply_2"))
    with pytest.raises(ValueError, match=r"interaction 1 .*Give the ply above as ``upper``"):
        model.compile()


def test_a_ply_above_another_with_a_gap_starts_silently():
    """Apart by a ply thickness: not touching, nothing to say."""
    assert _compile_saying(_stack(PLY).model()) == []
