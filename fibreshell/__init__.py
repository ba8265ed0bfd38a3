"""fibreshell: case files and the ``fibreshell`` command on top of the framework (femcore,
elements, materials, solvers). ``load_case`` reads a case file, ``run_case`` and
``compare_case`` run it, ``fibreshell.sweep.sweep`` runs it over values of its keys and
``fibreshell.identify.identify`` fits them to measurements (both on Dask distributed);
``python -m fibreshell --help`` lists the commands. Each holds the folder it writes
(fibreshell.folder_lock): one another command writes in is refused with ``FolderInUse``."""

from fibreshell.case import Case, CaseError, load_case
from fibreshell.compare import compare_case
from fibreshell.folder_lock import FolderInUse
from fibreshell.run import Run, run_case, strict_json

__all__ = [
    "Case", "CaseError", "FolderInUse", "Run", "compare_case", "load_case", "run_case",
    "strict_json",
]  # fmt: skip
