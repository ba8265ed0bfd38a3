"""The shortcuts of an explicit forming run's contacts change nothing: the meshed die's
closest-facet search with each node's last facet as its hint (elements/facet_search.py) and
the contact forces answered from memory when asked again (ContactBlock.contact_forces) give a
run identical to the last bit to one without them; so does the compiled contact pass of the
tools (elements/tool_contact.py) against the numpy formulas."""

import numpy as np

from elements.contact import ContactBlock
from elements.rigid_surface import RigidSurface
from solvers import CentralDifference
from validation.cases import hemisphere_forming as case


def formed():
    """The hemisphere case at 12 cells, the punch's stroke in 0.02 s (into the die within
    the run): the last positions and the punch's forces at every record."""
    mesh, model = case.model(12, "fibrous")
    result = CentralDifference(
        duration=0.02, damping=case.DAMPING, progress=False, kinetic_bound=None
    ).solve(model)
    return result.frames[-1].positions, result.tool_forces


def test_a_forming_run_is_the_same_to_the_last_bit_without_its_shortcuts(monkeypatch):
    """The run with every shortcut on against one with all of them off, bit for bit: the
    die's hints and the forces from memory; the compiled pass of the punch (a sphere), the
    holder (a ring along z) and the meshed die (elements/tool_contact.py) against
    ContactBlock's numpy formulas; the die's candidate lists searched again in batches
    (REBUILD_SHARE) and each node's nearest facet kept while it cannot change (KEEP_NEAREST,
    elements/facet_search.py), with the short lists between the two (SHORT_LISTS), against
    the lists searched again node by node past the margin
    and scanned at every step (the nodes beyond the search distance, told a distance that
    depends on when they were searched, touch nothing). Two runs, not one per shortcut (5 s
    of CPU each): a shortcut that changed a bit would show in the pair, which a run with that
    shortcut alone off then names."""
    from elements import rigid_surface as tools
    from elements import tool_contact

    positions, forces = formed()
    assert np.abs(forces[-1]).max() > 1.0  # the tools pressed the blank
    assert tools.REBUILD_SHARE < 1.0 and tools.KEEP_NEAREST and tools.SHORT_LISTS

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
    monkeypatch.setattr(tool_contact, "compiled_pass_applies", lambda *args: False)
    monkeypatch.setattr(tools, "REBUILD_SHARE", 1.0)
    monkeypatch.setattr(tools, "KEEP_NEAREST", False)
    plain_positions, plain_forces = formed()
    np.testing.assert_array_equal(positions, plain_positions)
    np.testing.assert_array_equal(forces, plain_forces)


def test_the_die_s_compiled_pass_without_the_short_lists_is_the_same_run(monkeypatch):
    """The die's compiled contact pass reads each node's facet from the short lists' copies;
    without the short lists (SHORT_LISTS off) it makes those rows from the die's corners and
    normals by facet: the same run to the last bit."""
    from elements import rigid_surface as tools

    positions, forces = formed()
    monkeypatch.setattr(tools, "SHORT_LISTS", False)
    plain_positions, plain_forces = formed()
    np.testing.assert_array_equal(positions, plain_positions)
    np.testing.assert_array_equal(forces, plain_forces)
