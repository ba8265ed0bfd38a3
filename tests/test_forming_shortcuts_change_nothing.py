"""The shortcuts of an explicit forming run's contacts change nothing: the meshed die's
closest-facet search with each node's last facet as its hint (elements/facet_search.py) and
the contact forces answered from memory when asked again (ContactBlock.contact_forces) give a
run identical to the last bit to one without them; so does the compiled contact pass of the
tools (elements/tool_contact.py) against the numpy formulas."""

import numpy as np
import pytest

from elements.contact import ContactBlock
from elements.rigid_surface import RigidSurface
from solvers import CentralDifference
from validation.cases import hemisphere_forming as case


def formed():
    """The hemisphere case at 12 cells, the punch's stroke in 0.02 s (into the die within
    the run): the last positions and the punch's forces at every record."""
    mesh, model = case.model(12, "fibrous")
    result = CentralDifference(duration=0.02, damping=case.DAMPING, progress=False).solve(model)
    return result.frames[-1].positions, result.tool_forces


@pytest.fixture(scope="module")
def with_shortcuts():
    """``formed()`` with every shortcut on, run once for the three comparisons (set up
    before any test's monkeypatch): its arrays read-only, so that no test alters the
    reference of the others."""
    positions, forces = formed()
    positions.setflags(write=False)
    forces.setflags(write=False)
    return positions, forces


def test_a_forming_run_is_the_same_to_the_last_bit_without_the_hints_and_the_memory(
    monkeypatch, with_shortcuts
):
    positions, forces = with_shortcuts
    assert np.abs(forces[-1]).max() > 1.0  # the tools pressed the blank

    kept = RigidSurface._kept_lists  # what the numpy and the compiled die's pass start from
    asked = ContactBlock.contact_forces

    def without_hint(self, count):
        self._hint = np.zeros(0, dtype=np.int64)
        return kept(self, count)

    def without_memory(self, state, history=None):
        self._last_forces = None
        return asked(self, state, history)

    monkeypatch.setattr(RigidSurface, "_kept_lists", without_hint)
    monkeypatch.setattr(ContactBlock, "contact_forces", without_memory)
    plain_positions, plain_forces = formed()
    np.testing.assert_array_equal(positions, plain_positions)
    np.testing.assert_array_equal(forces, plain_forces)


def test_a_forming_run_is_the_same_to_the_last_bit_with_the_numpy_contact_of_the_tools(
    monkeypatch, with_shortcuts
):
    """The compiled pass of the punch (a sphere), the holder (a ring along z) and the meshed
    die (elements/tool_contact.py) against ContactBlock's numpy formulas over a whole run."""
    from elements import tool_contact

    positions, forces = with_shortcuts
    monkeypatch.setattr(tool_contact, "compiled_pass_applies", lambda *args: False)
    plain_positions, plain_forces = formed()
    np.testing.assert_array_equal(positions, plain_positions)
    np.testing.assert_array_equal(forces, plain_forces)


def test_a_forming_run_is_the_same_to_the_last_bit_with_the_dies_lists_as_they_were(
    monkeypatch, with_shortcuts
):
    """The die's candidate lists searched again in batches (REBUILD_SHARE) and each node's
    nearest facet kept while it cannot change (KEEP_NEAREST, elements/facet_search.py)
    against the lists searched again node by node past the margin and scanned at every
    step: the same run, bit for bit (the nodes beyond the search distance, told a distance
    that depends on when they were searched, touch nothing)."""
    from elements import rigid_surface as tools

    positions, forces = with_shortcuts
    assert tools.REBUILD_SHARE < 1.0 and tools.KEEP_NEAREST
    monkeypatch.setattr(tools, "REBUILD_SHARE", 1.0)
    monkeypatch.setattr(tools, "KEEP_NEAREST", False)
    plain_positions, plain_forces = formed()
    np.testing.assert_array_equal(positions, plain_positions)
    np.testing.assert_array_equal(forces, plain_forces)
