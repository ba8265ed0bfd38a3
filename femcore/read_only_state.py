"""Objects whose read-only arrays stay read-only through a pickle or a deep copy.

Below pickle protocol 5 (the default protocol, 4, which process pools use) numpy pickles an
array's data and shape but not its ``writeable`` flag, and a deep copy of an array is
writeable: the copy of a read-only array takes an edit in place. (Protocol 5, which checkpoints
use, solvers/output.py, keeps the flag of a contiguous array only: a non-contiguous read-only
array comes back writeable there too, and the list below covers it.) A block keeps some arrays
read-only on purpose: arrays it hands out and keeps for later calls (the fibrous bending
patch's nodes, slots and fold, elements/fibrous/bending.py; the ply contact's faces, directions
and facing, elements/ply_block.py; a mesh's points and cells, a topology's tables, a tool's
motion), where a caller's edit in place would corrupt every later answer, and whose flag is
part of the compiled kernels' argument types (elements/kernel_inputs.py).

``ReadOnlyState`` pickles, beside the object's attributes, the list of the read-only arrays
found among them (inside tuples, lists, dicts and dataclasses): pickle stores each object once
and refers to it again (a deep copy likewise), so the list holds the very arrays the attributes
hold, and unpickling clears their flag again. An object pickled before this list existed loads
as before, its arrays writeable.
"""

from __future__ import annotations

import dataclasses
from typing import Any

import numpy as np

__all__ = ["ReadOnlyState", "read_only_arrays"]

#: The state's key of the read-only arrays' list (not an attribute: taken out on load).
KEY = "__read_only_arrays__"


def read_only_arrays(value: Any) -> list[np.ndarray]:
    """The read-only numpy arrays within ``value``: itself, or inside its tuples, lists,
    dicts' values and dataclass instances' fields (each object visited once; other objects
    are not entered: one of ``ReadOnlyState`` lists its own)."""
    found: list[np.ndarray] = []
    seen: set[int] = set()
    stack = [value]
    while stack:
        item = stack.pop()
        if id(item) in seen:
            continue
        seen.add(id(item))
        if isinstance(item, np.ndarray):
            if not item.flags.writeable and item.dtype != object:
                found.append(item)
        elif isinstance(item, (tuple, list)):
            stack.extend(item)
        elif isinstance(item, dict):
            stack.extend(item.values())
        elif dataclasses.is_dataclass(item) and not isinstance(item, (type, ReadOnlyState)):
            stack.extend(getattr(item, field.name) for field in dataclasses.fields(item))
    return found


class ReadOnlyState:
    """A mixin: the object's read-only arrays are read-only again once unpickled or deep-copied
    (module docstring). The object's state is its ``__dict__``."""

    def __getstate__(self) -> dict[str, Any]:
        state = dict(self.__dict__)
        state[KEY] = read_only_arrays(list(self.__dict__.values()))
        return state

    def __setstate__(self, state: dict[str, Any]) -> None:
        state = dict(state)
        frozen = state.pop(KEY, ())
        self.__dict__.update(state)
        for array in frozen:
            array.setflags(write=False)
