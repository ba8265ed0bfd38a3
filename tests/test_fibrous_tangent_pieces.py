"""elements/fibrous/tangent_pieces.py: the fibrous shell's tangent a run of rows at a time
sums to its whole tangent (elements/fibrous/tangent.py), and the explicit solver's Gershgorin
bound streamed from the pieces (femcore/gershgorin.py) is the bound of the whole tangent.

The pieces add the membrane's and the bending's blocks of a node pair before the generalised
coordinates are taken, where ``tangent`` gives them as two parts, so the two agree to
round-off: 1e-12 of the largest entry (the entries are sums of at most a few hundred terms of
one sign of magnitude, each rounded at 1e-16). Each piece's rows are summed as the whole
tangent formed at once sums them, so pieces of any size give the same rows and the same bound
to the last bit."""

import dataclasses

import numpy as np
import pytest

from elements import FibrousShell
from elements.base import SparseTangent
from elements.fibrous import hessian_kernels, tangent_pieces
from femcore import Mesh, Model
from femcore import gershgorin as gershgorin_module
from femcore.assembly import tangent_matrix
from femcore.gershgorin import gershgorin_largest
from femcore.rotation import rotate_about
from materials import presets


def jittered_sheet(clamped: bool):
    """A 160-cell fibrous sheet (nodal normals) jittered, its directors tilted; ``clamped``:
    its left edge bends against a wall (wall nodes: normal sums held)."""
    mesh = Mesh.rectangle(40.0, 30.0, nx=10, ny=8)
    model = Model(mesh)
    options = {"clamped": "left"} if clamped else {}
    model.add(FibrousShell(presets.g986_stack(), **options))
    model.fix("left")
    compiled = model.compile()
    state = compiled.initial_state()
    rng = np.random.default_rng(6)
    positions = state.positions + rng.normal(scale=0.3, size=state.positions.shape)
    turn = np.cross(state.directors, rng.normal(scale=0.2, size=state.positions.shape))
    directors = rotate_about(state.directors, turn)
    return compiled, dataclasses.replace(state, positions=positions, directors=directors)


def small_pieces(monkeypatch, nodes: int) -> None:
    """Pieces of ``nodes`` nodes whatever the model's size."""
    monkeypatch.setattr(tangent_pieces, "PIECE", nodes)
    monkeypatch.setattr(tangent_pieces, "PIECE_MIN", nodes)


@pytest.mark.parametrize("clamped", [False, True], ids=["free", "clamped"])
def test_the_pieces_sum_to_the_whole_tangent(monkeypatch, clamped):
    # Pieces of 20 nodes on the 99-node sheet (rows of 11 nodes): 5 runs, each piece's
    # membrane reaching three rings of nodes around the run; Hessians 10 cells at a time.
    small_pieces(monkeypatch, 20)
    monkeypatch.setattr(tangent_pieces, "_HESSIANS", 10)
    compiled, state = jittered_sheet(clamped)
    block = compiled.blocks[0]
    pieces = list(block.tangent_pieces(state))
    assert len(pieces) == 5
    assert all(isinstance(piece, SparseTangent) for piece in pieces)
    frames = compiled.dofs.frames(state.directors)
    whole = tangent_matrix(compiled.dofs, block.tangent(state), frames).toarray()
    summed = tangent_matrix(compiled.dofs, pieces, frames).toarray()
    assert np.abs(summed - whole).max() <= 1e-12 * np.abs(whole).max()
    # A piece left out is seen: each carries its slice's share.
    fewer = tangent_matrix(compiled.dofs, pieces[1:], frames).toarray()
    assert np.abs(fewer - whole).max() > 1e-3 * np.abs(whole).max()


def test_the_streamed_bound_is_the_whole_tangents(monkeypatch):
    """The model's assembled stable step streams the pieces (each node's row summed as the
    pieces leave it): the number of the same pieces with every pair held to the last bit,
    and the whole tangent's to 1e-12."""
    small_pieces(monkeypatch, 20)
    compiled, state = jittered_sheet(True)
    block = compiled.blocks[0]
    pieces = list(block.tangent_pieces(state))
    rng = np.random.default_rng(2)
    scale = np.zeros(compiled.dofs.n_slots)
    free = compiled.dofs.free_slots
    scale[free] = rng.uniform(0.5, 2.0, size=free.size)
    maps = compiled.dofs.node_maps(compiled.dofs.frames(state.directors))
    n = compiled.n_nodes
    held = gershgorin_largest(pieces, maps, scale, n)
    streamed = gershgorin_module._streamed(pieces, maps, scale, n)
    assert streamed is not None  # streamed, not made again with every pair held
    assert streamed == held
    whole = gershgorin_largest(block.tangent(state), maps, scale, n)
    assert held == pytest.approx(whole, rel=1e-12, abs=0.0)

    mass, inertia = compiled.lumped_mass(state)
    diagonal = np.column_stack([mass, mass, mass, inertia, inertia]).ravel()[free]
    scale[:] = 0.0
    scale[free] = 1.0 / np.sqrt(diagonal)
    expected = 2.0 / np.sqrt(gershgorin_largest(block.tangent(state), maps, scale, n))
    step = compiled.assembled_stable_dt(state, mass, inertia)
    assert step == pytest.approx(expected, rel=1e-12, abs=0.0)


def test_the_bound_does_not_depend_on_the_pieces(monkeypatch):
    """Pieces of 1, 7, 20 and 99 nodes (the whole sheet) give the same rows and the same
    bound to the last bit: a node pair's blocks are summed over every cell around in the
    cells' order whatever the run. (Slices of cells summed piece by piece, as before, moved
    the bound in its last bit between pieces of 7 and of 37 cells on this sheet.)"""
    compiled, state = jittered_sheet(True)
    block = compiled.blocks[0]
    rng = np.random.default_rng(2)
    scale = np.zeros(compiled.dofs.n_slots)
    free = compiled.dofs.free_slots
    scale[free] = rng.uniform(0.5, 2.0, size=free.size)
    maps = compiled.dofs.node_maps(compiled.dofs.frames(state.directors))
    bounds, rows = [], []
    for nodes in (1, 7, 20, 99):
        small_pieces(monkeypatch, nodes)
        pieces = list(block.tangent_pieces(state))
        assert len(pieces) == -(-compiled.n_nodes // nodes)
        bounds.append(gershgorin_largest(pieces, maps, scale, compiled.n_nodes))
        # The runs' rows are disjoint: their sum is each entry of one piece, unrounded.
        summed = sum(piece.matrix.tocsr() for piece in pieces)
        rows.append(summed.toarray())
    assert bounds == [bounds[-1]] * 4
    for other in rows[:-1]:
        np.testing.assert_array_equal(other, rows[-1])


def test_runs_follow_the_cells_whatever_the_node_numbering(monkeypatch):
    """The sheet with its nodes numbered at random: the runs are taken in the order of the
    cells (the first cell at each node), so a run of 20 nodes reaches the nodes of the cells
    around it (at most 42 of the 99 here), not those of cells all over the sheet (runs of 20
    node numbers: 70 to 83), its pieces' rows reach the nodes of those cells and form their
    Hessians alone, and the bound is the same to the last bit as with one piece."""
    mesh = Mesh.rectangle(40.0, 30.0, nx=10, ny=8)
    shuffle = np.random.default_rng(4).permutation(mesh.n_nodes)  # new number of each node
    points = np.empty_like(mesh.points)
    points[shuffle] = mesh.points
    shuffled = Mesh(points, shuffle[mesh.triangles])
    model = Model(shuffled)
    model.add(FibrousShell(presets.g986_stack()))
    model.fix(np.flatnonzero(points[:, 0] == 0.0))
    compiled = model.compile()
    block = compiled.blocks[0]
    small_pieces(monkeypatch, 20)
    conn, n = block.connectivity, compiled.n_nodes
    around = tangent_pieces._NodeCells(conn, n)
    order = np.argsort(tangent_pieces._first_cells(conn, n), kind="stable")
    by_cells = [
        tangent_pieces._ring(conn, around, np.sort(order[i : i + 20])) for i in range(0, n, 20)
    ]
    by_number = [
        tangent_pieces._ring(conn, around, np.arange(i, min(i + 20, n))) for i in range(0, n, 20)
    ]
    assert max(len(ring) for ring in by_cells) <= 45
    assert min(len(ring) for ring in by_number) >= 70
    # tangent_pieces itself: each piece's rows reach at most 64 of the 99 nodes (runs of
    # node numbers: 92 to 97), and the Hessians of 235 cells are formed for the 160 (each
    # run's ring's; runs of node numbers: 371).
    formed = []
    membrane_hessians = hessian_kernels.membrane_hessians

    def counted(block, x, *args):
        formed.append(len(x))
        return membrane_hessians(block, x, *args)

    monkeypatch.setattr(hessian_kernels, "membrane_hessians", counted)
    state = compiled.initial_state()
    pieces = list(block.tangent_pieces(state))
    assert len(pieces) == 5
    assert max(len(np.unique(piece.matrix.indices)) for piece in pieces) <= 66
    assert sum(formed) <= 1.6 * len(conn)
    monkeypatch.setattr(hessian_kernels, "membrane_hessians", membrane_hessians)
    mass, inertia = compiled.lumped_mass(state)
    step = compiled.assembled_stable_dt(state, mass, inertia)
    small_pieces(monkeypatch, n)
    assert compiled.assembled_stable_dt(state, mass, inertia) == step


def test_a_piece_is_a_share_of_the_model():
    """A piece's nodes follow the model's size between PIECE_MIN and PIECE (its work arrays a
    small part of the model's memory, benchmarks/model_memory.py)."""
    assert tangent_pieces.piece_nodes(10) == tangent_pieces.PIECE_MIN
    assert tangent_pieces.piece_nodes(10**7) == tangent_pieces.PIECE
    middle = tangent_pieces.PIECE_SHARE * (tangent_pieces.PIECE_MIN + tangent_pieces.PIECE) // 2
    assert tangent_pieces.piece_nodes(middle) == middle // tangent_pieces.PIECE_SHARE


def test_element_normals_give_the_whole_tangent():
    mesh = Mesh.rectangle(40.0, 30.0, nx=4, ny=3)
    model = Model(mesh)
    model.add(FibrousShell(presets.g986_stack(), thickness="element"))
    compiled = model.compile()
    state = compiled.initial_state()
    block = compiled.blocks[0]
    pieces = list(block.tangent_pieces(state))
    whole = block.tangent(state)
    assert len(pieces) == len(whole)
    for piece, part in zip(pieces, whole):
        np.testing.assert_array_equal(piece.blocks, part.blocks)
