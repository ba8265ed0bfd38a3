"""The ``material`` of a case file's part: a preset (with some of its values replaced), an
inline fabric or elastic shell, its laws from their tables, and the material of a user's
element type (fibreshell/case.py; README "Case files")."""

from __future__ import annotations

import inspect
from typing import Any

from fibreshell import registry
from fibreshell.case_reading import CaseError, _keywords, _number, _table, _vector, _Where
from materials import BendingLaw, ElasticShell, Fabric, ShearLaw, TensionLaw


def _user_element(where: _Where, kind: str, cls: type, material: Any, options: dict):
    """A registered element type from its part (fibreshell.registry): its ``from_case``
    classmethod or its constructor, called with the options as keywords and ``material=`` the
    part's material (a preset built, an inline table as a dict)."""
    make = getattr(cls, "from_case", cls)
    parameters = inspect.signature(make).parameters
    if not any(p.kind is inspect.Parameter.VAR_KEYWORD for p in parameters.values()):
        _keywords(where.child("options"), make, options, frozenset({"self", "material"}))
    arguments = dict(options)
    if material is not None:
        if "material" not in parameters:
            raise where.error("material", f"element {kind!r} ({cls.__name__}) takes no material")
        if isinstance(material, str):
            material = {"preset": material}
        if not isinstance(material, dict):
            raise where.error("material", f"expected a preset name or a table, got {material!r}")
        if "preset" in material:
            arguments["material"] = _preset(where, where.child("material"), material)
        else:
            arguments["material"] = dict(material)
    elif "material" in parameters and parameters["material"].default is inspect.Parameter.empty:
        raise where.error(None, "missing key 'material'")
    return make(**arguments)


_LAWS = {
    "tension": TensionLaw, "tension_weft": TensionLaw, "shear": ShearLaw,
    "bending": BendingLaw, "bending_weft": BendingLaw,
}  # fmt: skip


# The fields a Fabric needs, and those of a fabric no elastic section has (a Mindlin part's
# material with one of them is a fabric, missing its laws: not an elastic section).
_FABRIC_REQUIRED = tuple(
    name
    for name, p in inspect.signature(Fabric).parameters.items()
    if p.default is inspect.Parameter.empty
)
_FABRIC_ONLY = (
    set(inspect.signature(Fabric).parameters)
    - set(inspect.signature(ElasticShell).parameters)
    - set(inspect.signature(ElasticShell.orthotropic).parameters)
)


def _material(where: _Where, kind: str, value: Any):
    if value is None:
        raise where.error(None, "missing key 'material'")
    if isinstance(value, str):
        value = {"preset": value}
    inner = where.child("material")
    if not isinstance(value, dict):
        raise where.error("material", f"expected a preset name or a table, got {value!r}")
    if "preset" in value:
        # A Mindlin part of a fabric preset has the fabric section (its own laws, MindlinShell
        # accepts a Fabric): the same material the fibrous shell would have.
        return _preset(where, inner, value)
    fabric_only = set(value) & _FABRIC_ONLY
    if kind == "mindlin" and not ({"tension", "bending"} & set(value)) and not fabric_only:
        make = ElasticShell.orthotropic if "E1" in value else ElasticShell
        arguments = _keywords(inner, make, value)
        for key, item in arguments.items():
            if key == "warp":
                _vector(inner, item, key)
            else:
                _number(inner, item, key)
        return make(**arguments)
    _keywords(inner, Fabric, value)
    missing = [k for k in _FABRIC_REQUIRED if k not in value]
    if missing:
        given = (
            f"a Mindlin part of a fabric (it gives {', '.join(sorted(fabric_only))}) "
            if kind == "mindlin" and fabric_only
            else "a fabric "
        )
        raise inner.error(
            None,
            f"missing key{'s' if len(missing) > 1 else ''} {', '.join(map(repr, missing))}: "
            f"{given}needs {', '.join(_FABRIC_REQUIRED)}",
        )
    return Fabric(**_fabric_fields(inner, value))


def _fabric_fields(inner: _Where, value: dict) -> dict:
    """Fabric arguments from a material table: numbers checked, law tables made laws."""
    fields = dict(value)
    for key, item in fields.items():
        if key in _LAWS and isinstance(item, dict):
            fields[key] = _law(inner.child(key), _LAWS[key], item)
        elif key in _LAWS and (not isinstance(item, int | float) or isinstance(item, bool)):
            raise inner.error(key, f"expected a number (linear law) or a law table, got {item!r}")
        else:
            _number(inner, item, key)
    return fields


def _preset(where: _Where, inner: _Where, value: dict):
    """``{ preset = "name", ... }``: the preset of that name (fibreshell.registry: the
    materials.presets and the registered materials), built with the keys that are its own
    arguments (``plies``, ``sheets``), then with the others, fields of ``Fabric``, replaced
    (``Fabric.replace``): a preset with some of its values changed, for a sweep."""
    name = value["preset"]
    try:
        make = registry.material_factory(name)
    except ValueError as error:
        raise where.error("material", str(error)) from None
    parameters = inspect.signature(make).parameters
    if any(p.kind is inspect.Parameter.VAR_KEYWORD for p in parameters.values()):
        own = set(value) - {"preset"}  # a factory taking **keywords takes every key
    else:
        own = set(parameters)
    arguments = {k: v for k, v in value.items() if k in own}
    changes = {k: v for k, v in value.items() if k != "preset" and k not in own}
    try:
        material = make(**arguments)
    except (ValueError, TypeError) as error:
        raise inner.error(None, str(error)) from None
    if changes:
        if not isinstance(material, Fabric):
            raise inner.error(next(iter(changes)), f"preset {name!r} takes no other keys")
        allowed = tuple(material.__dataclass_fields__) + tuple(own)
        _table(inner, changes, "", allowed)
        material = material.replace(**_fabric_fields(inner, changes))
    return material


def _law(where: _Where, family, value: dict):
    """A law from {linear = C} | {table = {x, y}} | {bilinear = {initial, final, knee}} |
    {polynomial = {k1, k3, k5}}, with tension_only for tension laws."""
    forms = [k for k in value if k != "tension_only"]
    known = ("linear", "table", "bilinear", "polynomial")
    if len(forms) != 1 or forms[0] not in known:
        raise where.error(
            None,
            "expected one of linear = C, table = { x = [...], y = [...] }, bilinear = "
            "{ initial, final, knee }, polynomial = { k1, k3, k5 }",
        )
    form = forms[0]
    extra = {"tension_only": value["tension_only"]} if "tension_only" in value else {}
    if extra and family is not TensionLaw:
        raise where.error("tension_only", "only tension laws can be tension-only")
    if extra and not isinstance(extra["tension_only"], bool):
        raise where.error("tension_only", f"expected true or false, got {extra['tension_only']!r}")
    if not hasattr(family, form):
        raise where.error(form, f"{family.__name__} has no {form} form")
    try:  # the law's own refusal, named by the key and the table it is in
        if form == "linear":
            return family.linear(_number(where, value["linear"], "linear"), **extra)
        if form == "table":
            table = _table(where, value["table"], "table", ("x", "y"), ("x", "y"))
            return family.table(table["x"], table["y"], **extra)
        parameters = inspect.signature(getattr(family, form)).parameters
        names = tuple(parameters)
        required = tuple(n for n, p in parameters.items() if p.default is inspect.Parameter.empty)
        arguments = _table(where, value[form], form, names, required)
        return getattr(family, form)(**arguments, **extra)
    except CaseError:
        raise
    except ValueError as error:
        raise where.error(form, str(error)) from None
