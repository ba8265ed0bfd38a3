"""Validation cases: one module each, stating its source, geometry, parameters and checks.

Every module in this package declares one ``CASE = validation.records.Case(...)``. The registry
below discovers the modules (``pkgutil.iter_modules``), so a new module is run and reported
without being listed anywhere; a module without a ``CASE`` record, or two cases with the same
name, make the import of this package fail with a message that names the module. Code that
several cases share belongs in ``validation`` (``specimens``, ``checks``, ``plots``, ``paper``),
not here: the cases do not import each other.

The report order is that of ``Case.sort_key``: the group (paper, sensitivity, verification),
then the order key within the group.
"""

from __future__ import annotations

import importlib
import pkgutil
from types import ModuleType

from validation.records import GROUPS, RESOLUTIONS, Case

__all__ = [
    "CASES",
    "PAPER_CASES",
    "RESOLUTIONS",
    "SENSITIVITY_CASES",
    "VERIFICATION_CASES",
    "RegistryError",
    "discover",
]


class RegistryError(ImportError):
    """A module of a case package declares no ``Case`` record, or two cases share a name."""


def discover(package: ModuleType | str) -> dict[str, Case]:
    """Import every module of ``package`` and collect its ``CASE`` record, in report order.

    Parameters
    ----------
    package : module or str
        The case package (``validation.cases``) or its import name.

    Returns
    -------
    dict of str to Case
        Case name -> case, sorted by ``Case.sort_key``.

    Raises
    ------
    RegistryError
        When a module has no ``CASE`` attribute, when its ``CASE`` is not a ``Case``, or when
        two modules declare the same case name.
    """
    if isinstance(package, str):
        package = importlib.import_module(package)
    found: dict[str, tuple[Case, str]] = {}
    for info in sorted(pkgutil.iter_modules(package.__path__), key=lambda m: m.name):
        module_name = f"{package.__name__}.{info.name}"
        module = importlib.import_module(module_name)
        case = getattr(module, "CASE", None)
        if case is None:
            raise RegistryError(
                f"{module_name} ({module.__file__}) declares no CASE record: every module in "
                f"{package.__name__} is a validation case and must define "
                f"CASE = validation.records.Case(...); move shared code to the validation package"
            )
        if not isinstance(case, Case):
            raise RegistryError(
                f"{module_name}.CASE is a {type(case).__name__}, not a validation.records.Case"
            )
        if case.name in found:
            raise RegistryError(
                f"duplicate case name {case.name!r}: declared by {found[case.name][1]} and "
                f"{module_name}"
            )
        found[case.name] = (case, module_name)
    ordered = sorted((case for case, _ in found.values()), key=lambda case: case.sort_key)
    return {case.name: case for case in ordered}


CASES = discover(__name__)
PAPER_CASES, SENSITIVITY_CASES, VERIFICATION_CASES = (
    tuple(case for case in CASES.values() if case.group == group) for group in GROUPS
)
