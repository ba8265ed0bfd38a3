"""The tool contact's frozen set as the linear model the static solver predicts the next set
on (elements/contact_set_model.py): each node's row of dg/dq is the tool's normal on its
translations, so g + G dq is the gap of the moved node to first order; with friction a
sliding node's force direction is n - mu v (its friction mu k p follows the gap) and a stuck
node has two stick rows in its tangent plane, so that the rows sum to the frozen law's own
forces and tangent; without a frozen set there is no model."""

import numpy as np
import pytest

from femcore.dofs import N_COLUMNS
from tests.test_interaction_conformance import MU, TOOLS, contact

STEP = 1e-4  # mm, each component of the random motion


@pytest.mark.parametrize("name", TOOLS)
def test_the_rows_linearise_each_nodes_gap(name):
    """g + G du against the tool's distance at x + du less the offset: the remainder is the
    second-order term, |du|^2 / (2 R) for a tool of radius R (R >= 6 mm here, |du| <= 1.8e-4
    mm: 2.7e-9 mm; zero on the plane and the meshed floor, which is a plane), so 1e-8 mm
    bounds it, while dropping the first-order term would miss by about 1e-4 mm."""
    block, state, _ = contact(name)
    frozen, _ = block.freeze(state, None)
    model = block.set_model(state, frozen, None, None)
    assert model is not None
    rng = np.random.default_rng(11)
    du = np.zeros((len(state.positions), N_COLUMNS))
    du[:, :3] = STEP * rng.uniform(-1.0, 1.0, size=(len(state.positions), 3))
    linear = model["gap"] + np.sum(model["values"] * du.ravel()[model["slots"]], axis=1)
    nodes = block.connectivity[model["points"], 0]
    moved, _ = block.tool.distance(state.positions[nodes] + du[nodes, :3], state.load_factor)
    np.testing.assert_allclose(linear, moved - block.offset[model["points"]], rtol=0, atol=1e-8)
    np.testing.assert_array_equal(model["active"], frozen.active)


def test_a_contact_without_a_frozen_set_gives_no_model():
    """Without a frozen set there is nothing to predict."""
    plain, state, _ = contact("plane")
    assert plain.set_model(state, None, None, None) is None
    rough, state, history = contact("plane", friction=MU)
    assert rough.set_model(state, history, None, None) is None


def frictional_model():
    """(block, state, frozen history, set model) of the rough plane of the conformance kit
    (its even nodes stick, its odd nodes slide: tests/test_interaction_conformance.py)."""
    block, state, history = contact("plane", friction=MU)
    frozen, _ = block.freeze(state, history)
    model = block.set_model(state, frozen, None, None)
    assert model is not None
    return block, state, frozen, model


def test_a_frictional_sets_rows_sum_to_its_frozen_forces():
    """The rows of the frozen set's members give the internal forces sum k g F: on the plane
    the block's own frozen law (k g n, the stick springs k_t s, the slip force mu k p along
    -v) to round-off (1e-12 of the largest), at stuck and at sliding nodes alike."""
    block, state, frozen, model = frictional_model()
    p, n, touching = block.touch(state, frozen)
    _, _, stuck, sliding = block.tangential(state, frozen, p, n, touching)
    assert stuck.sum() >= 1 and (sliding & (p > 0)).sum() >= 1
    on = model["active"]
    weights = (model["stiffness"] * model["gap"])[on][:, None] * model["forces"][on]
    rows = np.bincount(
        model["slots"][on].ravel(), weights.ravel(), len(state.positions) * N_COLUMNS
    ).reshape(-1, N_COLUMNS)[:, :3]
    own = np.zeros_like(rows)
    own[block.connectivity[:, 0]] = -block.contact_forces(state, frozen)
    np.testing.assert_allclose(rows, own, rtol=0, atol=1e-12 * np.abs(own).max())


def test_a_frictional_sets_rows_are_its_frozen_tangent_on_a_plane():
    """sum k F G^T over a member's rows is the block's tangent at the node (k n n^T, k_t (I -
    n n^T) stuck, -mu k v n^T sliding) to round-off: on a plane no curvature term is left
    out."""
    block, state, frozen, model = frictional_model()
    (own,) = block.tangent(state, frozen)
    blocks = own.blocks[:, 0, :, 0, :]  # (s, 3, 3) per contact node
    on = model["active"]
    f, g = model["forces"][on][:, :3], model["values"][on][:, :3]
    terms = model["stiffness"][on][:, None, None] * f[:, :, None] * g[:, None, :]
    rows = np.zeros_like(blocks)
    np.add.at(rows, model["points"][on], terms)
    np.testing.assert_allclose(rows, blocks, rtol=0, atol=1e-12 * np.abs(blocks).max())


def test_a_frictional_sets_stick_rows_follow_their_nodes_gap():
    """A stuck node's two stick rows are decided by its gap's row (``leader``): a node is in
    the set or out of it with its friction."""
    block, state, frozen, model = frictional_model()
    count = len(block.connectivity)
    assert len(model["points"]) > count
    np.testing.assert_array_equal(model["leader"][:count], np.arange(count))
    np.testing.assert_array_equal(model["points"][model["leader"]], model["points"])


def test_a_node_the_prediction_lands_is_frictionless_as_its_rows_are():
    """A node that joins a frictional set on the linear model has only its gap's row there
    (no stick or slip state: it was off the tool); in the set it joins it slides without a
    direction, so its force is the normal k p n alone until the set is frozen again at a
    converged state, where the return mapping gives it its friction."""
    block, state, history = contact("plane", friction=MU)
    frozen, _ = block.freeze(state, history)
    off = np.flatnonzero(~frozen.active)
    assert off.size >= 1
    joined = block.with_set(frozen, off, np.ones(off.size, bool), np.zeros(off.size))
    assert joined.active[off].all() and joined.sliding[off].all()
    p, n, _ = block.touch(state, joined)
    forces = block.contact_forces(state, joined)
    np.testing.assert_allclose(forces[off], (block.stiffness * p)[off, None] * n[off], atol=1e-15)
    kept = np.flatnonzero(frozen.active)
    np.testing.assert_array_equal(joined.sliding[kept], frozen.sliding[kept])
    np.testing.assert_array_equal(joined.direction[kept], frozen.direction[kept])


def test_a_new_set_changes_the_given_rows_alone():
    block, state, _ = contact("plane")
    frozen, _ = block.freeze(state, None)
    rows = np.array([0, 2])
    changed = block.with_set(frozen, rows, ~frozen.active[rows], np.zeros(2))
    np.testing.assert_array_equal(changed.active[rows], ~frozen.active[rows])
    others = np.setdiff1d(np.arange(len(frozen.active)), rows)
    np.testing.assert_array_equal(changed.active[others], frozen.active[others])
