"""The error of one entry of a model's description, raised when the model is compiled: an
element block that cannot bind, an interaction whose body starts inside its tool, a support,
a prescribed motion or a load that cannot apply. It says which entry (its kind and its index
in the model's list of them), so that a builder that knows where each entry was written (a
case file's table: fibreshell/case_model.py) can name that place."""

from __future__ import annotations

__all__ = ["ENTRY_LISTS", "EntryError", "EntryWarning", "OptionError"]

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

    def __init__(
        self,
        kind: str,
        index: int,
        reason: str,
        prefix: str = "",
        key: str | None = None,
        case_reason: str | None = None,
    ) -> None:
        super().__init__(f"{prefix}{reason}")
        self.kind = kind
        self.index = index
        self.reason = reason
        self.key = key
        self.case_reason = case_reason

    def __reduce__(self):
        prefix = str(self)[: len(str(self)) - len(self.reason)]
        args = (self.kind, self.index, self.reason, prefix, self.key, self.case_reason)
        return (type(self), args)


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
    key : str or None
        The key of the entry's description the error is about ("options.clamped"), None
        for the entry as a whole.
    case_reason : str or None
        ``reason`` in a case file's terms, where its remedy differs from the Python one
        ("a [[fix]] table" for "model.fix"); None: ``reason`` serves both.
    """


class EntryWarning(_AboutAnEntry, UserWarning):
    """A UserWarning about ``model.<ENTRY_LISTS[kind]>[index]`` (a body that starts
    overlapping an interaction's tool); ``kind``, ``index`` and ``reason`` as EntryError's."""


class OptionError(ValueError):
    """A ValueError about one option of an element, raised when the model is compiled (a
    ``clamped`` edge the supports do not hold): ``option`` the keyword, ``case_reason`` the
    message in a case file's terms (None: the message serves both). The model names the
    block with an ``EntryError`` whose ``key`` is ``options.<option>``, which a case file's
    reader places at its ``[[part]]`` table's key."""

    def __init__(self, message: str, option: str, case_reason: str | None = None) -> None:
        super().__init__(message)
        self.option = option
        self.case_reason = case_reason

    def __reduce__(self):
        return (type(self), (str(self), self.option, self.case_reason))
