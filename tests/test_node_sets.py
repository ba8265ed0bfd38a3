"""Node sets of a case file by bounds (fibreshell/case_sets.py): a bound in mesh units or as a
share of the mesh's extent ("100%"), so that a sweep over the mesh's size keeps its sets; and
bounds that select nothing are an error naming the set, the bound and the mesh's extent; a path
is a line of nodes, one at each position along it, or an error."""

import copy
from pathlib import Path

import numpy as np
import pytest

from femcore.mesh import Mesh
from fibreshell.case import CaseError, case_from_data, read_case_data
from fibreshell.case_sets import BoundsError, order_path, select_by_bounds
from fibreshell.sweep import apply_overrides

CASES = Path(__file__).parents[1] / "cases"


def strip(sets: dict, lx: float = 200.0, **tables) -> dict:
    """The tables of a 200 x 60 mm Mindlin strip, 8 x 2 cells, with the node sets ``sets``."""
    return {
        "mesh": {"rectangle": {"lx": lx, "ly": 60.0, "nx": 8, "ny": 2}},
        "sets": sets,
        "part": [{"element": "mindlin", "material": {"E": 1e3, "nu": 0.3, "thickness": 1.0,
                                                      "density": 1e-9}}],
        "solver": {"kind": "static"},
        **tables,
    }  # fmt: skip


def points_of(case, name: str) -> np.ndarray:
    return case.mesh.points[case.node_sets[name]]


# ---------------------------------------------------------------------- relative bounds
def test_a_share_of_the_extent_selects_that_place_along_the_axis():
    case = case_from_data(
        strip({"tip": {"x_min": "100%"}, "middle": {"y_min": "50%", "y_max": "50%"},
               "first_quarter": {"x_max": "25 %"}}),
        "strip.toml",
    )  # fmt: skip
    assert np.array_equal(case.node_sets["tip"], case.mesh.nodes("right"))
    assert np.all(points_of(case, "middle")[:, 1] == 30.0) and len(case.node_sets["middle"]) == 9
    assert set(points_of(case, "first_quarter")[:, 0]) == {0.0, 25.0, 50.0}


def test_a_share_is_of_the_extent_from_its_low_end_not_from_zero():
    points = np.array([[-50.0, 0.0, 0.0], [0.0, 0.0, 0.0], [50.0, 0.0, 0.0]])
    assert select_by_bounds(points, {"x_min": "50%", "x_max": "50%"}).tolist() == [1]
    assert select_by_bounds(points, {"x_max": "0%"}).tolist() == [0]


def test_a_sweep_over_the_length_keeps_a_relative_set_at_the_tip_and_loses_an_absolute_one():
    data = strip({"tip": {"x_min": "100%"}})
    longer, _ = apply_overrides(data, {"mesh.rectangle.lx": 300.0})
    case = case_from_data(longer, "strip.toml")
    assert np.all(points_of(case, "tip")[:, 0] == 300.0) and len(case.node_sets["tip"]) == 3
    shorter, _ = apply_overrides(strip({"tip": {"x_min": 200.0}}), {"mesh.rectangle.lx": 150.0})
    with pytest.raises(CaseError, match=r"\[sets\.tip\]: no node within x_min = 200 "):
        case_from_data(shorter, "strip.toml")


def test_relative_bounds_work_wherever_nodes_are_selected_fixes_and_paths_too():
    case = case_from_data(
        strip({}, fix=[{"nodes": {"x_max": "0%"}}],
              output={"paths": {"centre": {"y_min": "50%", "y_max": "50%"}}}),
        "strip.toml",
    )  # fmt: skip
    assert np.array_equal(np.sort(case.fixes[0]["nodes"]), np.sort(case.mesh.nodes("left")))
    assert np.all(case.mesh.points[case.paths["centre"], 1] == 30.0)
    assert np.all(np.diff(case.mesh.points[case.paths["centre"], 0]) > 0)  # along x


# ---------------------------------------------------------------------- paths
def test_a_path_that_is_an_area_is_refused_with_its_nodes_per_position():
    """y_min = "0%" without y_max selects the whole 8 x 2-cell strip: 27 nodes at 9 positions
    along x, which the profiles would zigzag across (s 0, 30, ... on a strip of 200 mm)."""
    data = strip({}, output={"paths": {"edge": {"y_min": "0%"}}})
    with pytest.raises(CaseError) as caught:
        case_from_data(data, "strip.toml")
    said = str(caught.value)
    assert said.startswith("strip.toml: [output.paths.edge]: not a line: 27 of its 27 nodes ")
    assert "share 9 positions along x" in said and "(the first: 3 nodes at x = 0)" in said
    two_rows = strip({}, output={"paths": {"edge": {"y_max": "50%"}}})  # 18 nodes, 2 per x
    with pytest.raises(CaseError, match="18 of its 18 nodes share 9 positions along x"):
        case_from_data(two_rows, "strip.toml")
    one_row = strip({}, output={"paths": {"edge": {"y_max": "0%"}}})
    edge = case_from_data(one_row, "strip.toml").paths["edge"]
    assert len(edge) == 9


def test_a_curved_line_of_nodes_is_a_path_ordered_along_its_longest_extent():
    """A quarter circle's nodes (an arc of a meshed part, in any order) share no position
    along x: a path, ordered by x; a diagonal is ordered along its longer side."""
    angles = np.radians([90.0, 0.0, 30.0, 75.0, 45.0, 10.0, 60.0])
    arc = np.column_stack([50.0 * np.cos(angles), 50.0 * np.sin(angles), np.zeros(7)])
    ordered = order_path(arc, np.arange(7))
    assert np.all(np.diff(arc[ordered, 0]) > 0) and ordered.tolist() == [0, 3, 6, 4, 2, 5, 1]
    diagonal = np.column_stack([np.linspace(0, 10, 5)[::-1], np.linspace(0, 40, 5)[::-1],
                                np.zeros(5)])  # fmt: skip
    assert order_path(diagonal, np.arange(5)).tolist() == [4, 3, 2, 1, 0]
    corner = np.array([[0.0, 0.0, 0.0], [10.0, 0.0, 0.0], [10.0, 5.0, 0.0]])  # a bend: 2 at x=10
    with pytest.raises(BoundsError, match="2 of its 3 nodes share 1 position along x"):
        order_path(corner, np.arange(3))


def test_an_area_on_a_mesh_not_aligned_with_the_axes_is_refused_as_its_order_zigzags():
    """Two rows of a 10 x 4-cell strip turned 3 deg in its plane: no two of their 22 nodes
    share a position along x, and ordered by x they zigzag from row to row (an arc length of
    167 mm along a 100-mm strip): at every inner node the path turns back. One row of it,
    turned alike, is a path."""
    mesh = Mesh.rectangle(100.0, 20.0, nx=10, ny=4)
    turn = np.radians(3.0)
    rotation = np.array([[np.cos(turn), -np.sin(turn), 0], [np.sin(turn), np.cos(turn), 0],
                         [0, 0, 1]])  # fmt: skip
    turned = mesh.points @ rotation.T
    two_rows = np.flatnonzero(mesh.points[:, 1] <= 5.0 + 1e-9)
    assert len(two_rows) == 22
    with pytest.raises(
        BoundsError, match=r"not a line: ordered along x, .* at 20 of its 20 inner nodes"
    ):
        order_path(turned, two_rows)
    one_row = np.flatnonzero(mesh.points[:, 1] <= 1e-9)
    ordered = order_path(turned, one_row)
    assert np.all(np.diff(turned[ordered, 0]) > 0) and len(ordered) == 11


@pytest.mark.parametrize("rows", [3, 5])
def test_areas_of_more_rows_on_a_turned_mesh_are_refused_too(rows):
    # Sorted along x, a 20 x 4-cell mesh turned 2 deg runs column by column and turns back at
    # two nodes of each column only: every such turn is refused, not a share of them (a rule
    # of "more than half" let the whole rectangle through as a path).
    mesh = Mesh.rectangle(100.0, 20.0, nx=20, ny=4)
    turn = np.radians(2.0)
    rotation = np.array([[np.cos(turn), -np.sin(turn), 0], [np.sin(turn), np.cos(turn), 0],
                         [0, 0, 1]])  # fmt: skip
    band = np.flatnonzero(mesh.points[:, 1] <= 5.0 * (rows - 1) + 1e-9)
    with pytest.raises(BoundsError, match="not a line: ordered along x"):
        order_path(mesh.points @ rotation.T, band)


def test_a_corrugation_whose_crests_turn_back_is_given_as_pieces():
    # A triangle wave with 60-deg walls, a node every 1 mm along x: its crests turn back by
    # 120 deg, as two rows of an area do; refused, and each wall alone is a path.
    x = np.arange(9.0)
    z = np.sqrt(3.0) * np.minimum(x % 4, 4 - x % 4)
    wave = np.column_stack([x, np.zeros(9), z])
    with pytest.raises(BoundsError, match="turn back by more than 90 deg at 3 of its 7"):
        order_path(wave, np.arange(9))
    assert order_path(wave, np.arange(3)).tolist() == [0, 1, 2]


# ---------------------------------------------------------------------- errors
def test_an_absolute_bound_past_the_mesh_names_the_set_the_bound_and_the_extent():
    with pytest.raises(CaseError) as caught:
        case_from_data(strip({"tip": {"x_min": 250.0}}), "strip.toml")
    message = str(caught.value)
    assert message.startswith("strip.toml: [sets.tip]: no node within x_min = 250 ")
    assert "the mesh spans x 0 to 200, y 0 to 60, z 0 to 0" in message
    assert '"0%" to "100%", follows the mesh' in message  # the way out


def test_bounds_that_exclude_each_other_are_named_together():
    with pytest.raises(CaseError, match=r"no node within x_min = 50, x_max = 40 together"):
        case_from_data(strip({"gap": {"x_min": 50.0, "x_max": 40.0}}), "strip.toml")


def test_an_empty_relative_set_names_the_share_and_the_coordinate_it_is_at():
    # 8 cells along 200 mm: nodes every 25 mm, none at 10 % (20 mm)
    with pytest.raises(CaseError) as caught:
        case_from_data(strip({"line": {"x_min": "10%", "x_max": "10%"}}), "strip.toml")
    assert "x_min = '10%' (x = 20), x_max = '10%' (x = 20) together" in str(caught.value)
    assert "follows the mesh" not in str(caught.value)  # already relative


@pytest.mark.parametrize(
    "bounds, key, message",
    [
        ({"x_min": "101%"}, "x_min", "from 0% to 100%, got '101%'"),
        ({"x_min": "-1%"}, "x_min", "from 0% to 100%, got '-1%'"),
        ({"y_max": "half"}, "y_max", "a share of the mesh's extent such as \"100%\", got 'half'"),
        ({"z_min": True}, "z_min", "got True"),
        ({"x_min": float("nan")}, "x_min", "got nan"),
        ({"x_min": 0.0, "tolerance": -1.0}, "tolerance", "distance >= 0"),
        ({"x_mn": 0.0}, "x_mn", "unknown key 'x_mn'"),
    ],
)
def test_a_malformed_bound_is_an_error_at_its_own_key(bounds, key, message):
    with pytest.raises(CaseError, match=rf"\[sets\.tip\.{key}\]: .*{message}"):
        case_from_data(strip({"tip": bounds}), "strip.toml")


@pytest.mark.parametrize(
    "tables, at",
    [
        ({"fix": [{"nodes": {}}]}, r"\[fix\[0\]\.nodes\]"),
        ({"fix": [{"nodes": {"tolerance": 1.0}}]}, r"\[fix\[0\]\.nodes\]"),
        ({"displace": [{"nodes": {}, "uz": 1.0}]}, r"\[displace\[0\]\.nodes\]"),
        ({"force": [{"nodes": {}, "vector": [0.0, 0.0, 1.0]}]}, r"\[force\[0\]\.nodes\]"),
        ({"moment": [{"nodes": {}, "vector": [0.0, 0.0, 1.0]}]}, r"\[moment\[0\]\.nodes\]"),
        ({"grip": [{"nodes": {}, "stiffness": 1.0}]}, r"\[grip\[0\]\.nodes\]"),
        ({"contact": [{"tool": "plane", "point": [0.0, 0.0, -1.0], "normal": [0.0, 0.0, 1.0],
                       "nodes": {}}]}, r"\[contact\[0\]\.nodes\]"),
        ({"output": {"paths": {"centre": {}}}}, r"\[output\.paths\.centre\]"),
        ({"sets": {"blank": {}}}, r"\[sets\.blank\]"),
    ],
)  # fmt: skip
def test_an_empty_bounds_table_is_refused_not_read_as_every_node(tables, at):
    # ``nodes = {}`` held no bound, so every node passed: a [[fix]] clamped the whole mesh
    sets = tables.pop("sets", {})
    with pytest.raises(CaseError, match=rf"strip\.toml: {at}: no bound given.*x_min"):
        case_from_data(strip(sets, **tables), "strip.toml")


def test_select_by_bounds_raises_a_value_error_that_names_the_key():
    with pytest.raises(ValueError) as caught:
        select_by_bounds(np.zeros((2, 3)), {"x_min": "200%"})
    assert isinstance(caught.value, BoundsError) and caught.value.key == "x_min"


# ---------------------------------------------------------------------- the shipped cases
def selections(case) -> dict[str, list[int]]:
    """Every node selection of a case: its sets, paths, and the nodes of each table."""
    found = {f"sets.{k}": v for k, v in case.node_sets.items()}
    found.update({f"paths.{k}": v for k, v in case.paths.items()})
    for table in ("fixes", "displacements", "forces", "moments", "grips", "contacts"):
        for i, item in enumerate(getattr(case, table)):
            if item.get("nodes") is not None:
                found[f"{table}[{i}]"] = item["nodes"]
    return {name: sorted(np.asarray(ids).tolist()) for name, ids in found.items()}


@pytest.mark.parametrize("path", sorted(CASES.glob("*.toml")), ids=lambda p: p.name)
def test_every_shipped_case_keeps_its_node_sets_when_its_mesh_is_scaled(path):
    data = read_case_data(path)
    kind = next(iter(data["mesh"]))
    if kind not in ("rectangle", "corner"):
        pytest.skip("a mesh file has no size key to sweep")
    scaled = copy.deepcopy(data)
    for key in ("lx", "ly"):
        scaled["mesh"][kind][key] *= 1.5
    before = selections(case_from_data(data, path))
    assert selections(case_from_data(scaled, path)) == before  # the same nodes by id


# ---------------------------------------------------------------------- nodes no cell uses
# A 20 x 20 mm plate of 2 x 2 quads, and node 999 at (50, 50) that no element uses (a point
# left over in the deck): it carries no DOF, so its displacement reads 0 whatever the load.
STRAY_NODE_DECK = """*Node, nset=allnodes
 101, 0., 0., 0.
 102, 10., 0., 0.
 103, 20., 0., 0.
 201, 0., 10., 0.
 202, 10., 10., 0.
 203, 20., 10., 0.
 301, 0., 20., 0.
 302, 10., 20., 0.
 303, 20., 20., 0.
 999, 50., 50., 0.
*Element, type=S4R, elset=plate
 1, 101, 102, 202, 201
 2, 102, 103, 203, 202
 3, 201, 202, 302, 301
 4, 202, 203, 303, 302
*Nset, nset=edge_and_stray
 103, 203, 303, 999
"""


def plate_with_a_stray_node(tmp_path: Path, sets: dict, **tables) -> dict:
    (tmp_path / "plate.inp").write_text(STRAY_NODE_DECK)
    return {**strip(sets, **tables), "mesh": {"file": "plate.inp"}}


def test_a_share_is_of_the_extent_of_the_nodes_the_cells_use_not_of_a_stray_node(tmp_path):
    """ "100%" was x = 50, node 999 alone (its history 0.0 in every row); "40%" was x >= 20,
    the real edge and node 999 (which pulled the edge's mean deflection down by a quarter)."""
    data = plate_with_a_stray_node(
        tmp_path, {"tip": {"x_min": "100%"}, "outer": {"x_min": "40%"}, "far": {"x_min": 15.0}}
    )
    case = case_from_data(data, tmp_path / "case.toml")
    assert points_of(case, "tip")[:, 0].tolist() == [20.0, 20.0, 20.0]
    assert sorted(set(points_of(case, "outer")[:, 0])) == [10.0, 20.0]  # x >= 8
    assert points_of(case, "far")[:, 0].tolist() == [20.0, 20.0, 20.0]  # absolute: 999 too


def test_bounds_that_hold_only_a_stray_node_select_nothing_and_say_the_cells_extent(tmp_path):
    data = plate_with_a_stray_node(tmp_path, {"corner": {"x_min": 40.0}})
    with pytest.raises(CaseError, match=r"\[sets\.corner\]: no node .* spans x 0 to 20, y 0 to 20"):
        case_from_data(data, tmp_path / "case.toml")


@pytest.mark.parametrize("key", ["displacements", "reactions"])
def test_a_history_set_with_a_node_no_cell_uses_is_refused_naming_the_set(tmp_path, key):
    data = plate_with_a_stray_node(tmp_path, {}, output={"history": {key: ["edge_and_stray"]}})
    with pytest.raises(CaseError) as caught:
        case_from_data(data, tmp_path / "case.toml")
    message = str(caught.value)
    assert f"[output.history.{key}]" in message and "'edge_and_stray'" in message
    assert "[50.0, 50.0, 0.0]" in message and "no cell uses" in message


def test_a_history_set_on_nodes_of_cells_no_part_covers_is_refused_as_the_model_is_built(
    tmp_path,
):
    """A bar (T3D2) of the deck out to node 7 with no cable part: node 7 carries no DOF."""
    text = (
        STRAY_NODE_DECK.replace(" 999, 50., 50., 0.\n", " 999, 50., 50., 0.\n 7, 30., 0., 0.\n")
        + "*Element, type=T3D2, elset=bar\n 9, 103, 7\n*Nset, nset=bar_end\n 7\n"
    )
    (tmp_path / "plate.inp").write_text(text)
    data = {**strip({}, output={"history": {"displacements": ["bar_end"]}}),
            "mesh": {"file": "plate.inp"}}  # fmt: skip
    data["part"][0]["cells"] = "plate"
    case = case_from_data(data, tmp_path / "case.toml")
    refused = r"\[output\.history\.displacements\]: node set 'bar_end' holds 1 node\(s\) that"
    with pytest.raises(CaseError, match=refused + " no part's cells use"):
        case.model()
