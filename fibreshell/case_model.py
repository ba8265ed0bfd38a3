"""A case's model built table by table, each entry it adds (element block, support,
prescribed motion, load, interaction) remembered with the table of the case file that wrote
it, so that an error in building or compiling the model names the file, the table and the
key, as the errors of reading the file do (fibreshell/case_reading.py)."""

from __future__ import annotations

import warnings
from collections.abc import Callable, Iterator
from contextlib import contextmanager

from femcore import Model
from femcore.entry_error import ENTRY_LISTS, EntryError, EntryWarning
from femcore.model import CompiledModel
from femcore.topology import MeshTopologyError
from fibreshell.case_reading import CaseError, _Where

__all__ = ["LocatedModel"]


class LocatedModel:
    """A ``Model`` and, for each of its entries, the table that wrote it.

    ``with located.at(where, key) as model:`` builds with ``model``; a ValueError raised there
    becomes a CaseError at ``where`` (and ``key``), and the entries added there are noted as
    written at ``where``. ``compile()`` compiles the model; a ``femcore.entry_error.EntryError``
    becomes a CaseError at the table of the entry it names, and an ``EntryWarning`` (a body
    that starts overlapping a tool) a UserWarning that names that table. The entries
    ``model`` holds when given are noted as written at ``written_at`` (None: nowhere). A mesh
    that no shell can use (femcore.topology.MeshTopologyError: triangles facing opposite ways,
    duplicate nodes, ...) becomes a CaseError at ``mesh_at`` (the ``[mesh]`` table), naming
    ``mesh_file`` (its ``file``, None for a generated mesh).
    """

    def __init__(
        self,
        model: Model,
        written_at: _Where | None = None,
        mesh_at: _Where | None = None,
        mesh_file: str | None = None,
    ) -> None:
        self.model = model
        self.mesh_at, self.mesh_file = mesh_at, mesh_file
        self.places: dict[str, list[_Where]] = {kind: [] for kind in ENTRY_LISTS}
        if written_at is not None:  # the entries ``model`` has already (a layup's plies)
            for kind, name in ENTRY_LISTS.items():
                self.places[kind] = [written_at] * len(getattr(model, name))

    @contextmanager
    def at(self, where: _Where, key: str | None = None) -> Iterator[Model]:
        try:
            yield self.model
        except CaseError:
            raise
        except ValueError as error:
            raise where.error(key, str(error)) from None
        finally:
            for kind, name in ENTRY_LISTS.items():
                places = self.places[kind]
                places.extend([where] * (len(getattr(self.model, name)) - len(places)))

    def compile(self) -> Model:
        """The model, compiled (its compiled form is kept for the solver); raises CaseError
        for an entry that cannot bind or apply."""
        with warnings.catch_warnings(record=True) as said:
            warnings.simplefilter("always")
            try:
                self.model.compile()
            except EntryError as error:
                raise self.located(error) from None
            except MeshTopologyError as error:
                if self.mesh_at is None:
                    raise
                if self.mesh_file is None:
                    raise self.mesh_at.error(None, f"the mesh: {error}") from None
                raise self.mesh_at.error("file", f"{self.mesh_file}: {error}") from None
        for warning in said:  # said again, those about an entry at its table
            message = warning.message
            if isinstance(message, EntryWarning) and message.index < len(self.places[message.kind]):
                text = str(self.places[message.kind][message.index].error(None, message.reason))
                warnings.warn(text, UserWarning, stacklevel=3)
            else:
                warnings.warn_explicit(message, warning.category, warning.filename, warning.lineno)
        return self.model

    def located(self, error: EntryError) -> Exception:
        """``error`` as a CaseError at the table of the entry it names (and at its ``key``
        where it has one: a holder's "force"); ``error`` itself for an entry added outside
        ``at``, which no table wrote."""
        places = self.places[error.kind]
        if error.index >= len(places):
            return error
        reason = error.reason if error.case_reason is None else error.case_reason
        return places[error.index].error(error.key, reason)

    def check(self, check: Callable[[CompiledModel], None]) -> None:
        """Run ``check`` on the compiled model; an EntryError it raises becomes a CaseError at
        the table of the entry it names, as ``compile``'s do."""
        try:
            check(self.model.compile())
        except EntryError as error:
            raise self.located(error) from None
