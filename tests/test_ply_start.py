"""Where two plies start against each other (elements/ply_start.py): plies laid on each
other start silently, a visible overlap is reported, an upper ply whose mid-surface starts
beyond the lower one's (the plies given in the wrong order, or stacked through each other) is
refused with a message that says so. Two G986 plies of 0.3 mm (``g986_stack(2)``), 2 x 2
cells a ply, their faces a + b = 0.3 mm apart at touch."""

import warnings

import numpy as np
import pytest

from elements.plies import PlyStack
from elements.ply_contact import PlyContact
from femcore import Mesh, Model
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


def _on_cylinder(radius: float, cells: int, length: float = 20.0) -> Mesh:
    """A length x length square in cells x cells wrapped on a cylinder of ``radius`` (mm)
    about y, convex towards +z."""
    square = Mesh.rectangle(length, length, nx=cells, ny=cells)
    points = square.points.copy()
    along = points[:, 0] - length / 2
    points[:, 0] = radius * np.sin(along / radius)
    points[:, 2] = radius * (np.cos(along / radius) - 1.0)
    return Mesh(
        points,
        triangles=square.triangles,
        node_sets=square.node_sets,
        element_sets=square.cell_sets("triangle"),
    )


def _stacked(mesh: Mesh, lower=None, **options):
    """The two plies stacked on ``mesh`` by PlyStack, joined by one PlyContact of ply 2 on
    ``lower`` (triangle ids of ply 1; None: all of it) with ``options``."""
    stack = PlyStack(mesh, presets.g986_stack(2), 2)
    model = Model(stack.mesh)
    for k in range(2):
        model.add(stack.element(stack.ply_fabric), cells=f"ply_{k + 1}")
    half = PLY / 2
    model.interact(PlyContact("ply_2", "ply_1" if lower is None else lower, half, half, **options))
    return stack, model


def test_points_past_a_lower_patchs_outline_are_beside_it_not_in_it():
    """A patch of ply 1 (the cells within 6 mm of the crown) under the whole ply 2 on a
    cylinder of radius 10 mm in 5-mm cells, Gauss points: the points past the patch's outline
    face its growths' planes, 0.395 mm deep there, where the contact's fade weighs them by
    1.8e-3. They are not judged: the plies, laid a + b apart, start silently (refused
    before)."""
    mesh = _on_cylinder(10.0, 4)
    centres = mesh.points[mesh.triangles].mean(axis=1)
    stack = PlyStack(mesh, presets.g986_stack(2), 2)
    patch = stack.ply_cells[0][np.abs(centres[:, 0]) < 6.0]
    _, model = _stacked(mesh, patch, rule="gauss")
    assert _compile_saying(model) == []


def test_curved_faces_of_plies_laid_on_a_coarse_cylinder_start_silently():
    """Phong patches bulge differently between the nodes: stacked on a quarter cylinder of
    radius 10 mm in 4 cells, the two plies' curved faces overlap there by 4.4e-3 (a + b),
    under CURVED_OVERCLOSURE_SHARE (warned before, with advice PlyStack cannot follow)."""
    _, model = _stacked(_on_cylinder(10.0, 4, length=np.pi * 10.0 / 2), surface="curved")
    assert _compile_saying(model) == []


def test_the_mirrored_pass_names_its_points_ply():
    """``points="lower"``: the points are the lower ply's, and the refusal says so."""
    stack = _stack(-1.5 * PLY)
    model = Model(stack.mesh)
    for k in range(2):
        model.add(stack.element(stack.ply_fabric), cells=f"ply_{k + 1}")
    model.interact(PlyContact("ply_2", "ply_1", points="lower"))
    with pytest.raises(ValueError, match=r"points of the lower ply lie up to .* into the upper"):
        model.compile()
