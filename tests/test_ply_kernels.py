"""The ply contact's facing compiled (elements/ply_kernels.py) gives its numpy reference's
numbers to the last bit.

Reference: ``ply_projection.facets`` and ``ply_projection.closest_on_edges`` (numpy), and
``closest_facing`` with ``ply_projection.COMPILED = False``. The kernels do the same IEEE
operations in the same order, so the comparison is exact (no tolerance): the same facing
triangles, gaps, normals, projections, fades and forces, on random triangles, on a fan
folded at an outline vertex of three triangles whose growths are cut (tests/
test_ply_wedge.py's path round the vertex, bound folded and bound flat), on strips cut at
both ends with points all round, and on bent states of the two-ply hemisphere blank at 8 and
10 cells (both passes).
"""

import numpy as np
import pytest
from test_ply_wedge import _fan

from elements import (
    ply_friction,
    ply_friction_kernels,
    ply_kernels,
    ply_load_kernels,
    ply_projection,
)
from elements.ply_block import PlyContactBlock
from elements.ply_projection import (
    MARGIN,
    closest_facing,
    closest_on_edges,
    facets,
    grown_corners,
)
from elements.ply_topology import FaceTopology
from femcore.state import State
from tests.test_ply_wedge import cut_strip
from tests.thread_runs import on_one_thread_and_on_all


def _same(a, b) -> bool:
    """Equal to the bit wherever both are arrays (None where both are None)."""
    if a is None or b is None:
        return a is None and b is None
    return a.shape == b.shape and a.dtype == b.dtype and np.array_equal(a, b)


def _facings_equal(compiled, reference) -> list[str]:
    """The names of the Facing fields that differ."""
    return [
        name
        for name, value in vars(reference).items()
        if isinstance(value, np.ndarray) and not _same(getattr(compiled, name), value)
    ]


@pytest.mark.parametrize("shape", [(1, 1), (7, 3), (64, 5), (333, 8)])
def test_the_compiled_planes_are_numpy_s_to_the_bit(shape):
    """``facets_at(p, y, near)`` against ``facets(p, y[near])`` over random triangles (some
    thin: one corner 1e-3 of the side off the others' line) and points 0.01-100 mm off."""
    rng = np.random.default_rng(shape[0])
    count, k = shape
    y = rng.normal(0.0, 1.0, (40, 3, 3))
    y[::5, 2] = 0.5 * (y[::5, 0] + y[::5, 1]) + rng.normal(0.0, 1e-3, (8, 3))
    p = rng.normal(0.0, 1.0, (count, 3)) * 10.0 ** rng.uniform(-2, 2, (count, 1))
    near = rng.integers(0, len(y), shape)
    for got, want in zip(ply_kernels.facets_at(p, y, near), facets(p, y[near])):
        assert _same(got, want)


def test_the_compiled_edges_closest_points_are_numpy_s_to_the_bit():
    """``edges_closest`` against ``closest_on_edges`` on triangles grown past their edges by
    0-0.5 (as ``closest_facing`` grows its outline candidates) and points all round them."""
    rng = np.random.default_rng(3)
    corners = rng.normal(0.0, 1.0, (500, 3, 3))
    grown = grown_corners(corners, rng.choice([0.0, MARGIN], (500, 3)))
    p = grown.mean(axis=1) + rng.normal(0.0, 2.0, (500, 3))
    assert _same(ply_kernels.edges_closest(p, grown), closest_on_edges(p, grown))


def _both(monkeypatch, call):
    """``call()`` with the compiled kernels and with numpy's: (compiled, reference)."""
    monkeypatch.setattr(ply_projection, "COMPILED", True)
    compiled = call()
    monkeypatch.setattr(ply_projection, "COMPILED", False)
    return compiled, call()


@pytest.mark.parametrize("flat_at_bind", [False, True], ids=["folded at bind", "flat at bind"])
def test_the_facing_round_a_cut_outline_vertex_is_numpy_s_to_the_bit(monkeypatch, flat_at_bind):
    """Along the wedge test's path round a folded outline vertex of three triangles (cut
    growths, fades, edges' and vertices' pseudonormals, touching and not): every Facing
    field, the force and the energy of the compiled facing equal numpy's; the premise, the
    path crosses edges, a cut and the outline's fade."""
    block, positions, directors, _ = _fan(flat_at_bind)
    assert block.cuts.any
    zero = np.zeros_like(positions[0])
    seen = {"edge": 0, "cut or rim": 0, "faded": 0}
    for x in positions[::5]:
        state = State(x, directors, zero, zero)

        def facing_and_force(state=state):
            block._facing_at = None
            facing = block.facing(state, second=True)
            return facing, block.internal_force(state), block.strain_energy(state)

        (compiled, force, energy), (reference, force_ref, energy_ref) = _both(
            monkeypatch, facing_and_force
        )
        assert _facings_equal(compiled, reference) == []
        assert _same(force[0], force_ref[0]) and _same(force[1], force_ref[1])
        assert energy == energy_ref
        seen["edge"] += int((reference.weights.min(axis=1) < -1e-9).sum())
        seen["cut or rim"] += int(reference.on_growth.sum())
        seen["faded"] += int((reference.fade < 1.0).sum())
    assert min(seen.values()) > 0, seen


def _strip(rng):
    """tests/test_ply_wedge.py's strip of 4 cells, 0.3 mm high, its nodes jittered 0.05 mm in
    plane and 0.2 mm out of it: (nodes (m, 3), corners y (m, 3, 3), outline, cuts)."""
    return cut_strip(rng, 0.3)


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_the_facing_of_points_round_strips_cut_at_both_ends_is_numpy_s_to_the_bit(
    monkeypatch, seed
):
    """tests/test_ply_wedge.py's strips (cut at both ends of their outline triangles) and 400
    points round them, every triangle a candidate: the same facing to the bit, the premise
    some points past the cuts."""
    rng = np.random.default_rng(seed)
    nodes, y, outline, cuts = _strip(rng)
    cells = 4
    assert cuts.any
    topology = FaceTopology.of(nodes, outline)
    p = rng.uniform([-1.0, -1.2, -0.6], [cells + 1.0, 0.9, 0.6], (400, 3))
    near = np.tile(np.arange(len(nodes)), (len(p), 1))
    toward = np.tile([0.0, 0.0, 1.0], (len(p), 1))

    def facing():
        return closest_facing(
            p, y, near, 0.0, outline, True, depth=0.2, toward=toward, topology=topology, cuts=cuts
        )

    compiled, reference = _both(monkeypatch, facing)
    assert _facings_equal(compiled, reference) == []
    assert reference.on_growth.any() and (reference.fade < 1.0).any()


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_the_facing_after_its_choice_is_numpy_s_on_one_thread_and_on_all(monkeypatch, seed):
    """What follows the choice in two passes (elements/ply_edge_kernels.py ``edge_sides``: the
    closest points' signs by the features' pseudonormals, at outline vertices and on cuts,
    their gaps, normals, coordinates and Hessians, the flags on the growths, deeper than the
    plies, near the outline and touching) against numpy's expressions of ``closest_facing``
    (``ply_projection.COMPILED = False``), on tests/test_ply_wedge.py's strips cut at both
    ends with 400 points round them, every triangle a candidate, a layer turned away for a
    third of them, on one thread and on all of numba's: every Facing field to the bit; the
    premises, points at vertices (some of the outline's) and on edges, at the outline's
    vertices or on cuts, on joined edges' extensions, deeper than the plies and touching."""
    rng = np.random.default_rng(seed)
    nodes, y, outline, cuts = _strip(rng)
    topology = FaceTopology.of(nodes, outline)
    p = rng.uniform([-1.0, -1.2, -0.6], [5.0, 0.9, 0.6], (400, 3))
    near = np.tile(np.arange(len(nodes)), (len(p), 1))
    toward = np.tile([0.0, 0.0, 1.0], (len(p), 1))
    toward[::3] *= -1.0

    def facing():
        return closest_facing(
            p, y, near, 0.0, outline, True, depth=0.2, toward=toward, topology=topology, cuts=cuts
        )

    monkeypatch.setattr(ply_projection, "COMPILED", False)
    reference = facing()
    monkeypatch.setattr(ply_projection, "COMPILED", True)
    for compiled in on_one_thread_and_on_all(facing):
        assert _facings_equal(compiled, reference) == []
    edge = reference.on_edge
    bound = reference.weights <= -reference.reach + 1e-9
    assert (edge & (bound.sum(axis=1) == 2)).any() and (edge & (bound.sum(axis=1) == 1)).any()
    vertex = topology.nodes[reference.triangle, np.argmin(bound, axis=1)]
    assert (edge & (bound.sum(axis=1) == 2) & topology.rim[vertex]).any()  # outline vertices
    assert reference.on_growth.any() and reference.joined.any()
    assert (edge & (reference.gap < -0.2)).any() and reference.touching.any()
    assert reference.hessian is not None and np.any(reference.hessian != 0.0)


@pytest.mark.parametrize("seed", [0, 1])
def test_padded_lists_face_as_numpy_s_and_as_the_unpadded(monkeypatch, seed):
    """The kept lists pad each point's row with its first candidate (elements/ply_search.py);
    the compiled planes and choice copy the first's arrays into those slots rather than
    compute them again (elements/ply_kernels.py ``_facets_at``, elements/ply_choice.py
    ``_choose``). On tests/test_ply_wedge.py's cut strips with 400 points round them, each
    point given 1-5 random candidates (its nearest centroid's among them) padded to 5 with its
    first: the candidates' arrays (normals, gradients, gaps, weights, reach, inside, past)
    and every Facing field to the bit against numpy's (``COMPILED = False``) on one thread
    and on all of numba's, and the Facing as with the rows unpadded (each point alone, its
    own candidates only). Premise: a third or more of the slots are padding."""
    rng = np.random.default_rng(seed)
    nodes, y, outline, cuts = _strip(rng)
    topology = FaceTopology.of(nodes, outline)
    p = rng.uniform([-1.0, -1.2, -0.6], [5.0, 0.9, 0.6], (400, 3))
    toward = np.tile([0.0, 0.0, 1.0], (len(p), 1))
    nearest = np.argmin(np.linalg.norm(p[:, None] - y.mean(axis=1)[None], axis=2), axis=1)
    width = 5
    counts = rng.integers(1, width + 1, len(p))
    near = np.empty((len(p), width), dtype=np.int64)
    for i, count in enumerate(counts):
        others = rng.permutation(np.setdiff1d(np.arange(len(y)), [nearest[i]]))[: count - 1]
        own = np.sort(np.concatenate([[nearest[i]], others]))
        near[i] = np.concatenate([own, np.repeat(own[:1], width - count)])
    assert np.sum(width - counts) >= len(p) * width / 3  # the premise: padding

    def facing(rows=near, at=p, facing_toward=toward):
        return closest_facing(
            at, y, rows, 0.0, outline, True, depth=0.2, toward=facing_toward,
            topology=topology, cuts=cuts,
        )  # fmt: skip

    monkeypatch.setattr(ply_projection, "COMPILED", False)
    reference = facing()
    n, _, gradients, gap, weights = facets(p, y[near])
    monkeypatch.setattr(ply_projection, "COMPILED", True)
    planes = ply_kernels.candidates_at(p, y, near, outline, MARGIN, ply_projection.INSIDE)
    for name, ours, theirs in zip(
        ("n", "gradients", "gap", "weights"), planes[:4], (n, gradients, gap, weights)
    ):
        assert _same(ours, theirs), name
    reach = np.where(outline[near], MARGIN, 0.0)
    assert _same(planes[4], reach)
    assert _same(planes[5], (weights >= -reach - ply_projection.INSIDE).all(axis=-1))
    past = np.max(-(weights + reach) / np.linalg.norm(gradients, axis=-1), axis=-1)
    assert _same(planes[6], past)
    for compiled in on_one_thread_and_on_all(facing):
        assert _facings_equal(compiled, reference) == []
    for i in rng.choice(len(p), 40, replace=False):  # unpadded, one point at a time
        alone = facing(near[i : i + 1, : counts[i]], p[i : i + 1], toward[i : i + 1])
        for name in ("triangle", "gap", "normal", "weights", "touching", "fade"):
            assert _same(getattr(alone, name)[0], getattr(reference, name)[i]), (i, name)


def _bent(compiled, seed: int, depth: float) -> State:
    """The blank pressed ``depth`` mm (times (1 - r / 60 mm)^1.5) into a bowl about its pole,
    jittered 2e-3 mm, its directors tilted about 0.01 rad."""
    x0 = compiled.mesh.points
    n = len(x0)
    rng = np.random.default_rng(seed)
    radius = np.linalg.norm(x0[:, :2], axis=1)
    x = x0 + rng.normal(0.0, 2e-3, x0.shape)
    x[:, 2] -= depth * np.maximum(0.0, 1.0 - radius / 60.0) ** 1.5
    d = np.tile([0.0, 0.0, 1.0], (n, 1)) + rng.normal(0.0, 0.01, (n, 3))
    d /= np.linalg.norm(d, axis=1)[:, None]
    return State(x, d, np.zeros((n, 3)), np.zeros((n, 3)))


@pytest.mark.parametrize("cells", [8, 10])
def test_the_bent_two_ply_hemisphere_s_facing_and_forces_are_numpy_s_to_the_bit(monkeypatch, cells):
    """The two-ply Mindlin [0/90] hemisphere blank (validation/studies/
    hemisphere_plies_setup.py) bent 0-20 mm and jittered, both passes with friction's
    history: the same facing and the same forces and moments to the bit."""
    from validation.studies import hemisphere_plies_setup as setup

    _, model = setup.model(cells, setup.LAYUPS["0/90"], "mindlin", 20.0)
    compiled_model = model.compile()
    blocks = [b for b in compiled_model.interactions if isinstance(b, PlyContactBlock)]
    assert len(blocks) == 2
    touching = 0
    for seed, depth in enumerate((0.0, 5.0, 20.0)):
        state = _bent(compiled_model, seed, depth)
        for block in blocks:
            history = block.initial_history()

            def facing_and_force(block=block, state=state, history=history):
                block._facing_at = None
                block._faces_at = None
                block._directions_at = None
                return block.facing(state), block.internal_force(state, history)

            (compiled, force), (reference, force_ref) = _both(monkeypatch, facing_and_force)
            assert _facings_equal(compiled, reference) == []
            assert _same(force[0], force_ref[0]) and _same(force[1], force_ref[1])
            touching += int(reference.touching.sum())
    assert touching > 0


def test_the_compiled_grown_corners_are_numpy_s_to_the_bit(monkeypatch):
    """``ply_kernels.grown_corners`` against ``grown_corners``'s numpy reference (``COMPILED``
    off) over random triangles grown by random reaches in [0, 1) and by 0 or ``MARGIN``."""
    rng = np.random.default_rng(7)
    corners = rng.normal(0.0, 10.0, (300, 3, 3))
    for reach in (rng.uniform(0.0, 1.0, (300, 3)), rng.choice([0.0, MARGIN], (300, 3))):
        monkeypatch.setattr(ply_projection, "COMPILED", False)
        want = grown_corners(corners, reach)
        assert _same(ply_kernels.grown_corners(corners, reach), want)


def test_the_compiled_candidates_reach_inside_and_past_are_numpy_s_to_the_bit():
    """``candidates_at`` against ``closest_facing``'s numpy reference expressions: the reach
    past outline edges (a random third of them), the projection held by the grown triangle,
    its distance past the farthest edge line; the premise, both held and not held."""
    rng = np.random.default_rng(11)
    y = rng.normal(0.0, 1.0, (60, 3, 3))
    outline = rng.uniform(size=(60, 3)) < 1.0 / 3.0
    p = rng.normal(0.0, 1.0, (200, 3))
    near = rng.integers(0, len(y), (200, 6))
    n, gradients, gap, weights, reach, inside, past = ply_kernels.candidates_at(
        p, y, near, outline, MARGIN, ply_projection.INSIDE
    )
    n_, _, gradients_, gap_, weights_ = facets(p, y[near])
    reach_ = np.where(outline[near], MARGIN, 0.0)
    inside_ = (weights_ >= -reach_ - ply_projection.INSIDE).all(axis=-1)
    past_ = np.max(-(weights_ + reach_) / np.linalg.norm(gradients_, axis=-1), axis=-1)
    for got, want in zip(
        (n, gradients, gap, weights, reach, inside, past),
        (n_, gradients_, gap_, weights_, reach_, inside_, past_),
    ):
        assert _same(got, want)
    assert inside.any() and not inside.all()


@pytest.mark.parametrize("seed", [0, 1])
def test_the_search_s_closest_points_of_cut_growths_are_numpy_s_to_the_bit(monkeypatch, seed):
    """``closest_on_grown`` (the facing search's distances, elements/ply_search.py) with the
    compiled planes and edges against numpy's, every strip triangle against 100 points."""
    from elements.ply_wedge import closest_on_grown

    rng = np.random.default_rng(seed)
    _, y, outline, cuts = _strip(rng)
    rows = np.repeat(np.arange(len(y)), 100)
    p = y[rows].mean(axis=1) + rng.normal(0.0, 0.5, (len(rows), 3))
    reach = np.where(outline, MARGIN, 0.0)

    def closest():
        return closest_on_grown(p, y[rows], reach[rows], cuts.lines[rows], cuts.ends[rows])

    compiled, reference = _both(monkeypatch, closest)
    for got, want in zip(compiled, reference):
        assert _same(got, want)
    assert reference[1].any()  # the premise: some closest points on a cut


def _fields_equal(compiled, reference) -> list[str]:
    """The names of the array fields of two records (a Sliding, a friction history) that
    differ to the bit (NaN equal to NaN), of their float fields that differ, and of their
    records that hold such fields (the history's sides: ``name.field``)."""
    differ = []
    for name, value in vars(reference).items():
        other = getattr(compiled, name)
        if hasattr(value, "__dataclass_fields__"):
            differ += [f"{name}.{field}" for field in _fields_equal(other, value)]
        elif isinstance(value, np.ndarray):
            if not (
                other.shape == value.shape
                and other.dtype == value.dtype
                and np.array_equal(other, value, equal_nan=value.dtype.kind == "f")
            ):
                differ.append(name)
        elif other != value:
            differ.append(name)
    return differ


@pytest.mark.parametrize("stick", ["penalty", "normal law"])
def test_the_compiled_loads_with_friction_are_numpy_s_to_the_bit(monkeypatch, stick):
    """The two-ply Mindlin [0/90] hemisphere blank (8 cells) bent 5 then 5.2 mm, both passes,
    with friction (the history committed at the first state, so that the second has stuck
    and sliding anchors): the compiled loads (elements/ply_load_kernels.py), friction
    (elements/ply_friction_kernels.py) and facing give numpy's forces and moments, energy,
    return mapping and committed histories (the dissipation too) to the bit, on
    one thread and on all of numba's (every loop parallel); the premises, stuck and sliding
    points and touching points whose fade moves the outline's edges' ends (with the normal
    law's spring: stuck points whose potential lifts them, or whose fade moves; stuck points
    with a couple on their facing corners, ``ply_friction.stick_couple``)."""
    from validation.studies import hemisphere_plies_setup as setup

    _, model = setup.model(8, setup.LAYUPS["0/90"], "mindlin", 20.0)
    compiled_model = model.compile()
    blocks = [b for b in compiled_model.interactions if isinstance(b, PlyContactBlock)]
    assert len(blocks) == 2
    first, second = _bent(compiled_model, 3, 5.0), _bent(compiled_model, 3, 5.2)
    seen = {"stuck": 0, "sliding": 0, "ends moved": 0}

    def compare():
        for block in blocks:
            monkeypatch.setattr(block, "stick", stick)
            assert block.friction > 0.0

            def loads(block=block):
                for kept in ("_facing_at", "_faces_at", "_directions_at"):
                    setattr(block, kept, None)
                history = block.update_history(first, block.initial_history())
                for kept in ("_facing_at", "_faces_at", "_directions_at"):
                    setattr(block, kept, None)
                force = block.internal_force(second, history)
                return (
                    force,
                    block.strain_energy(second, history),
                    block.friction_state(second, history),
                    block.update_history(second, history),
                    block.facing(second),
                    history,
                )

            compiled, reference = _both(monkeypatch, loads)
            # the pass itself, on numpy's facing and return mapping (COMPILED off now)
            direct = ply_load_kernels.ply_loads(
                block, second, reference[4], reference[2], reference[5].anchor
            )
            assert _same(direct[0], reference[0][0]) and _same(direct[1], reference[0][1])
            mapping = ply_friction_kernels.friction_state(block, second, reference[5], reference[4])
            assert _fields_equal(mapping, reference[2]) == []
            assert _same(compiled[0][0], reference[0][0])
            assert _same(compiled[0][1], reference[0][1])
            assert compiled[1] == reference[1]
            assert _fields_equal(compiled[2], reference[2]) == []
            assert _fields_equal(compiled[3], reference[3]) == []
            assert _fields_equal(compiled[5], reference[5]) == []
            facing, sliding = reference[4], reference[2]
            seen["stuck"] += int(sliding.stuck.sum())
            seen["sliding"] += int(sliding.sliding.sum())
            moving = facing.touching & (facing.fade_edge >= 0)
            moving &= np.any(facing.fade_gradient[:, 4:] != 0.0, axis=(1, 2))
            seen["ends moved"] += int(moving.sum())
            # stuck points facing a plane carry the couple on the facing corners
            couple = ply_friction.stick_couple(block, sliding, facing, np.arange(len(facing.gap)))
            seen["couple"] = seen.get("couple", 0) + int(np.any(couple != 0.0, axis=1).sum())
            if stick == "normal law":  # the stick potential's normal force and fade term
                seen["lifted"] = seen.get("lifted", 0) + int(np.sum(sliding.lift != 0.0))
                faded = sliding.stored != 0.0
                faded &= np.any(facing.fade_gradient != 0.0, axis=(1, 2))
                seen["stored, faded"] = seen.get("stored, faded", 0) + int(faded.sum())

    on_one_thread_and_on_all(compare)
    assert min(seen.values()) > 0, seen


@pytest.mark.parametrize("stick", ["penalty", "normal law"])
def test_the_next_loads_take_the_return_mapping_their_history_was_committed_with(
    monkeypatch, stick
):
    """The two-ply Mindlin [0/90] hemisphere blank (8 cells) bent 5 then 5.2 mm, both passes,
    with friction: the history committed at the second state makes the return mapping from
    itself at that state in its own pass, and the next loads' ``friction_state`` at that
    state from that history is that one (no second pass), the same to the bit as the mapping
    made afresh and as numpy's (``ply_friction.friction_state``), on one thread and on all of
    numba's; not the committed history's own mapping (from the history before: the two
    mappings of a step differ where points slide); another history or facing is mapped
    afresh. The premises, stuck and sliding points."""
    from validation.studies import hemisphere_plies_setup as setup

    _, model = setup.model(8, setup.LAYUPS["0/90"], "mindlin", 20.0)
    compiled_model = model.compile()
    blocks = [b for b in compiled_model.interactions if isinstance(b, PlyContactBlock)]
    first, second = _bent(compiled_model, 3, 5.0), _bent(compiled_model, 3, 5.2)
    monkeypatch.setattr(ply_projection, "COMPILED", True)
    seen = {"stuck": 0, "sliding": 0, "differs": 0}

    def check():
        for block in blocks:
            monkeypatch.setattr(block, "stick", stick)
            history = block.update_history(first, block.initial_history())
            before = block.friction_state(second, history)  # the committed history's own
            later = block.update_history(second, history)
            served = block.friction_state(second, later)
            assert served is block._next_sliding[3]
            assert block.friction_state(second, history) is not served
            block._next_sliding = None
            fresh = block.friction_state(second, later)
            assert fresh is not served and _fields_equal(fresh, served) == []
            want = ply_friction.friction_state(block, second, later, block.facing(second))
            assert _fields_equal(served, want) == []
            seen["stuck"] += int(served.stuck.sum())
            seen["sliding"] += int(before.sliding.sum())
            seen["differs"] += len(_fields_equal(before, served))

    on_one_thread_and_on_all(check)
    assert min(seen.values()) > 0, seen


def test_the_kept_return_mapping_is_not_served_after_an_edit_in_place(monkeypatch):
    """The kept mapping is served to the history it was made with, unedited: an anchor moved
    in place, or the block's penalties scaled in place, maps afresh (numpy's mapping of the
    edited inputs), not the stale one."""
    from validation.studies import hemisphere_plies_setup as setup

    _, model = setup.model(8, setup.LAYUPS["0/90"], "mindlin", 20.0)
    compiled_model = model.compile()
    block = next(b for b in compiled_model.interactions if isinstance(b, PlyContactBlock))
    first, second = _bent(compiled_model, 3, 5.0), _bent(compiled_model, 3, 5.2)
    monkeypatch.setattr(ply_projection, "COMPILED", True)
    history = block.update_history(first, block.initial_history())
    later = block.update_history(second, history)
    served = block._next_sliding[3]
    assert block.friction_state(second, later) is served  # unedited: the kept one
    anchored = np.flatnonzero(np.isfinite(later.anchor[:, 0]))
    assert anchored.size
    later.anchor[anchored] = later.anchor[anchored][:, [1, 2, 0]]  # the anchors moved
    moved = block.friction_state(second, later)
    assert moved is not served
    want = ply_friction.friction_state(block, second, later, block.facing(second))
    assert _fields_equal(moved, want) == []
    assert _fields_equal(moved, served) != []
    later = block.update_history(second, history)
    served = block._next_sliding[3]
    block.stiffness = np.array(block.stiffness, dtype=float)  # the block's own, writable
    block.stiffness *= 2.0
    fresh = block.friction_state(second, later)
    assert fresh is not served
    want = ply_friction.friction_state(block, second, later, block.facing(second))
    assert _fields_equal(fresh, want) == []
    assert "force" in _fields_equal(fresh, served)  # the penalties shape the stuck force


@pytest.mark.parametrize("seed", [0, 1])
def test_the_fade_s_one_pass_is_numpy_s_on_one_thread_and_on_all(monkeypatch, seed):
    """``ply_fade_kernels.outline_fade_at`` (the outline's nearest edges, the fade's inputs,
    the grown and cut triangles' closest points and the fade in one pass) against numpy's
    (``ply_fade.every_segment``, ``ply_chosen.fade_inputs_numpy`` and ``ply_fade.outline_fade``
    with ``COMPILED`` off): tests/test_ply_wedge.py's strip cut at both ends, 600 points round
    its outline triangles, each against one of them, a third beside the growth (a fifth of
    those on a joined edge), the pass at every other point, with and without the cuts, the
    edges measured in the pass (each edge listed twice, ties to the lowest index, and an edge
    of no length among them) and given (as the KD-tree's path gives them; here
    every_segment's), on one thread and on all of numba's; the premises, w strictly between
    0 and 1 both past the outline and beside a growth, and some closest points on the cuts."""
    from elements import ply_chosen, ply_fade_kernels
    from elements.ply_fade import every_segment, fade_length, outline_fade, outline_segments
    from elements.ply_wedge import closest_on_grown

    rng = np.random.default_rng(seed)
    _, y, outline, cuts = _strip(rng)
    count = 600
    triangle = rng.choice(np.flatnonzero(outline.any(axis=1)), count)
    p = y[triangle].mean(axis=1) + rng.normal(0.0, 0.4, (count, 3))
    n, _, gradients, gap, lam = (a[:, 0] for a in facets(p, y[triangle][:, None]))
    planes = tuple(np.ascontiguousarray(a) for a in (n, gradients, gap, lam))
    reach = np.where(outline, MARGIN, 0.0)[triangle]
    beside = rng.uniform(size=count) < 1.0 / 3.0
    joined = beside & (rng.uniform(size=count) < 0.2)
    at = np.arange(0, count, 2)
    segment_rows, segment_ends = outline_segments(outline)
    starts, stops = (y[segment_rows, segment_ends[:, k]] for k in range(2))
    # the outline's edges once more after themselves (each nearest edge a tie, to the lowest
    # index as numpy's argmin) and an edge of no length at the first one's start
    edges = len(starts)
    starts = np.concatenate([starts, starts, starts[:1]])
    stops = np.concatenate([stops, stops, starts[:1]])
    length = fade_length(y, outline)
    edge = every_segment(p[at], starts, stops)
    assert edge.max() < edges
    for wedge in (cuts, None):
        monkeypatch.setattr(ply_projection, "COMPILED", False)
        inputs = ply_chosen.fade_inputs_numpy(
            at, p, y, triangle, reach, beside, joined, starts, stops, edge, wedge
        )
        at_p, corners, at_reach, at_beside, ends, at_joined, lines, cut_ends = inputs
        want = outline_fade(
            at_p, corners, at_reach, at_beside, ends, length, at_joined, lines, cut_ends
        )
        monkeypatch.setattr(ply_projection, "COMPILED", True)

        def fade(given, wedge=wedge):
            out = (np.ones(count), np.zeros((count, 6, 3)), np.full(count, -1))
            ply_fade_kernels.outline_fade_at(
                at, p, y, triangle, planes, reach, beside, joined, given, starts, stops, wedge,
                length, out,
            )  # fmt: skip
            return out

        for given in (None, edge):
            for got in on_one_thread_and_on_all(lambda given=given: fade(given)):
                assert _same(got[0][at], want[0]) and _same(got[1][at], want[1])
                assert _same(got[2][at], edge)
                off = np.setdiff1d(np.arange(count), at)
                assert np.all(got[0][off] == 1.0) and np.all(got[2][off] == -1)
        between = (want[0] > 0.0) & (want[0] < 1.0)
        assert (between & at_beside).any() and (between & ~at_beside).any()
    on_cut = closest_on_grown(
        at_p[at_beside], corners[at_beside], at_reach[at_beside],
        cuts.lines[triangle[at]][at_beside], cuts.ends[triangle[at]][at_beside],
    )[1]  # fmt: skip
    assert on_cut.any()


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_the_compiled_choice_of_the_facing_candidate_is_numpy_s_to_the_bit(seed):
    """``ply_choice.choose_facing`` against ``choose_facing_numpy`` on tests/test_ply_wedge.py's
    strips cut at both ends, 400 points round them, every triangle a candidate (in a shuffled
    order, so that ties go to the lowest row, not the first column): the same columns and
    closest points, cut flags, segments and parameters, on one thread and on all of numba's;
    the premises, points facing edges and cuts."""
    from elements import ply_choice

    rng = np.random.default_rng(seed)
    _, y, outline, cuts = _strip(rng)
    p = rng.uniform([-1.0, -1.2, -0.6], [5.0, 0.9, 0.6], (400, 3))
    near = np.argsort(rng.uniform(size=(len(p), len(y))), axis=1)
    planes = ply_kernels.candidates_at(p, y, near, outline, MARGIN, ply_projection.INSIDE)
    want = ply_choice.choose_facing_numpy(p, y, near, *planes[:6], planes[6].copy(), cuts)
    # on one thread and on all of numba's: each point's rows of the pass's working arrays
    # are its own (elements/ply_choice.py ``_scratch``)
    for got in on_one_thread_and_on_all(
        lambda: ply_choice.choose_facing(p, y, near, *planes, cuts)
    ):
        for a, b in zip(got, want):
            assert _same(a, b)
    assert want[1].any() and want[3].any()


def test_the_compiled_faces_are_numpy_s_to_the_bit(monkeypatch):
    """The two-ply Mindlin [0/90] hemisphere blank (8 cells, faces along the plies' nodal
    normals) bent 0-20 mm, both passes: the compiled nodal normals, contact points and lower
    corners (elements/ply_face_points.py) equal numpy's to the bit; a non-finite state is
    refused by the same ValueError on either path."""
    from validation.studies import hemisphere_plies_setup as setup

    _, model = setup.model(8, setup.LAYUPS["0/90"], "mindlin", 20.0)
    compiled_model = model.compile()
    blocks = [b for b in compiled_model.interactions if isinstance(b, PlyContactBlock)]
    assert all(block.along_normals for block in blocks)
    for seed, depth in enumerate((0.0, 5.0, 20.0)):
        state = _bent(compiled_model, seed, depth)
        for block in blocks:

            def faces(block=block, state=state):
                block._faces_at = block._directions_at = None
                return (block.offset_directions(state), *block._faces(state))

            for got, want in zip(*_both(monkeypatch, faces)):
                assert _same(got, want)
    x = state.positions.copy()
    x[3, 1] = np.nan
    broken = State(x, state.directors, state.velocities, state.angular_velocities)
    for flag in (True, False):
        monkeypatch.setattr(ply_projection, "COMPILED", flag)
        blocks[0]._faces_at = blocks[0]._directions_at = None
        with pytest.raises(ValueError, match="NaN or infinite"):
            blocks[0]._faces(broken)


def test_the_compiled_points_direction_toward_their_ply_is_numpy_s_to_the_bit():
    """``ply_face_points.offset_toward`` (the facing's ``toward``, sum_j N_j a_j d_j, d
    gathered at the upper corners in the pass) gives the bytes of numpy's
    ``einsum("pj,pj,pji->pi")``: the two-ply Mindlin [0/90]
    hemisphere blank's points (8 cells, both passes, bent 0-20 mm) and random rows with zero
    offsets, zero shape functions and -0.0 among them, on one thread and on all of numba's."""
    from elements import ply_face_points
    from validation.studies import hemisphere_plies_setup as setup

    _, model = setup.model(8, setup.LAYUPS["0/90"], "mindlin", 20.0)
    compiled_model = model.compile()
    blocks = [b for b in compiled_model.interactions if isinstance(b, PlyContactBlock)]
    rng = np.random.default_rng(5)
    cases = []
    for seed, depth in enumerate((0.0, 5.0, 20.0)):
        state = _bent(compiled_model, seed, depth)
        for block in blocks:
            d = block.offset_directions(state)
            cases.append((d, block.above, block.upper_offset, block.shape))
    count, nodes = 500, 40
    d = rng.normal(size=(nodes, 3))
    d[:5] = [[0.0, -0.0, 1.0]] * 5
    above = rng.integers(0, nodes, (count, 3))
    offset = np.where(rng.random((count, 3)) < 0.2, rng.choice([0.0, -0.0], (count, 3)), 1.5)
    shape = np.where(rng.random((count, 3)) < 0.2, 0.0, rng.dirichlet(np.ones(3), count))
    cases.append((d, above, offset * rng.uniform(0.5, 1.5, (count, 3)), shape))
    for d, above, offset, shape in cases:
        want = np.einsum("pj,pj,pji->pi", shape, offset, d[above])

        def toward(d=d, above=above, offset=offset, shape=shape):
            return ply_face_points.offset_toward(d, above, offset, shape)

        for got in on_one_thread_and_on_all(toward):
            assert got.tobytes() == want.tobytes()
    assert np.any(np.all(want == 0.0, axis=1))  # rows whose terms all vanish


def test_the_compiled_kept_lists_moves_are_numpy_s_to_the_bit(monkeypatch):
    """``FacingSearch.near`` with the kept lists' moves compiled (elements/ply_search.py
    ``_moves``) against numpy's: two searches of the two-ply hemisphere blank's first pass
    driven through the same 40 states (the bowl deepening by 0.05 mm a state, jittered, 3 mm
    more every thirteenth, every tenth point slid 0.6 skin every fifth), one on each path:
    the same candidates and the same kept lists (origins, moves, shifts) to the bit at every
    state; the premises, lists kept, refreshed and renewed."""
    from elements.ply_search import FacingSearch
    from validation.studies import hemisphere_plies_setup as setup

    _, model = setup.model(8, setup.LAYUPS["0/90"], "mindlin", 20.0)
    compiled_model = model.compile()
    block = next(b for b in compiled_model.interactions if isinstance(b, PlyContactBlock))
    searches = {flag: FacingSearch(block.search.reach, block.search.skin) for flag in (1, 0)}
    kept = refreshed = renewed = 0
    for step in range(40):
        state = _bent(compiled_model, step, 0.05 * step + (3.0 if step % 13 == 12 else 0.0))
        block._faces_at = block._directions_at = None
        p, y = block._faces(state)
        if step % 5 == 2:  # every tenth point slid 0.6 skin: past the bound, searched again
            p = p.copy()
            p[::10, 0] += 0.6 * block.search.skin
        answers = {}
        for flag, search in searches.items():
            monkeypatch.setattr(ply_projection, "COMPILED", bool(flag))
            before = (search.searches, search.searched_points)
            answers[flag] = (search.near(p, y), search._lists, before)
        (near, lists, before), (near_, lists_, _) = answers[1], answers[0]
        assert _same(near, near_)
        for name in ("near", "count", "origin", "moved", "shift", "epoch"):
            assert _same(getattr(lists, name), getattr(lists_, name)), name
        done = searches[1].searched_points - before[1]
        kept += done == 0
        refreshed += 0 < done < len(p)
        renewed += done == len(p)
    assert kept and refreshed and renewed, (kept, refreshed, renewed)


@pytest.mark.parametrize("with_toward", [False, True])
def test_the_compiled_chosen_candidate_s_arrays_are_numpy_s_to_the_bit(with_toward):
    """``ply_chosen.chosen`` against ``ply_chosen.chosen_numpy``: the chosen candidate's
    triangle, gap, normal, coordinates, gradients, reach, overshoot, reach past the outline
    and turn, to the bit, on random candidates with NaN coordinates (numpy's min takes the
    first NaN), signed zeros, ties of the least coordinate and normals at right angles to
    ``toward`` (a dot of exactly 0 is not turned), on one thread and on all of numba's."""
    from elements import ply_chosen

    rng = np.random.default_rng(7)
    count, k = 997, 4
    near = rng.integers(0, 50, (count, k))
    best = rng.integers(0, k, count)
    n = rng.normal(size=(count, k, 3))
    gap = rng.normal(size=(count, k))
    weights = rng.normal(0.3, 0.6, (count, k, 3))
    weights[::11, :, 1] = np.nan
    weights[::13, :, 0] = np.nan
    weights[::7, :, 2] = -0.0
    weights[::5, :, 0] = weights[::5, :, 2]  # ties
    weights[::17] = 0.0
    gradients = rng.normal(size=(count, k, 3, 3))
    reach = np.where(rng.random((count, k, 3)) < 0.3, 0.5, 0.0)
    toward = rng.normal(size=(count, 3)) if with_toward else None
    if with_toward:
        rows = np.arange(count)
        toward[::9] = np.cross(n[rows, best][::9], [0.0, 0.0, 1.0])  # at right angles
        toward[::9, 2] = 0.0
        n[rows[::9], best[::9], 2] = 0.0
    arguments = (best, near, n, gap, weights, gradients, reach, toward)
    reference = ply_chosen.chosen_numpy(*arguments)
    assert np.isnan(reference[6]).any() and (reference[6] == 0.0).any()
    assert reference[7].any() and not reference[7].all()

    def compare():
        compiled = ply_chosen.chosen(*arguments)
        assert len(compiled) == len(reference)
        for got, want in zip(compiled, reference, strict=True):
            assert got.shape == want.shape and got.dtype == want.dtype
            assert np.array_equal(got, want, equal_nan=True)
            # signed zeros too
            if got.dtype == float:
                assert np.array_equal(np.signbit(got), np.signbit(want))

    on_one_thread_and_on_all(compare)


@pytest.mark.parametrize("threads", [1, 2])
def test_the_largest_gradient_is_numpy_s_to_the_bit(threads):
    """``ply_kernels.largest_gradient`` (the ply springs' least height) gives numpy's
    ``max |grad phi|`` over ``triangle_frames`` to the bit: random triangles at three scales,
    a degenerate one (NaN, as numpy's max passes it), and 1 and 2 threads over 5000."""
    import numba

    from elements import ply_kernels
    from elements.ply_projection import triangle_frames

    held = numba.get_num_threads()
    numba.set_num_threads(min(threads, numba.config.NUMBA_NUM_THREADS))
    try:
        rng = np.random.default_rng(11)
        for count in (1, 7, 5000):
            for scale in (1e-6, 1.0, 1e3):
                y = rng.normal(scale=scale, size=(count, 3, 3))
                expected = float(np.max(np.linalg.norm(triangle_frames(y)[2], axis=-1)))
                assert ply_kernels.largest_gradient(y) == expected
        y = rng.normal(size=(50, 3, 3))
        y[7, 1] = y[7, 0]  # two corners at one place: no plane, NaN gradients
        with np.errstate(invalid="ignore", divide="ignore"):
            expected = float(np.max(np.linalg.norm(triangle_frames(y)[2], axis=-1)))
        assert np.isnan(expected) and np.isnan(ply_kernels.largest_gradient(y))
    finally:
        numba.set_num_threads(held)
