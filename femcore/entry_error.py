"""The error of one entry of a model's description, raised when the model is compiled: an
element block that cannot bind, an interaction whose body starts inside its tool, a support,
a prescribed motion or a load that cannot apply. It says which entry (its kind and its index
in the model's list of them), so that a builder that knows where each entry was written (a
case file's table: fibreshell/case_model.py) can name that place."""

from __future__ import annotations

__all__ = ["ENTRY_LISTS", "EntryError", "EntryWarning"]

#: The kinds of entries and the Model attribute that lists them, in the order they are added.
ENTRY_LISTS = {
    "block": "blocks",
    "interaction": "interactions",
    "fix": "fixes",
    "displacement": "prescribed",
    "load": "loads",
}


class _AboutAnEntry(Exception):
    """What EntryError and EntryWarning share: the entry (``kind``, ``index``), the ``reason``
    and a message ``prefix + reason``; pickled from those (``args`` holds the message alone),
    so that it crosses a process pool (a sweep's or a report's worker) as it was raised."""

    def __init__(self, kind: str, index: int, reason: str, prefix: str = "") -> None:
        super().__init__(f"{prefix}{reason}")
        self.kind = kind
        self.index = index
        self.reason = reason

    def __reduce__(self):
        prefix = str(self)[: len(str(self)) - len(self.reason)]
        return (type(self), (self.kind, self.index, self.reason, prefix))


class EntryError(_AboutAnEntry, ValueError):
    """A ValueError about ``model.<ENTRY_LISTS[kind]>[index]``.

    Attributes
    ----------
    kind : str
        "block", "interaction", "fix", "displacement" or "load".
    index : int
        The entry's index in its list.
    reason : str
        What is wrong, without the entry's name (the message is ``prefix + reason``).
    """


class EntryWarning(_AboutAnEntry, UserWarning):
    """A UserWarning about ``model.<ENTRY_LISTS[kind]>[index]`` (a body that starts
    overlapping an interaction's tool); ``kind``, ``index`` and ``reason`` as EntryError's."""
