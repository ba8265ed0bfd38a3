"""The frictionless tool contact's frozen set as the linear model the static solver predicts
the next set on (elements/contact_set_model.py): each node's row of dg/dq is the tool's normal
on its translations, so g + G dq is the gap of the moved node to first order; with friction,
or without a frozen set, there is no model."""

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


def test_a_frictional_contact_or_one_without_a_frozen_set_gives_no_model():
    """With friction the stick and slip sets are frozen with the contact set, and the linear
    model does not choose them; without a frozen set there is nothing to predict."""
    block, state, history = contact("plane", friction=MU)
    frozen, _ = block.freeze(state, history)
    assert block.set_model(state, frozen, None, None) is None
    plain, state, _ = contact("plane")
    assert plain.set_model(state, None, None, None) is None


def test_a_new_set_changes_the_given_rows_alone():
    block, state, _ = contact("plane")
    frozen, _ = block.freeze(state, None)
    rows = np.array([0, 2])
    changed = block.with_set(frozen, rows, ~frozen.active[rows], np.zeros(2))
    np.testing.assert_array_equal(changed.active[rows], ~frozen.active[rows])
    others = np.setdiff1d(np.arange(len(frozen.active)), rows)
    np.testing.assert_array_equal(changed.active[others], frozen.active[others])
