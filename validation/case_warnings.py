"""The Python warnings a case's runs raise, kept for the report.

A solver warns where a run is doubtful but goes on (a force-driven tool far from its force,
KE / W above its bound over a share of the run, a load step that jumped): printed on stderr
alone, a reader of index.html or results.json would see the case pass and never learn of it.
``kept_warnings`` records them while the case (or one of its parts) runs, still shows each
on stderr as before, and hands their text to the case's outcome (``Outcome.warnings``).
"""

from __future__ import annotations

import warnings
from collections.abc import Iterator
from contextlib import contextmanager

__all__ = ["kept_warnings"]


@contextmanager
def kept_warnings() -> Iterator[list[str]]:
    """Record the warnings raised inside the ``with`` block under the filters in force (an
    ignored warning stays ignored; each location's repeats count once, as on stderr).

    Yields
    ------
    list of str
        Filled when the block ends (raised or not): each distinct warning once, in the order
        raised, as "Category: message". Each is also shown as it would have been without
        the block (stderr, or the test runner's capture).
    """
    kept: list[str] = []
    show = warnings.showwarning  # the handler in force before the block
    with warnings.catch_warnings(record=True) as caught:
        try:
            yield kept
        finally:
            records = list(caught)
    for record in records:
        show(
            record.message,
            record.category,
            record.filename,
            record.lineno,
            record.file,
            record.line,
        )
        text = f"{record.category.__name__}: {record.message}"
        if text not in kept:
            kept.append(text)
