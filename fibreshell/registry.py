"""The element types and materials a case file can name: the project's own and a user's.

A case file names its element by ``element = "name"`` and a material preset by
``material = "name"`` (or ``material = { preset = "name", ... }``). The names come from two
registries, one for element types and one for materials; each holds the project's built-in
entries and takes a user's in two ways:

1. a call, before the case is read::

       import fibreshell.registry
       fibreshell.registry.register_element("cst", MyMembrane)
       fibreshell.registry.register_material("my_film", my_film)

2. a Python entry point of an installed distribution, in the group ``fibreshell.elements`` or
   ``fibreshell.materials`` (in the distribution's pyproject.toml)::

       [project.entry-points."fibreshell.elements"]
       cst = "my_package.membrane:MyMembrane"
       [project.entry-points."fibreshell.materials"]
       my_film = "my_package.membrane:my_film"

   An entry point is loaded only when a case names it and no registered entry has that name,
   so that an installed plugin costs nothing to the cases that do not use it and a broken one
   fails only the cases that name it. Entry points also reach the worker processes of a sweep
   or an identification, which a ``register_*`` call made in the parent process does not.

A name is registered once: registering it again raises ValueError unless ``replace=True``.
An unknown name raises ValueError naming every known one (``fibreshell.case`` turns it into a
CaseError naming the file, the table and the key).

How a case file's part reaches a user's element type (the built-in "fibrous", "mindlin" and
"cable" keep their own rules, fibreshell/case.py): the type is called with the part's
``options`` table as keyword arguments, and with ``material=`` the part's material if the
part gives one: a preset name or ``{ preset = "name", ... }`` is built first (the registered
factory, called with the table's other keys as its keywords), any other table is passed as a
plain dict for the type to read. A type that wants to take a case file's part differently
defines a classmethod ``from_case(material, **options)``, called instead of the constructor;
either way the keyword names are checked against the signature, so that an unknown option is
an error that names the ones the type takes.
"""

from __future__ import annotations

import importlib.metadata
from collections.abc import Callable
from typing import Any

from elements import Cable, ElementType, FibrousShell, MindlinShell
from materials import presets

__all__ = [
    "BUILTIN_ELEMENTS",
    "ELEMENTS",
    "ELEMENT_GROUP",
    "MATERIALS",
    "MATERIAL_GROUP",
    "Registry",
    "check_element_type",
    "check_material_factory",
    "element_names",
    "element_type",
    "material_factory",
    "register_element",
    "register_material",
]

ELEMENT_GROUP = "fibreshell.elements"
MATERIAL_GROUP = "fibreshell.materials"

# The element types whose case-file parts fibreshell/case.py builds by their own rules.
BUILTIN_ELEMENTS: dict[str, type[ElementType]] = {
    "fibrous": FibrousShell,
    "mindlin": MindlinShell,
    "cable": Cable,
}


class Registry:
    """Names of one kind of thing (element types, or material factories) a case may use.

    Parameters
    ----------
    kind : str
        What is named, for messages: "element", "material".
    group : str
        The entry-point group searched for a name no entry has.
    check : callable
        ``check(name, value)`` raises TypeError when ``value`` cannot be registered.
    builtins : dict
        The project's own entries, registered first.
    """

    def __init__(
        self,
        kind: str,
        group: str,
        check: Callable[[str, Any], None],
        builtins: dict[str, Any],
    ):
        self.kind = kind
        self.group = group
        self.check = check
        self.entries: dict[str, Any] = {}
        for name, value in builtins.items():
            self.register(name, value)

    def register(self, name: str, value: Any, replace: bool = False) -> None:
        """Make ``value`` known under ``name``; ValueError if the name is taken and not
        ``replace``, TypeError if ``value`` is not of the registry's kind."""
        if not isinstance(name, str) or not name.strip():
            raise ValueError(f"a {self.kind} name must be a non-empty string, got {name!r}")
        self.check(name, value)
        # The same value again is no conflict: a user's module imported twice registers twice.
        if name in self.entries and not replace and self.entries[name] is not value:
            raise ValueError(
                f"{self.kind} {name!r} is already registered ({self.entries[name]!r}); "
                f"pass replace=True to replace it"
            )
        self.entries[name] = value

    def get(self, name: str) -> Any:
        """The entry of ``name``, loading the entry point of that name if no entry has it.

        Raises
        ------
        ValueError
            No entry and no entry point has that name (the message lists the known names), or
            its entry point cannot be loaded or gives something of another kind.
        """
        if isinstance(name, str) and name in self.entries:
            return self.entries[name]
        for point in self.entry_points() if isinstance(name, str) else ():
            if point.name == name:
                try:
                    value = point.load()
                    self.register(name, value)
                except Exception as error:  # an import error, a wrong kind: say which plugin
                    raise ValueError(
                        f"{self.kind} {name!r}: the entry point {point.value!r} of group "
                        f"{self.group!r} cannot be used: {error}"
                    ) from error
                return value
        raise ValueError(f"unknown {self.kind} {name!r}; expected one of {', '.join(self.names())}")

    def names(self) -> list[str]:
        """Every name a case may use: the registered ones, then the entry points not loaded."""
        names = list(self.entries)
        return names + sorted({p.name for p in self.entry_points()} - set(names))

    def entry_points(self) -> list[importlib.metadata.EntryPoint]:
        """The installed entry points of the group (read each time: nothing is cached, so a
        distribution installed since is found)."""
        return list(importlib.metadata.entry_points(group=self.group))


def check_element_type(name: str, value: Any) -> None:
    """TypeError unless ``value`` is a subclass of the element protocol's ``ElementType``."""
    if not (isinstance(value, type) and issubclass(value, ElementType)):
        raise TypeError(
            f"element {name!r}: expected a subclass of elements.base.ElementType, got {value!r}"
        )


def check_material_factory(name: str, value: Any) -> None:
    """TypeError unless ``value`` is callable (a function or class that makes the material)."""
    if not callable(value):
        raise TypeError(f"material {name!r}: expected a callable that makes it, got {value!r}")


ELEMENTS = Registry("element", ELEMENT_GROUP, check_element_type, BUILTIN_ELEMENTS)
MATERIALS = Registry(
    "preset",
    MATERIAL_GROUP,
    check_material_factory,
    {name: getattr(presets, name) for name in presets.__all__ if callable(getattr(presets, name))},
)


def register_element(name: str, element_type: type[ElementType], replace: bool = False) -> None:
    """Let case files name ``element_type`` as ``element = "name"``.

    Parameters
    ----------
    name : str
        The name in the case file's ``[[part]]`` table.
    element_type : type
        A subclass of ``elements.base.ElementType``; it is called with the part's
        ``options`` as keywords and ``material=`` the part's material (module docstring),
        or its classmethod ``from_case(material, **options)`` when it has one.
    replace : bool
        Replace an entry of that name instead of refusing it.

    Raises
    ------
    ValueError
        The name is taken (and not ``replace``) or empty.
    TypeError
        ``element_type`` is not an ``ElementType`` subclass.
    """
    ELEMENTS.register(name, element_type, replace)


def register_material(name: str, factory: Callable[..., Any], replace: bool = False) -> None:
    """Let case files name the material ``factory()`` makes as ``material = "name"``.

    Parameters
    ----------
    name : str
        The preset name in the case file (``material = "name"`` or ``{ preset = "name",
        ... }``, the other keys the factory's keyword arguments; for a factory that returns a
        ``materials.Fabric``, keys that are not its arguments replace fields of the fabric).
    factory : callable
        Makes the material: a ``materials.Fabric`` or ``ElasticShell`` for the built-in
        elements, anything a user's element type takes as its ``material``.
    replace : bool
        Replace an entry of that name (a built-in preset too) instead of refusing it.

    Raises
    ------
    ValueError
        The name is taken (and not ``replace``) or empty.
    TypeError
        ``factory`` is not callable.
    """
    MATERIALS.register(name, factory, replace)


def element_type(name: str) -> type[ElementType]:
    """The element type named ``name``, from an entry point if none is registered by that
    name; ValueError naming the known names otherwise."""
    return ELEMENTS.get(name)


def material_factory(name: str) -> Callable[..., Any]:
    """The material factory named ``name``, from an entry point if none is registered by
    that name; ValueError naming the known names otherwise."""
    return MATERIALS.get(name)


def element_names() -> list[str]:
    """Every element name a case file may use (registered, then entry points)."""
    return ELEMENTS.names()
