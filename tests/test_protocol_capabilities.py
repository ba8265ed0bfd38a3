"""The capabilities the solvers ask of elements and interactions beyond forces, energies and
tangents, as members of the two protocols (femcore/element.py, femcore/interaction.py): the
defaults on the base classes are what the solvers assume of a block that lacks one, a user's
block that declares one is treated as the project's own are (the solvers call the protocol,
never ask what a block is), and the kits (femcore/capability_checks.py) name a declaration of
the wrong type or one the solvers would misread."""

from __future__ import annotations

from contextlib import contextmanager
from types import SimpleNamespace

import numpy as np
import pytest

from elements import Cable
from femcore import Mesh, Model
from femcore.capability_checks import check_element_capabilities, check_interaction_capabilities
from femcore.element import ElementBlock
from femcore.interaction import FacetRecord
from solvers.newton import curves_with_contact, imposes_alone, opens_on_ramp
from solvers.newton_fibres import fibre_edges
from solvers.penalty_start import softened
from solvers.stop_diagnosis import crossing_cycles
from tests.conformance_cases import CABLE
from tests.test_custom_interaction import PlaneContact, PlaneContactBlock
from tests.test_interaction_conformance import floor


class _Bar(ElementBlock):
    """An element block with the protocol's required members only."""

    dofs = ("ux", "uy", "uz")
    reach = 1
    connectivity = np.array([[0, 1]])

    def lumped_mass(self, state, density_scale=None):
        return np.ones(2), None

    def internal_force(self, state, history=None):
        return np.zeros((2, 3)), None

    def cell_stable_dt(self, state):
        return np.ones(1)

    def strain_energy(self, state, history=None):
        return 0.0


def _user(block, **members):
    """``block`` as an instance of a subclass of its class with ``members``."""
    block.__class__ = type(f"User{type(block).__name__}", (type(block),), members)
    return block


def test_the_defaults_are_what_the_solvers_assume_of_a_block_without_the_capability():
    bar = _Bar()
    assert bar.compression_free_tangent is False and bar.has_fibre_strains is False
    assert bar.tangent_compression_free(None) is None  # its tangent: the assembler's
    edges = bar.fibre_edges()
    assert edges.shape == (0, 2) and edges.dtype == np.int64
    with pytest.raises(NotImplementedError, match="has_fibre_strains"):
        bar.fibre_strains(None)
    block, state, history = floor()
    assert block.friction == 0.0 and block.unilateral_fallback is True
    assert block.opening_law is None and block.released(history) is history
    assert block.gaps_decide(None) is True and block.gaps_decide(history) is False
    assert block.set_model(state, history, None, None) is None
    with pytest.raises(NotImplementedError, match="set_model"):
        block.with_set(history, np.zeros(0, int), np.zeros(0, bool), np.zeros(0))
    with block.softened_penalty(0.5) as soft:
        assert soft is False
    assert block.facet_record() is None
    check_interaction_capabilities(block, state, history)


def _soft(self, share):
    """A user floor's soft start: its stiffness times ``share`` inside, restored after."""

    @contextmanager
    def scaled():
        kept = self.stiffness
        self.stiffness = share * kept
        try:
            yield True
        finally:
            self.stiffness = kept

    return scaled()


@contextmanager
def _left_changed(self, share):
    """A soft start that forgets to restore the penalty."""
    self.stiffness *= share
    yield True


def test_a_users_interaction_that_takes_a_soft_start_is_softened_by_static():
    block, state, history = floor()
    _user(block, softened_penalty=_soft)
    before, _ = block.internal_force(state, history)
    assert np.abs(before).max() > 0.0
    with softened(SimpleNamespace(interactions=[block]), 0.25) as soft:
        assert soft
        inside, _ = block.internal_force(state, history)
        np.testing.assert_allclose(inside, 0.25 * before, rtol=1e-15)  # k p: linear in k
    np.testing.assert_array_equal(block.internal_force(state, history)[0], before)
    check_interaction_capabilities(block, state, history)


def test_the_static_solver_reads_friction_gaps_and_opening_law_through_the_protocol():
    block, _, history = floor()
    model = SimpleNamespace(parts=[block], interactions=[block])
    assert not imposes_alone(model) and not opens_on_ramp(model)
    assert curves_with_contact(model, (None,)) and not curves_with_contact(model, (history,))
    _user(block, friction=0.3, gaps_decide=lambda self, h: True)
    assert imposes_alone(model) and curves_with_contact(model, (history,))


def test_the_fibre_edges_of_a_users_element_reach_the_fibre_projection():
    bar = _user(_Bar(), fibre_edges=lambda self: np.array([[1, 0]]))
    model = SimpleNamespace(blocks=[_Bar(), bar], parts=[_Bar(), bar], n_nodes=2)
    np.testing.assert_array_equal(fibre_edges(model), [[0, 1]])
    assert fibre_edges(SimpleNamespace(blocks=[_Bar()], parts=[], n_nodes=2)).shape == (0, 2)


@pytest.mark.parametrize(
    "edges", [np.array([[0, 99]]), np.zeros((1, 3), int), np.array([[0.0, 1.0]])]
)
def test_fibre_edges_off_the_mesh_or_of_another_shape_are_refused_naming_the_block(edges):
    """Read by Static's fibre projection: a node past the mesh was a bare IndexError deep
    in it, a third column silently dropped."""
    bar = _user(_Bar(), fibre_edges=lambda self: edges)
    model = SimpleNamespace(blocks=[bar], parts=[bar], n_nodes=2)
    with pytest.raises(ValueError, match=r"User_Bar.fibre_edges\(\) gave an array of shape"):
        fibre_edges(model)


def test_a_node_cycling_across_a_users_meshed_crease_is_named():
    """Two facets meeting at the edge (0,0,0)-(1,0,0) at 30 deg; the block's one row (node 7)
    on each in turn eight times: six switches or more make a cycle (stop_diagnosis)."""
    tilt = np.radians(30.0)
    corners = np.array(
        [
            [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, -1.0, 0.0]],
            [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, np.cos(tilt), np.sin(tilt)]],
        ]
    )
    normals = np.array([[0.0, 0.0, 1.0], [0.0, -np.sin(tilt), np.cos(tilt)]])
    record = np.array([[0, 1, 0, 1, 0, 1, 0, 1]])
    block = _user(floor()[0], facet_record=lambda self: FacetRecord(record, corners, normals))
    block.connectivity = np.array([[7]])
    (cycle,) = crossing_cycles(SimpleNamespace(interactions=[block]))
    assert cycle["node"] == 7 and cycle["facets"] == (0, 1) and cycle["switches"] == 7
    assert cycle["angle_deg"] == pytest.approx(30.0, abs=1e-12)


@pytest.mark.parametrize(
    "members, message",
    [
        ({"friction": -0.1}, "friction is -0.1"),
        ({"friction": True}, "friction is True"),
        ({"unilateral_fallback": "no"}, "True or False expected"),
        ({"unilateral_fallback": False}, "keeps no contact set"),
        ({"opening_law": "explicit"}, "one of"),
        ({"opening_law": "ramp"}, "without its own released and freeze"),
        ({"gaps_decide": lambda self, h: False}, "gaps_decide\\(None\\) is not True"),
        ({"set_model": lambda self, *a: None}, "without its own with_set"),
        ({"softened_penalty": _left_changed}, "softened_penalty changed the forces"),
        ({"tool_penetrations": lambda self, *a: []}, "tool_penetrations gave 0 entries"),
        (
            {"tool_penetrations": lambda self, *a: [{"deepest_mm": -1.0}] * self.n_tools},
            "finite depth >= 0",
        ),
        ({"tool_facing": lambda self, *a: [None, None, None]}, "tool_facing gave 3 entries"),
        ({"tool_displacements": lambda self, *a: np.zeros(3)}, "tool_displacements gave shape"),
        (
            {"tool_facing": lambda self, *a: [np.ones((2, 3))] * self.n_tools},
            "not \\(s, 3\\) unit vectors",
        ),
    ],
)
def test_the_interaction_kit_names_a_declaration_the_solvers_would_misread(members, message):
    block, state, history = floor()
    check_interaction_capabilities(block, state, history)  # the user's floor conforms
    _user(block, **members)
    with pytest.raises(AssertionError, match=message):
        check_interaction_capabilities(block, state, history)


def _cable_block():
    model = CABLE.model()
    return model.blocks[0], model.initial_state(), CABLE.deformed(model)


@pytest.mark.parametrize(
    "members, message",
    [
        ({"compression_free_tangent": 1}, "True or False expected"),
        ({"compression_free_tangent": True}, "without its own tangent_compression_free"),
        ({"tangent_compression_free": lambda self, s, h=None: []}, "never asks for it"),
        ({"has_fibre_strains": True}, "without its own fibre_strains"),
        (
            {
                "has_fibre_strains": True,
                "fibre_strains": lambda self, s: np.full((len(self.connectivity), 1), 1e-6),
                "fibre_strain_gradient": lambda self, s: (),
                "fibre_strain_range": lambda self: (np.array([-1.0]), np.array([1.0])),
            },
            "reference is unstrained",
        ),
        (
            {
                "has_fibre_strains": True,
                "fibre_strains": lambda self, s: np.zeros((len(self.connectivity), 1)),
                "fibre_strain_gradient": lambda self, s: (),
                "fibre_strain_range": lambda self: (np.array([-1.0, -1.0]), np.array([1.0, 1.0])),
            },
            "one bound per column of fibre_strains",
        ),
        (
            {
                "has_fibre_strains": True,
                "fibre_strains": lambda self, s: np.zeros((len(self.connectivity), 1)),
                "fibre_strain_gradient": lambda self, s: (),
                "fibre_strain_range": lambda self: (np.array([-1.0]), np.array([0.0])),
            },
            "lower < 0 < upper",
        ),
        ({"fibre_strains": lambda self, s: None}, "never asks for them"),
        ({"fibre_edges": lambda self: np.array([[0, 0]])}, "two distinct nodes"),
        ({"fibre_edges": lambda self: np.zeros((1, 3), int)}, "a \\(k, 2\\) int array"),
    ],
)
def test_the_element_kit_names_a_declaration_the_solvers_would_misread(members, message):
    block, reference, deformed = _cable_block()
    check_element_capabilities(block, reference, deformed)  # the cable as it is conforms
    _user(block, **members)
    with pytest.raises(AssertionError, match=message):
        check_element_capabilities(block, reference, deformed)


@pytest.mark.parametrize(
    "members, message",
    [
        ({"friction": "0.3"}, "friction is '0.3': expected a finite number >= 0"),
        ({"friction": np.nan}, "friction is nan"),
        ({"unilateral_fallback": None}, "unilateral_fallback is None: expected True or False"),
        ({"opening_law": "Ramp"}, "opening_law is 'Ramp': expected one of"),
    ],
)
def test_an_interactions_capability_of_the_wrong_type_is_refused_at_compile(members, message):
    """Bad input at the API boundary: the model refuses it before any solver reads it."""
    model = Model(Mesh.line([0.0, 0.0, 0.0], [10.0, 0.0, 0.0], 2))
    model.add(Cable(axial_stiffness=1e3, mass_per_length=1e-6))
    floor_type = type("UserFloor", (PlaneContactBlock,), members)
    model.interact(type("UserPlane", (PlaneContact,), {"block_class": floor_type})("end", 10.0))
    with pytest.raises(ValueError, match=message):
        model.compile()


def test_an_elements_capability_flag_of_the_wrong_type_is_refused_at_compile():
    class FlaggedCable(Cable):
        def bind(self, mesh, cell_ids, directors):
            block = super().bind(mesh, cell_ids, directors)
            return _user(block, has_fibre_strains="yes")

    model = Model(Mesh.line([0.0, 0.0, 0.0], [10.0, 0.0, 0.0], 2))
    model.add(FlaggedCable(axial_stiffness=1e3, mass_per_length=1e-6))
    with pytest.raises(ValueError, match="has_fibre_strains is 'yes': expected True or False"):
        model.compile()


def test_an_element_block_without_its_cells_ids_is_refused_when_compiled():
    """A block that does not keep bind's cell_ids ran under the explicit solver and stopped
    Static with a bare AttributeError; it is refused naming the attribute."""

    class Forgetful(Cable):
        def bind(self, mesh, cell_ids, directors):
            block = super().bind(mesh, cell_ids, directors)
            del block.cell_ids
            return block

    model = Model(Mesh.line((0.0, 0.0, 0.0), (10.0, 0.0, 0.0), 4))
    model.add(Forgetful(axial_stiffness=1e3, mass_per_length=1e-9))
    with pytest.raises(ValueError, match=r"cell_ids is missing: a block keeps the mesh ids"):
        model.compile()


def test_an_element_type_without_dofs_or_cell_type_is_refused_naming_it():
    """The README's type declares dofs and cell_type as its block does: one without them
    was a bare AttributeError, or an 'empty DOF list' naming no type."""

    class Bare(Cable):
        cell_type = None

    with pytest.raises(ValueError, match=r"Bare.cell_type is None: expected one of"):
        Model(Mesh.line((0.0, 0.0, 0.0), (10.0, 0.0, 0.0), 4)).add(Bare(1e3, 1e-9))

    class Silent(Cable):
        dofs = ()

    with pytest.raises(ValueError, match=r"Silent.dofs is \(\): the element type declares"):
        Model(Mesh.line((0.0, 0.0, 0.0), (10.0, 0.0, 0.0), 4)).add(Silent(1e3, 1e-9))
