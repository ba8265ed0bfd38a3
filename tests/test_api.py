"""The public API: every module of femcore, elements, materials and solvers declares __all__,
and every name it declares (or a package re-exports) resolves.

The modules are discovered with pkgutil.walk_packages, so a new module is checked without
editing this file.
"""

import importlib
import inspect
import pkgutil
from types import ModuleType

import pytest

PACKAGES = ("femcore", "elements", "materials", "solvers")


def public_modules() -> list[str]:
    """Dotted names of the four packages and of every module below them."""
    names = []
    for package_name in PACKAGES:
        package = importlib.import_module(package_name)
        names.append(package_name)
        names.extend(
            info.name for info in pkgutil.walk_packages(package.__path__, prefix=f"{package_name}.")
        )
    return names


MODULES = public_modules()


def declared(module: ModuleType) -> list[str]:
    exported = getattr(module, "__all__", None)
    assert exported is not None, f"{module.__name__} has no __all__"
    assert isinstance(exported, list | tuple), (
        f"{module.__name__}.__all__ must be a list or tuple, got {type(exported).__name__}"
    )
    return list(exported)


def test_the_walk_finds_the_modules():
    # A broken discovery would make the parametrised tests below pass vacuously.
    for name in ("femcore.mesh", "femcore.results", "elements.base", "materials.laws"):
        assert name in MODULES
    assert "solvers.static" in MODULES


@pytest.mark.parametrize("name", MODULES)
def test_module_declares_all_and_every_name_resolves(name):
    module = importlib.import_module(name)
    exported = declared(module)
    assert all(isinstance(item, str) for item in exported), f"{name}.__all__ holds a non-string"
    duplicates = sorted({item for item in exported if exported.count(item) > 1})
    assert not duplicates, f"{name}.__all__ repeats {duplicates}"
    missing = [item for item in exported if not hasattr(module, item)]
    assert not missing, f"{name}.__all__ names {missing}, which {name} does not define"
    namespace: dict[str, object] = {}
    exec(f"from {name} import *", namespace)  # what users actually get
    assert set(exported) <= set(namespace)


@pytest.mark.parametrize("package_name", PACKAGES)
def test_package_reexports_resolve_to_the_public_names_of_their_modules(package_name):
    """A class or function a package re-exports is public (in __all__) where it is defined."""
    package = importlib.import_module(package_name)
    for item in declared(package):
        value = getattr(package, item)
        assert value is not None, f"{package_name}.{item} is None"
        if inspect.ismodule(value):
            assert value.__name__.startswith(f"{package_name}."), value.__name__
            continue
        if not (inspect.isclass(value) or inspect.isfunction(value)):
            continue  # constants carry no home module
        home = importlib.import_module(value.__module__)
        assert getattr(home, value.__name__) is value
        assert value.__name__ in declared(home), (
            f"{package_name} re-exports {item} from {home.__name__}, whose __all__ lacks it"
        )
