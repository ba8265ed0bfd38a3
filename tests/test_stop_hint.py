"""What a stopped Static solve suggests after its reason (solvers/stop_diagnosis.py
``stop_hint``): on a model with contacts, more increments or dynamic relaxation (a contact
closing, opening or sliding inside an increment stops Newton, and the arc length follows a
limit point, not a contact's events); on a model without, the arc length for a load path and
smaller increments for an arc-length one."""

from types import SimpleNamespace

import numpy as np

from femcore.interaction import InteractionBlock
from solvers.stop_diagnosis import stop_hint


class _Tie(InteractionBlock):
    """An interaction without a meshed tool (its ``facet_record`` the protocol's None)."""

    dofs = ("ux", "uy", "uz")
    connectivity = np.zeros((0, 2), dtype=np.int64)

    def internal_force(self, state, history=None):
        return np.zeros_like(state.positions), None

    def strain_energy(self, state, history=None):
        return 0.0


def test_a_model_with_contacts_is_sent_to_more_increments_not_to_the_arc_length():
    hint = stop_hint(SimpleNamespace(interactions=[_Tie()]), None, "load")
    assert "interactions (contacts" in hint and "more increments" in hint
    assert "try path='arc_length'" not in hint


def test_a_model_without_contacts_keeps_the_limit_points_hint():
    assert "try path='arc_length'" in stop_hint(SimpleNamespace(interactions=[]), None, "load")
    hint = stop_hint(SimpleNamespace(interactions=[]), None, "arc_length")
    assert "smaller increments" in hint
