"""The fingerprint of a model: a digest of everything that changes its answer, per part.

A checkpoint stores the fingerprint of the model (and of the solver settings) that wrote it; a
run that resumes from it compares its own, part by part, and refuses a checkpoint of another
model naming what differs (solvers.checkpoint). The parts:

- ``mesh``: the node coordinates and the cells of every kind;
- ``elements``: each element block's type, its cells and its plain options (numbers, strings,
  arrays);
- ``materials``: the objects an element type holds (a Fabric, an ElasticShell, laws);
- ``supports``: the fixed and the prescribed DOFs;
- ``loads``: nodal forces and moments, gravity and prescribed displacements, with their
  amplitudes;
- ``tools``: the rigid tools the interactions act against (geometry, motion, amplitude; a
  force-driven tool's node and its mass);
- ``interactions``: the interactions' own options (nodes, penalty, friction, ...);
- ``solver``: the settings a solver passes in.

The digest is generic (``digest``), so that an element type, a law or an interaction written
outside the project needs nothing to be fingerprinted: numbers by their exact bits, arrays by
dtype, shape and bytes, dataclasses by their fields, other objects by their public attributes
(private ones are caches: a search cache changes as a run goes, not the model), functions by
their code, constants, defaults, closure values and the globals they read, and a function of
one argument (an amplitude a(tau)) also by its values at fixed points, so that two lambdas
whose captured numbers differ differ.
"""

from __future__ import annotations

import dataclasses
import enum
import functools
import hashlib
import inspect
import os
import types
import warnings
from collections.abc import Mapping
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from femcore.mesh import CELL_KINDS

if TYPE_CHECKING:
    from femcore.compiled import CompiledModel

__all__ = ["PARTS", "Fingerprint", "Uncalled", "digest", "fingerprint"]

#: The parts of a fingerprint, in the order a message names them.
PARTS = ("mesh", "elements", "materials", "supports", "loads", "tools", "interactions", "solver")

#: Where a function of one argument (an amplitude a(tau)) is sampled: load factors in [0, 1]
#: and a few points off the simple fractions a piecewise amplitude could hide its knees at.
SAMPLES = (*np.linspace(0.0, 1.0, 21).tolist(), 0.0123, 0.3141, 0.5772, 0.7071, 0.9876)

# Objects nested deeper than this are cut off (their class is still hashed): a guard against
# pathological structures, far deeper than any element or law.
_MAX_DEPTH = 48


@dataclass(frozen=True)
class Uncalled:
    """A value to digest by what it is made of, its functions never called: a solver's
    ``frame_summary`` (a function of a Frame) would otherwise be fed the load factors an
    amplitude is sampled at. A function inside it counts by its code, defaults, closure values
    and the globals it reads; an object by its public attributes."""

    value: Any


@dataclass(frozen=True)
class Fingerprint:
    """The digests of a model's parts and of the items each part is made of.

    Attributes
    ----------
    parts : dict[str, str]
        Part name (``PARTS``) -> hex sha256 digest.
    items : dict[str, tuple[str, str]]
        Item label (e.g. "gravity 0", "block 0 (Cable) axial_stiffness") -> (part, digest):
        what a message names within a part that differs.
    solver : str
        The solver's kind (its settings' "solver", e.g. "CentralDifference"; "" when none
        was given, and in a checkpoint written before it was kept): named first when a
        checkpoint of another kind is refused, where the settings of two kinds all differ.
    """

    parts: dict[str, str]
    items: dict[str, tuple[str, str]]
    solver: str = ""

    def differences(self, other: Fingerprint) -> list[str]:
        """What differs from ``other``, a phrase per part, e.g. "its loads differ (gravity
        0)"; empty when the two are the same model."""
        phrases = []
        for part in PARTS:
            if self.parts.get(part) == other.parts.get(part):
                continue
            labels = sorted(
                label
                for label in set(self.items) | set(other.items)
                if part in (self.items.get(label, ("",))[0], other.items.get(label, ("",))[0])
                and self.items.get(label) != other.items.get(label)
            )
            shown = ", ".join(labels[:4]) + (", ..." if len(labels) > 4 else "")
            name = "solver settings" if part == "solver" else part
            verb = "differs" if name == "mesh" else "differ"  # the one singular part
            phrases.append(f"its {name} {verb}" + (f" ({shown})" if shown else ""))
        return phrases


def fingerprint(model: CompiledModel, solver: Mapping[str, Any] | None = None) -> Fingerprint:
    """The fingerprint of a compiled model and of a solver's settings.

    Parameters
    ----------
    model : CompiledModel
    solver : mapping of setting name -> value, optional
        The settings of the solver that change its answer (its ``solver`` part).

    Returns
    -------
    Fingerprint
    """
    items: dict[str, tuple[str, str]] = {}

    def add(part: str, label: str, value: Any) -> None:
        items[label] = (part, digest(value))

    mesh = model.mesh
    add("mesh", "node coordinates", mesh.points)
    for kind in CELL_KINDS:
        cells = mesh.cells(kind)
        if len(cells):
            add("mesh", f"{kind} cells", cells)

    for index, entry in enumerate(model.block_entries):
        element = entry.element
        name = f"block {index} ({type(element).__name__})"
        add("elements", f"{name} type", type(element))
        add("elements", f"{name} cells", entry.cells)
        for attribute, value in _public_attributes(element).items():
            part = "elements" if _plain(value) else "materials"
            add(part, f"{name} {attribute}", value)

    if len(model.rigid_nodes):  # a force-driven tool's node and its mass
        add("tools", "rigid nodes", (model.rigid_nodes, model._rigid_mass))

    add("supports", "fixed DOFs", model.dofs.fixed)
    add("supports", "prescribed DOFs", model.dofs.prescribed)

    for index, (kind, amplitude, values) in enumerate(model._load_terms):
        add("loads", f"{kind} {index}", (values, amplitude))
    for index, (amplitude, vector) in enumerate(model._gravity_terms):
        add("loads", f"gravity {index}", (vector, amplitude))
    for index, (amplitude, values) in enumerate(model._prescribed_terms):
        add("loads", f"prescribed displacement {index}", (values, amplitude))

    for index, interaction in enumerate(model.given_interactions):
        name = f"interaction {index} ({type(interaction).__name__})"
        add("interactions", f"{name} type", type(interaction))
        for attribute, value in _public_attributes(interaction).items():
            # A tool is what builds its contact (Model.contact's protocol).
            part = "tools" if callable(getattr(value, "contact", None)) else "interactions"
            add(part, f"{name} {attribute}", value)

    for key, value in (solver or {}).items():
        add("solver", str(key), value)

    parts = {}
    for part in PARTS:
        hasher = hashlib.sha256(part.encode())
        for label in sorted(label for label, (p, _) in items.items() if p == part):
            hasher.update(f"{label}={items[label][1]};".encode())
        parts[part] = hasher.hexdigest()
    kind = (solver or {}).get("solver", "")
    return Fingerprint(parts, items, kind if isinstance(kind, str) else "")


def digest(value: Any) -> str:
    """The hex sha256 digest of any value (the module docstring says how each kind is read).

    Equal for equal values in any process; objects are read, never changed (a function of one
    argument is called at ``SAMPLES``, as an amplitude is called by a run)."""
    return _Digest().of(value, 0).hex()


def _public_attributes(obj: Any) -> dict[str, Any]:
    """The fields of a dataclass, else the public instance attributes (``__dict__`` and
    ``__slots__``) of an object."""
    if dataclasses.is_dataclass(obj) and not isinstance(obj, type):
        return {f.name: getattr(obj, f.name, None) for f in dataclasses.fields(obj)}
    found = {k: v for k, v in getattr(obj, "__dict__", {}).items() if not k.startswith("_")}
    for cls in type(obj).__mro__:
        slots = cls.__dict__.get("__slots__", ())
        for name in (slots,) if isinstance(slots, str) else slots:
            if not name.startswith("_") and hasattr(obj, name):
                found[name] = getattr(obj, name)
    return dict(sorted(found.items()))


def _plain(value: Any) -> bool:
    """Whether ``value`` is an option (numbers, strings, arrays, tuples of them), not a
    material object."""
    if value is None or isinstance(value, (bool, int, float, complex, str, bytes, np.generic)):
        return True
    if isinstance(value, np.ndarray):
        return value.dtype != object
    if isinstance(value, (tuple, list)):
        return all(_plain(v) for v in value)
    return False


class _Digest:
    """One digest computation: sub-digests memoised by object id (the objects stay alive for
    the call) and the objects being read, to cut reference cycles."""

    def __init__(self) -> None:
        self.calls = True  # whether a function of one argument is sampled (not in Uncalled)
        self.memo: dict[int, bytes] = {}
        self.reading: set[int] = set()
        self.keep: list[Any] = []  # memoised objects stay alive, so their ids stay theirs

    def of(self, value: Any, depth: int) -> bytes:
        leaf = _leaf(value)
        if leaf is not None:
            return hashlib.sha256(leaf).digest()
        if isinstance(value, Uncalled):  # its own memo: read uncalled is another digest
            inner = _Digest()
            inner.calls = False
            return hashlib.sha256(b"uncalled" + inner.of(value.value, depth + 1)).digest()
        key = id(value)
        if key in self.memo:
            return self.memo[key]
        tag = f"{type(value).__module__}.{type(value).__qualname__}".encode()
        if key in self.reading or depth > _MAX_DEPTH:
            return hashlib.sha256(b"cut:" + tag).digest()
        self.reading.add(key)
        try:
            hasher = hashlib.sha256(tag)
            try:
                pieces = self._pieces(value)
            except Exception:  # an object that cannot be read (a property that raises): its class
                pieces = [b"unreadable"]
            for piece in pieces:
                if isinstance(piece, bytes):
                    hasher.update(b"b" + len(piece).to_bytes(8, "little") + piece)
                else:
                    hasher.update(b"v" + self.of(piece, depth + 1))
            result = hasher.digest()
        finally:
            self.reading.discard(key)
        self.memo[key] = result
        self.keep.append(value)
        return result

    def _pieces(self, value: Any) -> list[Any]:
        """What ``value`` is made of: bytes taken as they are, anything else digested."""
        if isinstance(value, np.ndarray):
            if value.dtype == object:
                return [repr(value.shape).encode(), *value.ravel().tolist()]
            header = f"{value.dtype.str}{value.shape}".encode()
            return [header, np.ascontiguousarray(value).tobytes()]
        if isinstance(value, (list, tuple)):
            return [str(len(value)).encode(), *value]
        if isinstance(value, (set, frozenset)):
            return sorted(self.of(v, 0) for v in value)
        if isinstance(value, Mapping):
            pairs = sorted(((self.of(k, 0), v) for k, v in value.items()), key=lambda p: p[0])
            return [piece for pair in pairs for piece in pair]
        if isinstance(value, types.FunctionType):
            return _function_pieces(value, self.calls)
        if isinstance(value, types.MethodType):
            return [value.__func__, value.__self__]
        if isinstance(value, types.CodeType):
            return _code_pieces(value)
        if isinstance(value, functools.partial):
            return [value.func, value.args, value.keywords]
        if isinstance(value, (type, types.ModuleType, types.BuiltinFunctionType, np.ufunc)):
            name = getattr(value, "__qualname__", getattr(value, "__name__", ""))
            return [f"{getattr(value, '__module__', '')}.{name}".encode()]
        if isinstance(value, enum.Enum):
            return [value.value]
        if isinstance(value, os.PathLike):
            return [os.fspath(value).encode()]
        if dataclasses.is_dataclass(value) or hasattr(value, "__dict__"):
            attributes = _public_attributes(value)
            return [piece for name, item in attributes.items() for piece in (name.encode(), item)]
        return []  # a C object without attributes: its class alone


def _leaf(value: Any) -> bytes | None:
    """The bytes of a scalar (exact: floats by their hex bits), None for anything else."""
    if value is None or isinstance(value, (bool, str, bytes)):
        return f"{type(value).__name__}:".encode() + (
            value if isinstance(value, bytes) else repr(value).encode()
        )
    if isinstance(value, int):
        return b"int:" + repr(value).encode()
    if isinstance(value, float):
        return b"float:" + value.hex().encode()
    if isinstance(value, complex):
        return b"complex:" + value.real.hex().encode() + value.imag.hex().encode()
    if isinstance(value, np.generic) and not isinstance(value, np.object_):
        return f"np:{value.dtype.str}:".encode() + np.asarray(value).tobytes()
    return None


def _function_pieces(function: types.FunctionType, calls: bool = True) -> list[Any]:
    """A function's code, defaults, closure values and the globals its code reads, and its
    values at SAMPLES when it takes one argument (an amplitude) and ``calls``. Not its name
    nor its module: the same lambda defined in a script (``__main__``) and in a module is the
    same amplitude."""
    pieces: list[Any] = [function.__code__, function.__defaults__, function.__kwdefaults__]
    for cell in function.__closure__ or ():
        try:
            pieces.append(cell.cell_contents)
        except ValueError:  # a cell not filled yet
            pieces.append(b"empty cell")
    names = sorted(_global_names(function.__code__))
    for name in names:
        if name in function.__globals__:
            pieces += [name.encode(), function.__globals__[name]]
    if calls and _one_argument(function):
        pieces.append(_samples(function))
    return pieces


def _code_pieces(code: types.CodeType) -> list[Any]:
    """The bytecode, constants and names of a code object (not its line numbers: code moved
    within its file is the same code)."""
    return [code.co_code, code.co_consts, code.co_names, code.co_varnames, code.co_freevars]


def _global_names(code: types.CodeType) -> set[str]:
    names = set(code.co_names)
    for constant in code.co_consts:
        if isinstance(constant, types.CodeType):
            names |= _global_names(constant)
    return names


def _one_argument(function: types.FunctionType) -> bool:
    try:
        parameters = list(inspect.signature(function).parameters.values())
    except (TypeError, ValueError):
        return False
    required = [p for p in parameters if p.default is p.empty and p.kind is not p.VAR_KEYWORD]
    return len(required) == 1 and required[0].kind in (
        inspect.Parameter.POSITIONAL_ONLY,
        inspect.Parameter.POSITIONAL_OR_KEYWORD,
    )


def _samples(function: types.FunctionType) -> bytes:
    """The values of ``function`` at SAMPLES as bytes (the class of the error where it
    fails: a law of strains fed load factors may refuse them, and that is its answer)."""
    out = []
    for tau in SAMPLES:
        try:
            with warnings.catch_warnings(), np.errstate(all="ignore"):
                warnings.simplefilter("ignore")
                value = np.asarray(function(tau), dtype=float)
            out.append(f"{value.shape}".encode() + value.tobytes())
        except Exception as error:  # the user's function: its failure is part of its answer
            out.append(type(error).__name__.encode())
    return b"|".join(out)
