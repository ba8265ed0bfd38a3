"""Reading a case file's values: where a value sits (for messages), and the checks every
table, number, vector and keyword set of a case file goes through; each failure a
``CaseError`` naming the file, the table and the key (fibreshell/case.py)."""

from __future__ import annotations

import inspect
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np


class CaseError(ValueError):
    """A case file that cannot be read as written: the message names the file, the table
    and the key."""


@dataclass
class _Where:
    """Where a value sits in the case file, for messages: file, then table.key."""

    path: Path
    table: str

    def error(self, key: str | None, message: str) -> CaseError:
        at = self.table if key is None else f"{self.table}.{key}" if self.table else key
        return CaseError(f"{self.path}: [{at}]: {message}")

    def child(self, name: str) -> _Where:
        return _Where(self.path, f"{self.table}.{name}" if self.table else name)


def _table(where: _Where, value: Any, key: str, allowed: tuple[str, ...], required=()) -> dict:
    """``value`` checked to be a table with only ``allowed`` keys and every ``required``."""
    if not isinstance(value, dict):
        raise where.error(key, f"expected a table, got {type(value).__name__} {value!r}")
    inner = where.child(key) if key else where
    unknown = [k for k in value if k not in allowed]
    if unknown:
        raise inner.error(
            unknown[0], f"unknown key {unknown[0]!r}; expected one of {', '.join(allowed)}"
        )
    missing = [k for k in required if k not in value]
    if missing:
        raise inner.error(None, f"missing key {missing[0]!r}")
    return value


def _number(where: _Where, value: Any, key: str) -> float:
    if isinstance(value, bool) or not isinstance(value, int | float) or not np.isfinite(value):
        raise where.error(key, f"expected a finite number, got {value!r}")
    return float(value)


def _vector(where: _Where, value: Any, key: str) -> np.ndarray:
    if not isinstance(value, list) or len(value) != 3:
        raise where.error(key, f"expected a list of 3 numbers, got {value!r}")
    return np.array([_number(where, v, key) for v in value])


def _keywords(where: _Where, callable_: Any, options: dict, reserved=frozenset({"self"})):
    """``options`` checked against the keyword parameters of ``callable_``."""
    names = [p for p in inspect.signature(callable_).parameters if p not in reserved]
    for key in options:
        if key not in names:
            raise where.error(key, f"unknown option {key!r}; expected one of {', '.join(names)}")
    return options


def _amplitude(where: _Where, value: Any) -> str:
    if value not in ("step", "linear", "smooth"):
        raise where.error("amplitude", f"expected 'step', 'linear' or 'smooth', got {value!r}")
    return value
