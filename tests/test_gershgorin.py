"""femcore.gershgorin: the explicit solver's Gershgorin bound summed per node pair without a
sparse assembly equals the row sums of the assembled |K| (femcore.assembly.tangent_matrix)."""

import dataclasses

import numpy as np
import pytest

from elements import Cable, FibrousShell, MindlinShell
from femcore import Mesh, Model
from femcore.assembly import SparseTangent, tangent_matrix
from femcore.gershgorin import gershgorin_largest
from femcore.rotation import rotate_about
from materials import ElasticShell, presets


def bent_plate():
    mesh = Mesh.rectangle(40.0, 30.0, nx=5, ny=4)
    model = Model(mesh)
    model.add(MindlinShell(ElasticShell(70e3, 0.3, 1.0, 2.7e-9)))
    model.fix("left")
    model.fix("bottom", ["uz", "alpha"])
    compiled = model.compile()
    state = compiled.initial_state()
    rng = np.random.default_rng(4)
    positions = state.positions + rng.normal(scale=0.3, size=state.positions.shape)
    turn = np.cross(state.directors, rng.normal(scale=0.2, size=state.positions.shape))
    directors = rotate_about(state.directors, turn)
    return compiled, dataclasses.replace(state, positions=positions, directors=directors)


def hanging_cable():
    mesh = Mesh.line((0.0, 0.0, 0.0), (100.0, 0.0, 0.0), 12)
    model = Model(mesh)
    model.add(Cable(axial_stiffness=5e3, mass_per_length=1e-6))
    model.fix("start")
    compiled = model.compile()
    state = compiled.initial_state()
    stretched = state.positions * np.array([1.01, 1.0, 1.0]) + np.array([0.0, 0.0, 0.5])
    return compiled, dataclasses.replace(state, positions=stretched)


def sheared_fabric():
    mesh = Mesh.rectangle(40.0, 30.0, nx=5, ny=4)
    model = Model(mesh)
    model.add(FibrousShell(presets.g986_stack()))
    model.fix("left")
    compiled = model.compile()
    state = compiled.initial_state()
    rng = np.random.default_rng(6)
    positions = state.positions + rng.normal(scale=0.3, size=state.positions.shape)
    return compiled, dataclasses.replace(state, positions=positions)


def assembled(compiled, state, parts, scale):
    """The same bound from the assembled sparse tangent."""
    stiffness = tangent_matrix(compiled.dofs, parts, compiled.dofs.frames(state.directors))
    free = compiled.dofs.free_slots
    rows = np.asarray(abs(stiffness) @ scale).ravel()[free] * scale[free]
    return float(rows.max())


@pytest.mark.parametrize(
    "example", [bent_plate, hanging_cable, sheared_fabric], ids=["mindlin", "cable", "fibrous"]
)
def test_the_bound_summed_per_node_pair_is_the_assembled_one(example):
    """Rotations with fixed alpha / beta and turned directors (the plate), translations only
    (the cable), cell and sparse parts (the fibrous shell's bending): the same bound to
    1e-12."""
    compiled, state = example()
    parts = compiled.tangent_parts(state, list(range(len(compiled.parts))))
    assert parts is not None
    rng = np.random.default_rng(1)
    scale = np.zeros(compiled.dofs.n_slots)
    free = compiled.dofs.free_slots
    scale[free] = rng.uniform(0.5, 2.0, size=free.size)
    maps = compiled.dofs.node_maps(compiled.dofs.frames(state.directors))
    largest = gershgorin_largest(parts, maps, scale, compiled.n_nodes)
    reference = assembled(compiled, state, parts, scale)
    assert largest == pytest.approx(reference, rel=1e-12)
    assert largest > 0.0


def test_a_block_sparse_tangent_gives_the_bound_of_its_general_sparse_form():
    # The fibrous membrane's SparseTangent comes in BSR with 6 x 6 node blocks, read block by
    # block; the same matrix in CSR goes through scipy's T^T K T. Turned directors (node maps
    # that mix alpha and beta), a clamped edge (columns off the free slots): the same bound
    # to round-off.
    compiled, state = sheared_fabric()
    rng = np.random.default_rng(3)
    turn = np.cross(state.directors, rng.normal(scale=0.3, size=state.positions.shape))
    state = dataclasses.replace(state, directors=rotate_about(state.directors, turn))
    parts = compiled.tangent_parts(state, [0])
    sparse = [part for part in parts if isinstance(part, SparseTangent)]
    assert sparse and all(part.matrix.format == "bsr" for part in sparse)
    general = [
        SparseTangent(part.matrix.tocsr()) if isinstance(part, SparseTangent) else part
        for part in parts
    ]
    scale = np.zeros(compiled.dofs.n_slots)
    free = compiled.dofs.free_slots
    scale[free] = rng.uniform(0.5, 2.0, size=free.size)
    maps = compiled.dofs.node_maps(compiled.dofs.frames(state.directors))
    largest = gershgorin_largest(parts, maps, scale, compiled.n_nodes)
    assert largest == pytest.approx(
        gershgorin_largest(general, maps, scale, compiled.n_nodes), rel=1e-12
    )
    assert largest == pytest.approx(assembled(compiled, state, parts, scale), rel=1e-12)


def mindlin_pieces(patch, size):
    """Mindlin pieces of ``size`` cells, shorter than the cells' band or not
    (``banded_piece`` left out)."""
    from elements import mindlin

    patch.setattr(mindlin, "_PIECE", size)
    patch.setattr(mindlin, "banded_piece", lambda connectivity, cells: cells)


def test_the_mindlin_tangent_in_pieces_is_its_tangent(monkeypatch):
    """tangent_pieces gives the blocks of tangent a slice of cells at a time, and the
    model's assembled step from them is the one of the whole tangent."""
    mindlin_pieces(monkeypatch, 7)  # pieces of 7 cells on the 40-cell plate
    compiled, state = bent_plate()
    block = compiled.blocks[0]
    pieces = list(block.tangent_pieces(state))
    assert len(pieces) == 6
    whole = block.tangent(state)[0]
    np.testing.assert_array_equal(np.concatenate([p.nodes for p in pieces]), whole.nodes)
    # (numpy's batched products may round differently in batches of other sizes)
    blocks = np.concatenate([p.blocks for p in pieces])
    assert np.abs(blocks - whole.blocks).max() <= 1e-13 * np.abs(whole.blocks).max()
    mass, inertia = compiled.lumped_mass(state)
    free = compiled.dofs.free_slots
    diagonal = np.column_stack([mass, mass, mass, inertia, inertia]).ravel()[free]
    scale = np.zeros(compiled.dofs.n_slots)
    scale[free] = 1.0 / np.sqrt(diagonal)
    expected = 2.0 / np.sqrt(assembled(compiled, state, [whole], scale))
    step = compiled.assembled_stable_dt(state, mass, inertia)
    assert step == pytest.approx(expected, rel=1e-12)


def _plate_in_pieces(monkeypatch, size=14):
    """The bent plate's tangent in pieces of ``size`` cells at its state, node maps and a
    scale per free slot. Its 40 cells come in rows of 10, so that the cells around a node
    span at most 13 consecutive ones: a piece of 14 cells cannot fall between two of them."""
    mindlin_pieces(monkeypatch, size)
    compiled, state = bent_plate()
    block = compiled.blocks[0]
    rng = np.random.default_rng(2)
    scale = np.zeros(compiled.dofs.n_slots)
    free = compiled.dofs.free_slots
    scale[free] = rng.uniform(0.5, 2.0, size=free.size)
    maps = compiled.dofs.node_maps(compiled.dofs.frames(state.directors))
    return compiled, state, list(block.tangent_pieces(state)), maps, scale


def test_rows_summed_as_the_pieces_leave_their_nodes_give_the_same_bound(monkeypatch):
    """The pieces of consecutive cells: each node's row summed once no later piece holds it
    (``_summed`` with ``stream``), the pairs of the pieces around it alone held; the same
    number to the last bit as with every pair held, and the assembled bound to 1e-12."""
    from femcore import gershgorin

    compiled, state, pieces, maps, scale = _plate_in_pieces(monkeypatch)
    assert len(pieces) == 3
    n = compiled.n_nodes
    held = gershgorin_largest(pieces, maps, scale, n)
    streamed = gershgorin._streamed(pieces, maps, scale, n)
    assert streamed is not None
    assert streamed == held
    assert gershgorin_largest(pieces, maps, scale, n, again=lambda: pieces) == held
    assert held == pytest.approx(assembled(compiled, state, pieces, scale), rel=1e-12)


def test_the_bound_does_not_depend_on_the_pieces():
    """Each node's row alone (the scale 0 off its slots: the bound is then its diagonal block,
    the sum of the cells around it) from the Mindlin tangent in pieces of 1, 3, 7 and 40
    cells: the same to the last bit, a pair's blocks added in the cells' order onto its sum
    so far whatever the pieces. (Each piece's own sums added to the held ones, as before,
    moved 6 of the 30 nodes' blocks in their last bits.)"""
    compiled, state = bent_plate()
    block = compiled.blocks[0]
    maps = compiled.dofs.node_maps(compiled.dofs.frames(state.directors))
    parted = {}
    for size in (1, 3, 7, 40):
        with pytest.MonkeyPatch.context() as patch:
            mindlin_pieces(patch, size)
            parted[size] = list(block.tangent_pieces(state))
        assert len(parted[size]) == -(-40 // size)
    for node in range(compiled.n_nodes):
        scale = np.zeros(compiled.dofs.n_slots)
        scale[5 * node : 5 * node + 5] = [1.0, 0.7, 1.3, 0.9, 1.1]
        # every pair held, and streamed (made again with every pair held where it cannot be)
        bounds = {
            gershgorin_largest(pieces, maps, scale, compiled.n_nodes, again=again)
            for pieces in parted.values()
            for again in (None, lambda pieces=pieces: pieces)
        }
        assert len(bounds) == 1 and bounds != {0.0}


def test_a_mindlin_piece_is_a_share_of_the_model(monkeypatch):
    """The Mindlin pieces follow the model's size between _PIECE_MIN and _PIECE cells."""
    from elements import mindlin

    compiled, state = bent_plate()
    block = compiled.blocks[0]
    monkeypatch.setattr(mindlin, "banded_piece", lambda connectivity, cells: cells)
    monkeypatch.setattr(mindlin, "_PIECE_MIN", 4)
    monkeypatch.setattr(mindlin, "_PIECE_SHARE", 8)
    assert [len(p.nodes) for p in block.tangent_pieces(state)] == [5] * 8  # 40 // 8
    monkeypatch.setattr(mindlin, "_PIECE_MIN", 10)
    assert [len(p.nodes) for p in block.tangent_pieces(state)] == [10] * 4
    monkeypatch.setattr(mindlin, "_PIECE", 3)
    assert len(list(block.tangent_pieces(state))) == 14


def test_a_piece_holding_a_node_already_summed_makes_the_bound_again(monkeypatch):
    """Pieces in an order that comes back to a node whose row was summed: the streamed sums
    give up and the bound is made again from ``again()`` with every pair held: the number
    of the held sums of the same pieces."""
    from femcore import gershgorin

    compiled, _, pieces, maps, scale = _plate_in_pieces(monkeypatch, 7)
    shuffled = [pieces[k] for k in (0, 3, 1, 5, 2, 4)]
    n = compiled.n_nodes
    assert gershgorin._streamed(shuffled, maps, scale, n) is None
    asked = []

    def again():
        asked.append(True)
        return iter(shuffled)

    held = gershgorin_largest(shuffled, maps, scale, n)
    assert gershgorin_largest(iter(shuffled), maps, scale, n, again=again) == held
    assert asked == [True]


def test_every_pair_held_is_work_in_the_pieces_pairs(monkeypatch):
    """Every pair held (no ``again``, or streaming given up): each piece's pairs found by key
    in a table of the pairs so far, their sums taken and put back; no merge of each piece
    into all the pairs so far (work pieces x pairs: 12 s against 2.7 for a 44.8k-cell
    fibrous sheet as two blocks). The plate in 40 pieces of one cell: 9 pairs taken a piece,
    the slots grown a few times (doubling), the number of the streamed pieces of 14 cells to
    the last bit."""
    from femcore import gershgorin

    merged, taken, put = [], [], []
    monkeypatch.setattr(gershgorin, "_merge", lambda *args: merged.append(True))
    start, give_back = gershgorin._Table.start, gershgorin._Table.put
    monkeypatch.setattr(
        gershgorin._Table,
        "start",
        lambda table, keys: taken.append(len(keys)) or start(table, keys),
    )
    tables = []

    def counted_put(table, sums):
        put.append(len(sums))
        tables.append(table)
        give_back(table, sums)

    monkeypatch.setattr(gershgorin._Table, "put", counted_put)
    compiled, _, pieces, maps, scale = _plate_in_pieces(monkeypatch, 1)
    assert len(pieces) == 40
    n = compiled.n_nodes
    held = gershgorin_largest(pieces, maps, scale, n)
    assert merged == []
    assert taken == put == [9] * 40
    pairs = len({(a, b) for piece in pieces for a in piece.nodes[0] for b in piece.nodes[0]})
    assert tables[-1].count == pairs
    assert tables[-1].grown <= int(np.log2(pairs))
    monkeypatch.undo()
    compiled, _, streamed_pieces, maps, scale = _plate_in_pieces(monkeypatch, 14)
    assert gershgorin._streamed(streamed_pieces, maps, scale, n) == held


def test_the_cells_band_is_the_longest_step_between_a_nodes_cells():
    """``_band``: the most cells from one cell at a node to its next, against numpy's sort of
    each node's cells, on a rectangle in rows (2 nx - 1: a node's cells in the row below and
    above) and with its cells shuffled."""
    from femcore import gershgorin

    mesh = Mesh.rectangle(40.0, 30.0, nx=9, ny=5)
    shuffled = mesh.triangles[np.random.default_rng(3).permutation(len(mesh.triangles))]
    for conn in (mesh.triangles, shuffled):
        nodes = conn.ravel()
        cells = np.repeat(np.arange(len(conn)), 3)
        order = np.lexsort((cells, nodes))
        step = np.diff(cells[order])[np.diff(nodes[order]) == 0]
        band = gershgorin._band(np.ascontiguousarray(conn, dtype=np.int64), mesh.n_nodes)
        assert band == step.max()
    assert (
        gershgorin._band(np.ascontiguousarray(mesh.triangles, dtype=np.int64), mesh.n_nodes) == 17
    )
    assert gershgorin.banded_piece(mesh.triangles, 4) == 17  # 90 cells: a quarter is 22
    assert gershgorin.banded_piece(mesh.triangles, 25) == 25
    assert gershgorin.banded_piece(shuffled, 4) == 4  # no band: every pair held


def test_a_thin_strip_streams(monkeypatch):
    """A Mindlin strip of 2 x 200 x 6 cells in rows (Mesh.rectangle's order): its cells' band
    (2 nx - 1 = 399) is longer than its pieces would otherwise be (256 cells), so that a
    piece could fall between two cells of a node and the bound be made again with every pair
    held (as it was); the pieces are as long as the band: the tangent is formed once,
    streamed, the bound the same as with every pair held to the last bit."""
    from elements import mindlin

    mesh = Mesh.rectangle(400.0, 12.0, nx=200, ny=6)
    model = Model(mesh)
    model.add(MindlinShell(ElasticShell(70e3, 0.3, 1.0, 2.7e-9)))
    model.fix("left")
    compiled = model.compile()
    state = compiled.initial_state()
    rng = np.random.default_rng(5)
    state = dataclasses.replace(
        state, positions=state.positions + rng.normal(scale=0.05, size=state.positions.shape)
    )
    formed = []
    pieces_of = mindlin.MindlinShellBlock.tangent_pieces

    def counted(block, *args):
        formed.append(True)
        return pieces_of(block, *args)

    monkeypatch.setattr(mindlin.MindlinShellBlock, "tangent_pieces", counted)
    mass, inertia = compiled.lumped_mass(state)
    step = compiled.assembled_stable_dt(state, mass, inertia)
    assert formed == [True]  # streamed: not made again
    block = compiled.blocks[0]
    assert [len(piece.nodes) for piece in pieces_of(block, state)][:2] == [399, 399]
    monkeypatch.setattr(mindlin, "banded_piece", lambda connectivity, cells: cells)
    formed.clear()
    assert compiled.assembled_stable_dt(state, mass, inertia) == step
    assert formed == [True, True]  # pieces of 256 cells: made again, every pair held


def _two_blocks(kind):
    """A 12 x 5 sheet (120 cells in rows) as two blocks split at x = 20 mm: the seam's 6 nodes
    in both; positions jittered, the left edge fixed."""
    mesh = Mesh.rectangle(40.0, 30.0, nx=12, ny=5)
    model = Model(mesh)
    middle = mesh.points[mesh.triangles].mean(axis=1)[:, 0]
    for cells in (np.flatnonzero(middle < 20.0), np.flatnonzero(middle >= 20.0)):
        if kind == "mindlin":
            model.add(MindlinShell(ElasticShell(70e3, 0.3, 1.0, 2.7e-9)), cells)
        else:
            model.add(FibrousShell(presets.g986_stack()), cells)
    model.fix("left")
    compiled = model.compile()
    state = compiled.initial_state()
    rng = np.random.default_rng(8)
    positions = state.positions + rng.normal(scale=0.3, size=state.positions.shape)
    return compiled, dataclasses.replace(state, positions=positions)


@pytest.mark.parametrize("kind", ["mindlin", "fibrous"])
def test_blocks_sharing_a_seam_form_their_tangent_once(monkeypatch, kind):
    """Two blocks sharing the seam's nodes: the second block's first piece meets seam nodes
    the first block left, so streaming every row gave up and formed every piece again with
    every pair held (each block's tangent_pieces called twice). The seam's rows are held to
    the end (``shared``): each block's pieces formed once, the step the same to the last bit
    as with every pair held, and the assembled bound's to 1e-12."""
    from elements import mindlin
    from femcore import gershgorin

    compiled, state = _two_blocks(kind)
    if kind == "mindlin":
        # pieces of 24 cells, three a block, longer than each block's band (11 cells):
        # each block streams on its own
        monkeypatch.setattr(mindlin, "banded_piece", lambda connectivity, cells: 24)
    block_type = type(compiled.blocks[0])
    pieces_of = block_type.tangent_pieces
    formed = []

    def counted(block, *args):
        formed.append(compiled.blocks.index(block))
        return pieces_of(block, *args)

    monkeypatch.setattr(block_type, "tangent_pieces", counted)
    mass, inertia = compiled.lumped_mass(state)
    step = compiled.assembled_stable_dt(state, mass, inertia)
    assert formed == [0, 1]  # once each (twice each, [0, 1, 0, 1], before)

    pieces = [piece for block in compiled.blocks for piece in pieces_of(block, state)]
    n = compiled.n_nodes
    seam = compiled._seam_nodes()
    assert seam.sum() == 6  # the nodes at x = 20 mm
    free = compiled.dofs.free_slots
    diagonal = np.column_stack([mass, mass, mass, inertia, inertia]).ravel()[free]
    scale = np.zeros(compiled.dofs.n_slots)
    scale[free] = 1.0 / np.sqrt(diagonal)
    maps = compiled.dofs.node_maps(compiled.dofs.frames(state.directors))
    held = gershgorin_largest(pieces, maps, scale, n)
    assert step == 2.0 / np.sqrt(held)
    assert gershgorin._streamed(pieces, maps, scale, n) is None  # without the seam held
    assert gershgorin._streamed(pieces, maps, scale, n, seam) == held
    assert held == pytest.approx(assembled(compiled, state, pieces, scale), rel=1e-12)
