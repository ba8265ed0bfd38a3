"""A body in several connected parts: each part is a free body of its own, so the supports of
one hold nothing of another. The check names the part nothing holds (its node count and its
first nodes) and its free motions (femcore.connected_parts, femcore.diagnostics).

Reference: statics. A body that no element or interaction joins to a supported one is in
equilibrium only if its own loads do no work along its own six rigid motions; two strips 10 mm
apart, the first clamped and the second loaded at its free end along z, leave the second free
to translate along z (its net force) and to turn about y (the force's moment about its
centroid)."""

import numpy as np
import pytest

from elements import MindlinShell
from femcore import Mesh, Model
from materials import ElasticShell
from solvers import DynamicRelaxation, Static


def two_strips(clamp_second: bool = False) -> Model:
    """Two 100 x 40 mm strips side by side along x, 10 mm apart and not joined: the first
    clamped at its left edge, the second loaded at its right edge by 1e-3 N a node down."""
    strip = Mesh.rectangle(100.0, 40.0, nx=4, ny=2)
    points = np.vstack([strip.points, strip.points + [110.0, 0.0, 0.0]])
    mesh = Mesh(points, triangles=np.vstack([strip.triangles, strip.triangles + strip.n_nodes]))
    model = Model(mesh)
    model.add(MindlinShell(ElasticShell(E=1000.0, nu=0.3, thickness=1.0, density=1e-9)))
    model.fix(strip.nodes("left"))
    if clamp_second:
        model.fix(strip.nodes("left") + strip.n_nodes)
    model.force(strip.nodes("right") + strip.n_nodes, (0.0, 0.0, -0.001))
    return model


def test_the_unsupported_part_is_named_with_its_free_motions():
    motions = two_strips().compile().unheld_rigid_motions()
    assert len(motions) == 1  # the clamped strip is held: only the second is reported
    assert motions[0].startswith("translation along z, rotation about y of the part of 15 nodes")
    assert "15, 16, 17" in motions[0] and "29" in motions[0]
    assert "one of 2 parts" in motions[0]


def test_every_free_motion_of_the_unloaded_part_is_listed_when_loads_do_not_matter():
    motions = two_strips().compile().unheld_rigid_motions(loaded_only=False)
    assert len(motions) == 1
    for name in ("translation along x", "translation along y", "rotation about z"):
        assert name in motions[0]


@pytest.mark.parametrize(
    "solver",
    [Static(progress=False), DynamicRelaxation(progress=False)],
    ids=["static", "relaxation"],
)
def test_the_solvers_refuse_a_free_part_before_iterating(solver):
    # Static stopped after 8 cuts with "a limit point or buckling may be near".
    with pytest.raises(ValueError, match=r"translation along z of the part of 15 nodes 15, 16"):
        solver.solve(two_strips())


def test_two_parts_each_clamped_are_held():
    assert two_strips(clamp_second=True).compile().unheld_rigid_motions(loaded_only=False) == []


def test_many_free_parts_are_named_up_to_five_and_the_rest_counted():
    # Eight squares side by side (a mesh whose facets were never merged), the first clamped,
    # all under gravity: seven fall, five are named and two counted.
    square = Mesh.rectangle(10.0, 10.0, nx=2, ny=2)
    points = np.vstack([square.points + [12.0 * i, 0.0, 0.0] for i in range(8)])
    cells = np.vstack([square.triangles + square.n_nodes * i for i in range(8)])
    model = Model(Mesh(points, triangles=cells))
    model.add(MindlinShell(ElasticShell(E=1000.0, nu=0.3, thickness=1.0, density=1e-9)))
    model.fix(np.arange(square.n_nodes))
    model.gravity((0.0, 0.0, -9810.0))
    motions = model.compile().unheld_rigid_motions()
    assert len(motions) == 6 and motions[-1] == "and 2 more parts so"
    assert motions[0].startswith("translation along z of the part of 9 nodes 9, 10, 11")
