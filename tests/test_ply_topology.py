"""The ply contact's per-call work made once (elements/ply_topology.py, elements/ply_fade.py
``OutlineTree``): the same bits as the whole computation it replaces.

References: ``pseudonormals`` over the whole face (np.bincount over every triangle, the
computation the facing call made before), the definition of an edge's neighbour (the other
triangle holding the same edge id), and the nearest outline edge by every pair
(``every_segment``). Exact equality throughout: the contact's answers must be bit-reproducible
and the same as before, so no tolerance.
"""

from __future__ import annotations

import numpy as np

from elements import ply_facets, ply_fade
from elements.ply_projection import edge_ids, open_edges, pseudonormals, pseudonormals_at
from elements.ply_topology import FaceTopology


def _face(seed: int):
    """A wavy 6 x 5 grid of triangles (node ids shuffled), a triangle off it and a third
    triangle on one of its inner edges (an edge of three halves): corners y (m, 3, 3) and
    node ids (m, 3)."""
    rng = np.random.default_rng(seed)
    nx, ny = 6, 5
    u, v = np.meshgrid(np.arange(nx + 1.0), np.arange(ny + 1.0), indexing="ij")
    x = np.column_stack([u.ravel(), v.ravel(), 0.3 * np.sin(u.ravel()) * np.cos(v.ravel())])
    x += rng.normal(0.0, 0.05, x.shape)
    a = (np.arange(nx)[:, None] * (ny + 1) + np.arange(ny)[None, :]).ravel()
    cells = np.vstack(
        [np.column_stack([a, a + ny + 1, a + ny + 2]), np.column_stack([a, a + ny + 2, a + 1])]
    )
    extra = len(x)
    x = np.vstack([x, [[20.0, 0.0, 0.0], [21.0, 0.0, 0.0], [20.0, 1.0, 0.0], [2.0, 2.0, 1.0]]])
    cells = np.vstack([cells, [extra, extra + 1, extra + 2], [cells[0, 0], cells[0, 2], extra + 3]])
    relabel = rng.permutation(len(x))
    nodes = relabel[cells]
    points = np.empty_like(x)
    points[relabel] = x
    return points[nodes], nodes


def test_the_pseudonormals_at_a_few_rows_are_the_whole_face_s_bits():
    for seed in range(3):
        y, nodes = _face(seed)
        topology = FaceTopology.of(nodes, open_edges(nodes))
        vertex, edge = pseudonormals(y, nodes)
        rng = np.random.default_rng(seed)
        vertices = rng.choice(np.unique(nodes), 15)
        halves = rng.integers(0, nodes.size, 25)
        few_vertex, few_edge = pseudonormals_at(y, topology, vertices, halves)
        np.testing.assert_array_equal(few_vertex, vertex[vertices])
        np.testing.assert_array_equal(few_edge, edge.reshape(-1, 3)[halves])
        every_vertex, every_edge = pseudonormals_at(
            y, topology, np.unique(nodes), np.arange(nodes.size)
        )
        np.testing.assert_array_equal(every_vertex, vertex[np.unique(nodes)])
        np.testing.assert_array_equal(every_edge, edge.reshape(-1, 3))


def test_each_half_edge_s_neighbour_holds_the_same_edge():
    _, nodes = _face(0)
    topology = FaceTopology.of(nodes, open_edges(nodes))
    ids = edge_ids(nodes).ravel()
    halves = np.bincount(ids)[ids]
    own = np.arange(ids.size)
    assert np.array_equal(ids[topology.other], ids)
    assert np.array_equal(topology.other == own, halves == 1)
    assert (halves == 3).sum() == 3 and (halves == 1).sum() > 0
    # the outline's ends and the edges' tables as defined
    outline = open_edges(nodes)
    assert np.array_equal(topology.edge_halves[ids, 0] <= own, np.ones(ids.size, dtype=bool))
    rows, ends = ply_fade.outline_segments(outline)
    assert np.array_equal(topology.segment_rows, rows)
    assert np.array_equal(np.flatnonzero(topology.rim), np.unique(nodes[rows[:, None], ends]))


def test_a_kept_outline_tree_answers_as_every_pair_while_the_outline_moves():
    rng = np.random.default_rng(5)
    starts = rng.uniform(-100.0, 100.0, (300, 3))
    ends = starts + rng.uniform(-6.0, 6.0, (300, 3))
    kept = ply_fade.OutlineTree()
    calls = 0
    for scale in (1e-4, 1e-3, 0.05, 2.0):  # moves far below, near and above TREE_MOVE
        for _ in range(6):
            starts = starts + rng.normal(0.0, scale, starts.shape)
            ends = ends + rng.normal(0.0, scale, ends.shape)
            p = np.vstack([rng.uniform(-100.0, 100.0, (200, 3)), starts[:40] + 1e-7])
            found = ply_fade.nearest_segments(p, starts, ends, kept)
            np.testing.assert_array_equal(found, ply_fade.every_segment(p, starts, ends))
            calls += 1
    # the tree served the small moves and was built again for the large ones
    assert 1 < kept.builds < calls


def test_a_stepped_two_ply_model_is_as_with_the_whole_face_computed_at_each_call(monkeypatch):
    """Facing, forces and energies of the two-ply Mindlin [0/90] hemisphere's contacts
    (validation/studies/hemisphere_plies_setup.py, 10 cells) over steps of a rough layup,
    against the same blocks with the pseudonormals of the whole face at each call and no
    kept outline tree. Every nearest outline edge by a tree (``EVERY_PAIR`` 0: the model's
    40 outline edges would otherwise be measured pair by pair and no tree used), each
    block's kept tree built at least once."""
    from elements.ply_block import PlyContactBlock
    from femcore.state import State
    from validation.studies import hemisphere_plies_setup as setup

    monkeypatch.setattr(ply_fade, "EVERY_PAIR", 0)
    _, model = setup.model(10, setup.LAYUPS["0/90"], "mindlin", 20.0)
    compiled = model.compile()
    blocks = [b for b in compiled.interactions if isinstance(b, PlyContactBlock)]
    n = compiled.mesh.n_nodes
    rng = np.random.default_rng(11)
    rough = compiled.mesh.points + rng.normal(0.0, 0.2, (n, 3))
    directors = np.tile([0.0, 0.0, 1.0], (n, 1))
    zero = np.zeros((n, 3))

    def whole(y, topology, vertices, halves):
        vertex, edge = pseudonormals(y, topology.nodes, topology.edges)
        return vertex[vertices], edge.reshape(-1, 3)[halves]

    edged = 0
    for step in range(8):
        x = rough + rng.normal(0.0, 1e-3, (n, 3))
        x[:, 2] -= 0.01 * step
        state = State(x, directors, zero, zero)
        answers = []
        for reference in (False, True):
            if reference:
                monkeypatch.setattr(ply_facets, "pseudonormals_at", whole)
            found = []
            for block in blocks:
                tree = block.outline_tree
                if reference:
                    block.outline_tree = None
                block._facing_at = None
                facing = block.facing(state, second=True)
                block._facing_at = None
                found.append((facing, block.internal_force(state), block.strain_energy(state)))
                block.outline_tree = tree
            answers.append(found)
        monkeypatch.setattr(ply_facets, "pseudonormals_at", pseudonormals_at)
        for (facing, force, energy), (ref_facing, ref_force, ref_energy) in zip(*answers):
            edged += int(np.count_nonzero(np.any(facing.weights < -1e-9, axis=1)))
            for name, value in vars(ref_facing).items():
                if isinstance(value, np.ndarray):
                    np.testing.assert_array_equal(getattr(facing, name), value, err_msg=name)
            np.testing.assert_array_equal(force[0], ref_force[0])
            np.testing.assert_array_equal(force[1], ref_force[1])
            assert energy == ref_energy
    assert edged > 50  # points off their triangles: edges' and vertices' pseudonormals read
    assert all(block.outline_tree.builds >= 1 for block in blocks)  # the kept tree answered


def test_a_kept_tree_s_bound_takes_the_samples_move():
    """Dense short segments, each moved by just under ``TREE_MOVE`` of the kept tree's bound
    in its own direction: the tree serves (one build), and its answers are every pair's
    only with the bound widened by the move (without it, points of this draw went to a
    farther segment: the test fails, at 5 of its 25 moves; 24 of 100 over 20 draws)."""
    rng = np.random.default_rng(1)
    for _ in range(5):
        starts = rng.uniform(0.0, 10.0, (400, 3)) * [1.0, 1.0, 0.1]
        ends = starts + rng.normal(0.0, 0.7, (400, 3))
        kept = ply_fade.OutlineTree()
        ply_fade.nearest_segments(rng.uniform(0.0, 10.0, (3000, 3)), starts, ends, kept)
        half = kept.half
        for _ in range(5):
            way = rng.normal(0.0, 1.0, (400, 3))
            way *= 0.24 * half / np.linalg.norm(way, axis=1)[:, None]
            p = rng.uniform(0.0, 10.0, (3000, 3)) * [1.0, 1.0, 0.1]
            moved_starts, moved_ends = starts + way, ends + way
            found = ply_fade.nearest_segments(p, moved_starts, moved_ends, kept)
            every = ply_fade.every_segment(p, moved_starts, moved_ends)
            np.testing.assert_array_equal(found, every)
        assert kept.builds == 1
