"""The ``material`` of a case file's part: a preset (with some of its values replaced), an
inline fabric or elastic shell, its laws from their tables, and the material of a user's
element type (fibreshell/case.py; README "Case files")."""

from __future__ import annotations

import inspect
from typing import Any

from fibreshell import registry
from fibreshell.case_reading import _keywords, _number, _table, _vector, _Where
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
    if kind == "mindlin" and not ({"tension", "bending"} & set(value)):
        make = ElasticShell.orthotropic if "E1" in value else ElasticShell
        arguments = _keywords(inner, make, value)
        for key, item in arguments.items():
            if key == "warp":
                _vector(inner, item, key)
            else:
                _number(inner, item, key)
        return make(**arguments)
    _keywords(inner, Fabric, value)
    return Fabric(**_fabric_fields(inner, value))


def _fabric_fields(inner: _Where, value: dict) -> dict:
    """Fabric arguments from a material table: numbers checked, law tables made laws."""
    fields = dict(value)
    for key, item in fields.items():
        if key in _LAWS and isinstance(item, dict):
            fields[key] = _law(inner.child(key), _LAWS[key], item)
        elif key in _LAWS and not isinstance(item, int | float) or isinstance(item, bool):
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
    if not hasattr(family, form):
        raise where.error(form, f"{family.__name__} has no {form} form")
    if form == "linear":
        return family.linear(_number(where, value["linear"], "linear"), **extra)
    if form == "table":
        table = _table(where, value["table"], "table", ("x", "y"), ("x", "y"))
        return family.table(table["x"], table["y"], **extra)
    names = tuple(inspect.signature(getattr(family, form)).parameters)
    return getattr(family, form)(**_table(where, value[form], form, names), **extra)
