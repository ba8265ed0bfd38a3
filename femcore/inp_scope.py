"""The scopes of an Abaqus/CAE deck: a part's mesh and the assembly's own nodes and sets.

Abaqus/CAE writes a part's nodes, elements and sets between *PART and *END PART, and the
assembly's between *ASSEMBLY and *END ASSEMBLY: a reference point is an assembly *NODE
numbered from 1 like the part's nodes, and an assembly set is another set than a part's set
of the same name (the part's is ``Plate-1.Set-1`` in the assembly; Abaqus Analysis User's
Guide, "Defining an assembly"). Labels and names are scoped; the reader's mesh is one flat
numbering and one set per name. So, for the one unmoved instance the reader takes
(femcore.mesh_io): an assembly *NODE (a reference point, in no element of the part) is left
out, with its NSET= and the assembly's sets without INSTANCE= (they name the assembly's own
nodes and elements), each named in a warning; an assembly set with INSTANCE= names the
instance's labels, which are the part's; and a set name defined both in a part and in the
assembly is refused naming both lines, rather than merged into one set.
"""

from __future__ import annotations

from dataclasses import dataclass, field

__all__ = ["DeckScopes"]


@dataclass
class DeckScopes:
    """Where the keyword lines of a deck stand, fed each keyword line in deck order.

    Attributes
    ----------
    scope : str
        "" (a flat deck, or between blocks), "part", "assembly" or "instance".
    left_out : list[str]
        "deck.inp: line 40: *NODE (a reference point)", what is not read, in deck order.
    set_places : dict[tuple[str, str, str], str]
        (NSET or ELSET, the set's name, "part" or "assembly") -> the place it is first
        defined at.
    """

    scope: str = ""
    left_out: list[str] = field(default_factory=list)
    set_places: dict[tuple[str, str, str], str] = field(default_factory=dict)

    def enter(self, keyword: str) -> None:
        """Follow a keyword line (upper case, e.g. "END PART") into its scope."""
        self.scope = {
            "PART": "part",
            "END PART": "",
            "ASSEMBLY": "assembly",
            "INSTANCE": "instance",
            "END INSTANCE": "assembly",
            "END ASSEMBLY": "",
        }.get(keyword, self.scope)

    def assembly_own(self, keyword: str, parameters: dict[str, str], where: str) -> bool:
        """Whether the *NODE, *NSET or *ELSET line at ``where`` defines the assembly's own
        nodes or sets (not the instance's): it is then left out, and noted in
        ``left_out``."""
        if self.scope != "assembly" or "INSTANCE" in parameters:
            return False
        what = "a reference point's node" if keyword == "NODE" else "the assembly's own set"
        name = parameters.get(keyword, "")
        named = f" {name}" if name and keyword != "NODE" else ""
        self.left_out.append(f"{where}: *{keyword}{named} ({what})")
        return True

    def check_set(self, kind: str, key: str, shown: str, where: str) -> None:
        """Note a set defined at ``where`` (``key``: its name as compared); ValueError when
        the same name is a part's set and an assembly's."""
        scope = "part" if self.scope in ("part", "instance") else self.scope
        if scope not in ("part", "assembly"):
            return
        self.set_places.setdefault((kind, key, scope), where)
        other_scope = "part" if scope == "assembly" else "assembly"
        other = self.set_places.get((kind, key, other_scope))
        if other is not None:
            places = {scope: where, other_scope: other}
            raise ValueError(
                f"{where}: *{kind} {shown!r} is defined in the part ({places['part']}) and in "
                f"the assembly ({places['assembly']}): Abaqus keeps them apart (the part's is "
                "'<instance>.name' in the assembly), the reader's mesh has one set per name; "
                "rename one of them"
            )

    def warning(self) -> str | None:
        """The warning naming what is left out (each with its file and line), None when
        nothing is."""
        if not self.left_out:
            return None
        shown = "; ".join(self.left_out[:4]) + ("; ..." if len(self.left_out) > 4 else "")
        return (
            f"The assembly's own nodes and sets are left out ({shown}): Abaqus numbers "
            "them apart from the part's (a reference point's node 1 is not the part's node 1); "
            "the reader keeps the part's mesh and the sets given with INSTANCE="
        )
