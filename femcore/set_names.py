"""Set names looked up as Abaqus reads them, for the meshes of decks.

Abaqus reads a label without quotes in any case and without its blanks (Analysis User's
Guide, "Input syntax rules"): a deck's ``*NSET, NSET=Tip`` is the set a case file or a load
calls ``TIP``. A mesh read from a deck keeps each set under the name the deck first writes
(femcore.inp_sets) and finds it by any spelling Abaqus takes for it; a mesh of gmsh or of
Python keeps its names exact, where ``Tip`` and ``TIP`` may be two sets.
"""

from __future__ import annotations

from collections.abc import Iterable

__all__ = ["abaqus_key", "set_named"]


def abaqus_key(name: str) -> str:
    """The name as Abaqus compares it: upper case, without blanks."""
    return "".join(name.split()).upper()


def set_named(names: Iterable[str], name: str, fold: bool) -> str:
    """The set ``name`` means among ``names``: itself when it is one or when ``fold`` is
    False, else the one name equal to it up to case and blanks (``name`` itself when none
    is, for the caller's unknown-set message). Every lookup of a set by a user's name goes
    through here (Mesh.nodes, Model.add, PlyContact).

    Raises
    ------
    ValueError
        When ``fold`` and several names equal ``name`` up to case and blanks (a mesh whose
        sets were given so; Mesh.add_node_set and add_cell_set refuse the second one).
    """
    names = list(names)
    if not fold or name in names:
        return name
    key = abaqus_key(name)
    matches = [known for known in names if abaqus_key(known) == key]
    if len(matches) > 1:
        raise ValueError(
            f"the set name {name!r} is ambiguous: the sets {matches} are all it, read as "
            "Abaqus reads names (in any case and without blanks); rename all but one"
        )
    return matches[0] if matches else name
