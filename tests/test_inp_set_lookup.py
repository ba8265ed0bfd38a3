"""A deck's set names, found by every lookup as Abaqus reads them, and never given twice.

Reference: the Abaqus Analysis User's Guide, "Input syntax rules": a label without quotes is
read in any case and without its blanks, so ``Upper``, ``UPPER`` and ``up per`` name one set.
A mesh read from a deck finds its sets so (femcore.set_names) in Mesh.nodes, Model.add and
PlyContact alike, and refuses a new set of a name Abaqus would read as one it has. Decks of a
few nodes; the sets expected are read off their text.
"""

from pathlib import Path

import numpy as np
import pytest

from elements import MindlinShell
from elements.ply_contact import PlyContact
from femcore import Mesh, Model
from femcore.set_names import set_named
from materials import ElasticShell

TWO_PLIES = """*Node
1, 0., 0., 0.
2, 10., 0., 0.
3, 10., 10., 0.
4, 0., 10., 0.
11, 0., 0., 1.
12, 10., 0., 1.
13, 10., 10., 1.
14, 0., 10., 1.
*Element, type=S4R, elset=Lower
1, 1, 2, 3, 4
*Element, type=S4R, elset=Upper
2, 11, 12, 13, 14
*Nset, nset=Top
11, 12, 13, 14
"""


def two_plies(tmp_path: Path) -> Mesh:
    path = tmp_path / "twoply.inp"
    path.write_text(TWO_PLIES)
    return Mesh.read(path)


def bound_upper(mesh: Mesh, upper: str, lower: str) -> np.ndarray:
    """The upper nodes of the ply contact ``PlyContact(upper, lower)`` on the two plies."""
    model = Model(mesh)
    shell = ElasticShell(E=70e3, nu=0.3, thickness=0.2, density=2.7e-9)
    model.add(MindlinShell(shell), cells="lower")  # the deck writes Lower
    model.add(MindlinShell(shell), cells="UPPER")
    model.interact(PlyContact(upper, lower, 0.1, 0.1, penalty=50.0))
    return model.compile().interactions[0].upper


@pytest.mark.parametrize(
    "upper, lower", [("UPPER", "LOWER"), ("upper", "lower"), ("Up per", "L ower"), ("TOP", "lower")]
)
def test_ply_contact_finds_a_deck_s_sets_by_any_spelling_abaqus_takes(tmp_path, upper, lower):
    """Refused before ("no triangle or node set named 'UPPER'") where Model.add found it."""
    mesh = two_plies(tmp_path)
    np.testing.assert_array_equal(bound_upper(mesh, upper, lower), [4, 5, 6, 7])


def test_ply_contact_names_stay_exact_on_a_mesh_not_read_from_a_deck(tmp_path):
    mesh = two_plies(tmp_path)
    exact = Mesh(mesh.points, mesh.triangles, element_sets=dict(mesh.element_sets))
    model = Model(exact)
    shell = ElasticShell(E=70e3, nu=0.3, thickness=0.2, density=2.7e-9)
    model.add(MindlinShell(shell))
    model.interact(PlyContact("UPPER", "Lower", 0.1, 0.1, penalty=50.0))
    with pytest.raises(ValueError, match=r"no triangle or node set named 'UPPER'"):
        model.compile()


STRIP = """*NODE
1, 0., 0., 0.
2, 10., 0., 0.
3, 10., 5., 0.
4, 0., 5., 0.
*ELEMENT, TYPE=S3, ELSET=Skin
1, 1, 2, 3
2, 1, 3, 4
*NSET, NSET=Tip
2, 3
"""


@pytest.mark.parametrize("name", ["TIP", "tip", "T ip"])
def test_a_set_named_as_a_deck_s_set_up_to_case_or_blanks_is_refused_as_used(tmp_path, name):
    """Accepted before as a second set, which Mesh.nodes then called unknown ('tip') or
    Mesh.write refused: Abaqus reads both names as one."""
    path = tmp_path / "strip.inp"
    path.write_text(STRIP)
    mesh = Mesh.read(path)
    with pytest.raises(ValueError, match=rf"node set name '{name}' is already used, as 'Tip'"):
        mesh.add_node_set(name, [0])
    skin = {"TIP": "SKIN", "tip": "skin", "T ip": "S kin"}[name]
    with pytest.raises(ValueError, match=rf"name '{skin}' is already used, as 'Skin'"):
        mesh.add_element_set(skin, [0])
    np.testing.assert_array_equal(mesh.nodes(name), [1, 2])


def test_a_lookup_matching_several_sets_up_to_case_says_it_is_ambiguous():
    with pytest.raises(ValueError, match=r"'tip' is ambiguous: the sets \['Tip', 'TIP'\]"):
        set_named(["Tip", "TIP"], "tip", fold=True)
    assert set_named(["Tip", "TIP"], "tip", fold=False) == "tip"  # exact names: unknown


def test_a_case_set_named_as_a_deck_s_set_up_to_case_is_refused(tmp_path):
    from fibreshell.case import load_case

    (tmp_path / "strip.inp").write_text(STRIP)
    case = tmp_path / "case.toml"
    case.write_text(
        '[mesh]\nfile = "strip.inp"\n[sets]\nTIP = { x_min = "50%" }\n[[part]]\n'
        'element = "fibrous"\nmaterial = { thickness = 0.5, areal_density = 1e-10, '
        "tension = 1000.0, shear = 0.5, bending = 1.0 }\n"
        '[solver]\nkind = "static"\nincrements = 1\n'
    )
    with pytest.raises(ValueError, match=r"\[sets.TIP\]: node set name 'TIP' is already used"):
        load_case(case)
