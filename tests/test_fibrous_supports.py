"""FibrousShell bending at supports (docs/theory.md §4.5): where the model holds nodes
(translations and directors fixed or prescribed), the rotation-free bending clamps itself.

A side whose two nodes are held bends against a wall in its element's reference plane and
couples no elements; an element whose three nodes are held carries no bending. So the natural
model of a clamp (one block over the whole sheet, the supported nodes fixed) solves the same
equations as the block restricted to the free part with the ``clamped`` option, and a line of
held nodes inside a sheet clamps both sides. The ``clamped`` option asks for a clamp
explicitly; its nodes must be held.

Plates and strips of fabric under their own weight, small deflections (about 2 % of the
overhang), solved with Static.
"""

import numpy as np
import pytest

from elements import FibrousShell, MindlinShell
from femcore import Mesh, Model
from materials import BendingLaw, Fabric, ShearLaw
from solvers import Static
from tests.shell_helpers import position_gradient
from validation.specimens import mindlin_equivalent

G = 9810.0  # mm/s^2
# Thin stiff-bending fabric: the overhang of the plate below sags about 2 % of its length.
FABRIC = Fabric(
    thickness=1.0,
    areal_density=5.7e-9,
    tension=1200.0,
    shear=ShearLaw.linear(4.0),
    bending=BendingLaw.linear(75.0),
)
SIDE, TABLE = 90.0, 30.0  # a square plate lying on a table over x <= 30 mm


def cell_centres_x(mesh: Mesh) -> np.ndarray:
    return mesh.points[mesh.triangles].mean(axis=1)[:, 0]


def solve_tip_sag(model: Model, tip: np.ndarray) -> float:
    result = Static(increments=1).solve(model)
    return float(-result.displacements[tip, 2].mean())


# ------------------------------------------------------------------ the plate on a table
def table_plate(cells: int, restricted: bool) -> tuple[Mesh, Model]:
    """The plate of cells x cells under gravity, its part x <= TABLE on the table: either one
    block over the whole plate with every table node fixed (the natural model), or the block
    restricted to the overhang with the table edge ``clamped`` and fixed."""
    mesh = Mesh.rectangle(SIDE, SIDE, nx=cells, ny=cells)
    model = Model(mesh)
    if restricted:
        edge = mesh.nodes(lambda x, y, z: np.isclose(x, TABLE))
        overhang = np.flatnonzero(cell_centres_x(mesh) > TABLE)
        model.add(FibrousShell(FABRIC, clamped=edge), cells=overhang)
        model.fix(edge)
    else:
        model.add(FibrousShell(FABRIC))
        model.fix(mesh.nodes(lambda x, y, z: x <= TABLE + 1e-9))
    model.gravity((0.0, 0.0, -G))
    return mesh, model


def test_a_plate_on_a_table_is_clamped_at_the_table_edge():
    # The elements on the table carry no bending and the overhanging ones see a clamped side
    # at the table edge, so both models solve the same equations on the free DOFs: they differ
    # by Newton's stopping tolerance (1e-8 of the load) and round-off only; 1e-6 leaves room.
    # (Before the supports clamped the bending, the one-block model sagged 25 % more: the
    # fixed elements bent, which moved the clamp half an element onto the table.)
    mesh, natural = table_plate(12, restricted=False)
    _, explicit = table_plate(12, restricted=True)
    tip = mesh.nodes(lambda x, y, z: np.isclose(x, SIDE))
    sag = solve_tip_sag(natural, tip)
    assert sag == pytest.approx(solve_tip_sag(explicit, tip), rel=1e-6)
    # Against the Mindlin shell calibrated as Bai calibrated S3 (E = 12 B / h^3), which holds
    # the table nodes' rotations exactly: the clamped-edge rotation-free bending converges at
    # second order, +1.5 % at 12 cells (0.37 % at 24); 2 % bounds it.
    mindlin = Model(mesh)
    mindlin.add(MindlinShell(mindlin_equivalent(FABRIC)))
    mindlin.fix(mesh.nodes(lambda x, y, z: x <= TABLE + 1e-9))
    mindlin.gravity((0.0, 0.0, -G))
    assert sag == pytest.approx(solve_tip_sag(mindlin, tip), rel=0.02)


def test_elements_on_the_table_store_no_bending_energy():
    # Held elements have zero curvature coefficients: whatever the state (the table nodes
    # moved too), their curvature is exactly zero, and the bending energy and forces of the
    # one-block model are those of the overhang alone (the restricted model), to round-off
    # of the sums (1e-12 relative).
    _, natural = table_plate(6, restricted=False)
    _, explicit = table_plate(6, restricted=True)
    natural, explicit = natural.compile(), explicit.compile()
    block = natural.blocks[0]
    on_table = block.held_cell
    assert on_table.sum() == 2 * 6 * 2  # the 2 x 6 grid cells of the table, 2 triangles each
    assert not block.clamped_side[on_table].any() and not block.interior_side[on_table].any()
    assert not block.reference_coefficients[on_table].any()

    state = natural.initial_state()
    rng = np.random.default_rng(5)
    state.positions = state.positions + rng.normal(scale=0.3, size=state.positions.shape)
    fields = block.cell_fields(state)
    assert not fields["warp_curvature"][on_table].any()
    assert not fields["weft_curvature"][on_table].any()
    energy = block.strain_energy_parts(state)["bending"]
    assert energy > 0.0
    assert energy == pytest.approx(explicit.blocks[0].strain_energy_parts(state)["bending"], 1e-12)
    force = block.internal_force_parts(state)["bending"][0]
    expected = explicit.blocks[0].internal_force_parts(state)["bending"][0]
    assert np.abs(force - expected).max() <= 1e-12 * np.abs(expected).max()


# ------------------------------------------------------------------ a clamp along a column
STRIP, WIDTH, CELLS = 60.0, 10.0, 12


def strip_tip_sag(length: float, cells: int, clamp_x: float, clamped_option: bool) -> tuple:
    """Tip sags (x = 0 end, x = length end) of a strip under gravity whose column of nodes at
    ``clamp_x`` is fixed, with or without the ``clamped`` option on those nodes."""
    mesh = Mesh.rectangle(length, WIDTH, nx=cells, ny=2)
    column = mesh.nodes(lambda x, y, z: np.isclose(x, clamp_x))
    model = Model(mesh)
    model.add(FibrousShell(FABRIC, clamped=column if clamped_option else None))
    model.fix(column)
    model.gravity((0.0, 0.0, -G))
    result = Static(increments=1).solve(model)
    x = mesh.points[:, 0]
    ends = [np.flatnonzero(np.isclose(x, end)) for end in (0.0, length)]
    return tuple(float(-result.displacements[nodes, 2].mean()) for nodes in ends)


def test_fixing_the_end_of_a_strip_clamps_it_as_the_clamped_option_does():
    # The column of fixed nodes makes the clamped sides the option asks for: the same model,
    # to Newton's stopping tolerance (1e-6 as above).
    _, natural = strip_tip_sag(STRIP, CELLS, 0.0, clamped_option=False)
    _, explicit = strip_tip_sag(STRIP, CELLS, 0.0, clamped_option=True)
    assert natural > 0.0
    assert natural == pytest.approx(explicit, rel=1e-6)


def test_translations_prescribed_and_directors_fixed_hold_a_node_as_fix_does():
    # "Held" is every DOF not free, whichever way: displace(0) for the translations and fixed
    # directors give the clamp of model.fix (same equations; 1e-6 as above).
    mesh = Mesh.rectangle(STRIP, WIDTH, nx=CELLS, ny=2)
    model = Model(mesh)
    model.add(FibrousShell(FABRIC))
    model.displace("left", ux=0.0, uy=0.0, uz=0.0)
    model.fix("left", ("alpha", "beta"))
    model.gravity((0.0, 0.0, -G))
    assert model.compile().blocks[0].clamped_side.sum() == 2  # the two left sides
    sag = solve_tip_sag(model, mesh.nodes("right"))
    _, fixed = strip_tip_sag(STRIP, CELLS, 0.0, clamped_option=False)
    assert sag == pytest.approx(fixed, rel=1e-6)


def test_a_line_held_inside_a_strip_clamps_both_sides():
    # A strip of twice the length fixed along its middle column: each half hangs as the
    # half-length cantilever with the clamped option (the halves are decoupled at the held
    # line: the same equations, 1e-6 as above), and the two halves alike (the mesh maps onto
    # itself under the half turn about the vertical axis through the centre, which leaves
    # gravity unchanged: Newton's tolerance and round-off again).
    left, right = strip_tip_sag(2 * STRIP, 2 * CELLS, STRIP, clamped_option=False)
    _, cantilever = strip_tip_sag(STRIP, CELLS, 0.0, clamped_option=True)
    assert right == pytest.approx(cantilever, rel=1e-6)
    assert left == pytest.approx(right, rel=1e-6)
    # The clamped option may name the interior line too (the union is the same clamp).
    assert strip_tip_sag(2 * STRIP, 2 * CELLS, STRIP, clamped_option=True)[1] == pytest.approx(
        right, rel=1e-6
    )


def test_bending_forces_and_tangent_at_supports_are_the_energy_derivatives():
    # With the reference curvature coefficients the bending forces are the exact gradient of
    # the bending energy at the free nodes, clamped sides and held elements included (a held
    # region x <= 10 and a held interior line x = 30 on a jittered, bent patch): central
    # differences of step 1e-6 mm agree to 1e-6 of the largest force. The element tangent
    # against the coloured finite differences of the force: both differences of step 1e-6,
    # 1e-6 of the largest entry (as tests/test_static.py).
    mesh = Mesh.rectangle(40.0, 20.0, nx=4, ny=2)
    model = Model(mesh)
    model.add(FibrousShell(FABRIC, bending_geometry="reference"))
    model.fix(mesh.nodes(lambda x, y, z: (x <= 10.0 + 1e-9) | np.isclose(x, 30.0)))
    compiled = model.compile()
    block = compiled.blocks[0]
    assert block.held_cell.any() and block.clamped_side.any()
    rng = np.random.default_rng(11)
    state = compiled.initial_state()
    x, y = mesh.points[:, 0], mesh.points[:, 1]
    state.positions[:, 2] = 0.02 * (x - 10.0) ** 2 / 10.0 + 0.01 * x * y / 10.0
    state.positions = state.positions + rng.normal(scale=0.05, size=state.positions.shape)

    force = block.internal_force_parts(state)["bending"][0]
    gradient = position_gradient(lambda s: block.strain_energy_parts(s)["bending"], state)
    # On the free nodes: the held ones never move, and a clamped side's fold is varied
    # (docs/theory.md §4.5) as a rotation of its element about the side, which is the
    # whole motion while the side's two nodes stay put.
    free_nodes = compiled.dofs.free[:, 0]
    error = np.abs(force - gradient)[free_nodes].max()
    assert error <= 1e-6 * np.abs(gradient[free_nodes]).max()

    free = compiled.dofs.free.ravel()
    reference = compiled.stiffness(state, "finite_difference").toarray()[np.ix_(free, free)]
    own = compiled.stiffness(state).toarray()[np.ix_(free, free)]
    assert np.abs(own - reference).max() <= 1e-6 * np.abs(reference).max()


# ------------------------------------------------------------------ clamps that cannot apply
def test_a_clamped_edge_the_supports_do_not_hold_is_refused():
    mesh = Mesh.rectangle(STRIP, WIDTH, nx=CELLS, ny=2)
    loose = Model(mesh)
    loose.add(FibrousShell(FABRIC, clamped="left"))  # nothing fixed
    with pytest.raises(ValueError, match="must have their translations and directors fixed"):
        loose.compile()
    pinned = Model(mesh)
    pinned.add(FibrousShell(FABRIC, clamped="left"))
    pinned.fix("left", ("ux", "uy", "uz"))  # the directors free: a pin, not a clamp
    with pytest.raises(ValueError, match="must have their translations and directors fixed"):
        pinned.compile()
    nowhere = Model(mesh)
    nowhere.add(FibrousShell(FABRIC, clamped=[0, 2]))  # two nodes that make no edge
    nowhere.fix([0, 2])
    with pytest.raises(ValueError, match="no edge of the block"):
        nowhere.compile()


# ------------------------------------------------------------------ the clamped option's sets
def test_a_list_of_set_names_clamps_each_as_symmetric_takes_one():
    mesh = Mesh.rectangle(STRIP, WIDTH, nx=CELLS, ny=2)
    sags = []
    for clamped in (["left", "right"], None):
        model = Model(mesh)
        model.add(FibrousShell(FABRIC, clamped=clamped))
        model.fix("left")
        model.fix("right")
        model.gravity((0.0, 0.0, -9810.0))
        sags.append(Static(increments=1).solve(model).displacements[:, 2].min())
    # Fixing both ends clamps them by itself (docs/theory.md §4.5): the option adds nothing.
    assert sags[0] < 0.0
    assert sags[0] == pytest.approx(sags[1], rel=1e-12)


def test_fractional_clamped_ids_are_refused_not_truncated():
    mesh = Mesh.rectangle(STRIP, WIDTH, nx=CELLS, ny=2)
    model = Model(mesh)
    model.add(FibrousShell(FABRIC, clamped=[0.9, 2 * CELLS + 1.9]))
    model.fix("left")
    with pytest.raises(ValueError, match=r"clamped: node ids must be integers, got \[0\.9"):
        model.compile()
    whole = Model(mesh)
    whole.add(FibrousShell(FABRIC, clamped=[0.0, float(CELLS + 1)]))  # whole floats: ids
    whole.fix("left")
    whole.compile()


# ------------------------------------------------------------------ the option in a case file
CASE = """title = "t"
[mesh]
rectangle = {{ lx = 40.0, ly = 10.0, nx = 4, ny = 1 }}
[[part]]
element = "fibrous"
material = {{thickness = 0.3, areal_density = 3e-10, tension = 100.0, shear = 0.2, bending = 0.01}}
options = {{ clamped = {clamped} }}
{fixes}
[gravity]
acceleration = [0.0, 0.0, -9810.0]
[solver]
kind = "static"
"""


def test_a_case_file_clamps_a_list_of_sets(tmp_path):
    from fibreshell.case import load_case

    path = tmp_path / "both.toml"
    fixes = '[[fix]]\nnodes = "left"\n[[fix]]\nnodes = "right"'
    path.write_text(CASE.format(clamped='["left", "right"]', fixes=fixes))
    load_case(path).model().compile()  # before: "invalid literal for int()" from numpy


def test_a_case_file_clamp_without_its_fix_names_the_file_table_key_and_the_fix(tmp_path):
    from fibreshell.case import CaseError, load_case

    path = tmp_path / "loose.toml"
    path.write_text(CASE.format(clamped='"left"', fixes=""))
    expected = r'loose\.toml: \[part\[0\]\.options\.clamped\]: .*\[\[fix\]\] nodes = "left"'
    with pytest.raises(CaseError, match=expected):
        load_case(path).model().compile()
