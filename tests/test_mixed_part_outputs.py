"""A case of a fibrous part and a Mindlin part on shared nodes writes what each part defines
and nothing else: each block's nodal fields (``thickness``, ``director_tilt_deg``; the
second block's ``thickness_2``, ``director_tilt_deg_2``) are NaN off the block's nodes, not
0.0 (which ParaView and a min over the nodes read as a value); summary.json's tilt range is
over the nodes where a tilt is defined, every block's; and the run is called "mixed", with
its parts' elements, not "fibrous".

Before, the Mindlin-only nodes read thickness 0.0 and tilt 0.0, the summary's tilt min was
0.0 and summary.json said "kinematics": "fibrous"."""

import json
from xml.etree import ElementTree

import meshio
import numpy as np
import pytest

from fibreshell.case import load_case
from fibreshell.run import run_case

# A 100 x 10 mm strip of four 25 mm quads (each split in two triangles): NEAR the two at
# x < 50 (fibrous, clamped at x = 0), FAR the two at x > 50 (Mindlin); nodes 3 and 8
# (1-based) at x = 50 are shared.
DECK = """*NODE
1, 0.0, 0.0, 0.0
2, 25.0, 0.0, 0.0
3, 50.0, 0.0, 0.0
4, 75.0, 0.0, 0.0
5, 100.0, 0.0, 0.0
6, 0.0, 10.0, 0.0
7, 25.0, 10.0, 0.0
8, 50.0, 10.0, 0.0
9, 75.0, 10.0, 0.0
10, 100.0, 10.0, 0.0
*ELEMENT, TYPE=S4R, ELSET=NEAR
1, 1, 2, 7, 6
2, 2, 3, 8, 7
*ELEMENT, TYPE=S4R, ELSET=FAR
3, 3, 4, 9, 8
4, 4, 5, 10, 9
*NSET, NSET=LEFT
1, 6
"""

CASE = """title = "mixed strip"
[mesh]
file = "strip.inp"
[[part]]
element = "fibrous"
material = "g986_stack"
cells = "NEAR"
options = { clamped = "LEFT" }
[[part]]
element = "mindlin"
material = "g986_stack"
cells = "FAR"
[[fix]]
nodes = "LEFT"
[gravity]
acceleration = [0.0, 0.0, -9810.0]
[solver]
kind = "static"
increments = 2
"""


def test_a_fibrous_and_a_mindlin_part_write_nan_where_a_field_is_not_theirs(tmp_path):
    (tmp_path / "strip.inp").write_text(DECK)
    (tmp_path / "case.toml").write_text(CASE)
    out = tmp_path / "out"
    run = run_case(load_case(tmp_path / "case.toml"), out, progress=False)
    assert run.status == "done"
    last = list(ElementTree.parse(out / "result.pvd").getroot().iter("DataSet"))[-1]
    frame = meshio.read(out / last.get("file"))
    x = frame.points[:, 0]
    fibrous, mindlin = x <= 50.0, x >= 50.0
    fields = frame.point_data
    for first, second in (
        ("thickness", "thickness_2"),
        ("director_tilt_deg", "director_tilt_deg_2"),
    ):
        assert np.isfinite(fields[first][fibrous]).all() and np.isnan(fields[first][~fibrous]).all()
        assert np.isfinite(fields[second][mindlin]).all()
        assert np.isnan(fields[second][~mindlin]).all()
    summary = json.loads((out / "summary.json").read_text())
    assert summary["kinematics"] == "mixed" and summary["parts"] == ["fibrous", "mindlin"]
    free = x > 0.0  # the clamped nodes' directors are held: left out of the range
    tilts = np.concatenate(
        [fields[name][free & np.isfinite(fields[name])]
         for name in ("director_tilt_deg", "director_tilt_deg_2")]
    )  # fmt: skip
    assert summary["director_tilt_deg"]["min"] == tilts.min() > 0.0
    assert summary["director_tilt_deg"]["max"] == tilts.max()


def test_a_path_across_both_parts_reads_each_nodes_thickness_from_its_own_part(tmp_path):
    # The paths' thickness read the first block's field alone: null (NaN) at the Mindlin
    # part's nodes. Each node's thickness is its own part's: the fibrous h_m where the
    # fibrous part holds the node (the shared nodes too), the Mindlin section's 6 mm beyond.
    (tmp_path / "strip.inp").write_text(DECK)
    (tmp_path / "case.toml").write_text(CASE + '[output]\npaths = { side = { y_max = "0%" } }\n')
    out = tmp_path / "out"
    run = run_case(load_case(tmp_path / "case.toml"), out, progress=False)
    side = json.loads((out / "summary.json").read_text())["paths"]["side"]
    assert run.status == "done" and None not in side["thickness"]
    s, thickness = np.asarray(side["s"]), np.asarray(side["thickness"])
    assert thickness[s > 50.0] == pytest.approx(6.0)  # g986_stack's section, Mindlin
    assert (thickness[s <= 50.0] >= 6.0).all()  # the fibrous part's h_m, from 6 mm
