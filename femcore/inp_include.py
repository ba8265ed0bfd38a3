"""An Abaqus deck with its *INCLUDE files read in place: one stream of lines, each with the
file and the line number where it stands.

Abaqus and CalculiX read ``*INCLUDE, INPUT=file`` as if the lines of ``file`` stood in place
of the keyword line, to any depth of nesting. A relative INPUT= is found from the folder the
job runs in, which is the main deck's (``abaqus job=model`` and ``ccx model`` run in the
folder holding ``model.inp``), at every depth: ``INPUT=nodes.inp`` written in
``parts/mesh.inp`` is the ``nodes.inp`` beside the main deck, not ``parts/nodes.inp``
(CalculiX 2.20 run on such a deck stops with "cannot open file nodes.inp"; the Abaqus
convention as tools that write decks for it state it: a relative path is relative to the
directory the job was started from). The mesh reader has no job folder of its own, so the
main deck's folder stands for it, whatever the working folder of the Python process: a file
of the same name there is never taken instead.

The data lines of *NODE, *ELEMENT, *NSET and *ELSET may stand in a file of their own
(``*NODE, INPUT=nodes.txt``): that file's lines are read in place of the keyword's, found by
the same rule, after the keyword line without its INPUT=. A keyword line that ends with a
comma continues on the next line (``*ELEMENT, TYPE=S3,`` then ``ELSET=Plate``): it is given
as one line, at the number of its first.

Every reader of a deck's lines (femcore.inp_deck's keyword scan, femcore.inp_sets' sets)
reads them through :func:`deck_lines`, so a set in an included file naming the main deck's
nodes, a set defined in two files, or an *ELSET of sets across files are read by one rule,
and an error names the file and the line where the text stands.
"""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path

__all__ = ["deck_lines", "located"]


def located(file: Path, number: int, main: Path) -> str:
    """Where a line stands, for messages: ``"line 12"`` in the main deck, ``"mesh.inp line
    3"`` in a file it includes (its path as the main deck's folder reaches it)."""
    if file == main:
        return f"line {number}"
    try:
        shown = file.relative_to(main.parent)
    except ValueError:
        shown = file
    return f"{shown} line {number}"


def deck_lines(path: Path) -> Iterator[tuple[Path, int, str]]:
    """The lines of the deck at ``path`` in the order Abaqus reads them, each *INCLUDE line
    replaced by the lines of the file it names (nested to any depth).

    Parameters
    ----------
    path : pathlib.Path
        The main deck (.inp, UTF-8 text).

    Yields
    ------
    tuple[pathlib.Path, int, str]
        (the file the line stands in: ``path`` or ``path.parent / INPUT``, its 1-based line
        number there, the line without its line break).

    Raises
    ------
    ValueError
        Naming the including file and line: an *INCLUDE without INPUT=, a file it names that
        does not exist (and where a file of that name stands beside the including file, the
        INPUT= that reaches it), an include cycle (the chain of files); naming the file: one
        that is not UTF-8 text.
    """
    return _lines(path, path.parent, [path.resolve()])


def _lines(path: Path, job: Path, chain: list[Path]) -> Iterator[tuple[Path, int, str]]:
    try:
        text = path.read_text(encoding="utf-8")
    except UnicodeDecodeError as err:
        raise ValueError(
            f"cannot read {path} as 'abaqus': not a text file ({err.reason} at byte {err.start})"
        ) from None
    for number, line in _keyword_lines_joined(text.splitlines()):
        data_keyword = line.startswith("*") and _data_keyword(line)
        if not (line.startswith("*") and (_is_include(line) or data_keyword)):
            yield path, number, line
            continue
        keyword = f"*{data_keyword}" if data_keyword else "*INCLUDE"
        where = f"{path}: line {number}: {keyword}"
        named = _input(line)
        if data_keyword and not named:  # the data lines follow the keyword line
            yield path, number, line
            continue
        if not named:
            raise ValueError(f"{where}: no INPUT= file name (expected *INCLUDE, INPUT=mesh.inp)")
        included = job / named  # an absolute INPUT= stays itself
        if not included.is_file():
            raise ValueError(f"{where}, INPUT={named}: {_missing(included, path, named, job)}")
        if data_keyword:
            # The keyword's data lines stand in the file INPUT= names (Abaqus Keywords
            # Reference, *NODE, *ELEMENT, *NSET, *ELSET: INPUT): the keyword line without
            # INPUT=, then those lines, read where they stand.
            yield path, number, _without_input(line)
            yield from _data_lines(included, f"{where}, INPUT={named}")
            continue
        resolved = included.resolve()
        if resolved in chain:
            cycle = " -> ".join(str(file) for file in [*chain[chain.index(resolved) :], resolved])
            raise ValueError(
                f"{where}, INPUT={named}: an include cycle ({cycle}): a deck would include "
                "itself without end; remove the *INCLUDE that closes the cycle"
            )
        yield from _lines(included, job, [*chain, resolved])


def _keyword_lines_joined(lines: list[str]) -> Iterator[tuple[int, str]]:
    """(1-based number, line) of ``lines``, a keyword line that ends with a comma joined with
    the lines that continue it (Abaqus "Input syntax rules": a keyword line continues on the
    next line when it ends with a comma), numbered as its first line."""
    number = 0
    while number < len(lines):
        line, first = lines[number], number + 1
        number += 1
        if line.startswith("*") and not line.startswith("**"):
            while line.rstrip().endswith(",") and number < len(lines):
                line = line.rstrip() + " " + lines[number].strip()
                number += 1
        yield first, line


def _is_include(line: str) -> bool:
    """Whether the keyword or comment line ``line`` is an *INCLUDE keyword line (keywords:
    any case, blanks ignored)."""
    if line.startswith("**"):
        return False
    head = line[1:].partition(",")[0]
    return "".join(head.split()).upper() == "INCLUDE"


# The keywords whose data lines may stand in a file of their own (INPUT=).
_DATA_KEYWORDS = frozenset({"NODE", "ELEMENT", "NSET", "ELSET"})


def _data_keyword(line: str) -> str:
    """The keyword (upper case) of the keyword line ``line`` when it is one whose data lines
    INPUT= may name, "" otherwise."""
    if line.startswith("**"):
        return ""
    keyword = " ".join(line[1:].partition(",")[0].split()).upper()
    return keyword if keyword in _DATA_KEYWORDS else ""


def _without_input(line: str) -> str:
    """The keyword line ``line`` without its INPUT= parameter."""
    head, *items = line.split(",")
    kept = [item for item in items if item.partition("=")[0].strip().upper() != "INPUT"]
    return ",".join([head, *kept])


def _data_lines(path: Path, where: str) -> Iterator[tuple[Path, int, str]]:
    """The lines of a file of data lines named by INPUT=; ValueError naming ``where`` and the
    line for a keyword line in it (such a file holds data lines only)."""
    try:
        text = path.read_text(encoding="utf-8")
    except UnicodeDecodeError as err:
        raise ValueError(
            f"{where}: cannot read {path}: not a text file ({err.reason} at byte {err.start})"
        ) from None
    for number, line in enumerate(text.splitlines(), start=1):
        if line.startswith("*") and not line.startswith("**"):
            raise ValueError(
                f"{where}: {path} line {number} is a keyword line ({line.strip()!r}); a file "
                "named by a keyword's INPUT= holds that keyword's data lines only (use "
                "*INCLUDE for a file of keywords)"
            )
        yield path, number, line


def _input(line: str) -> str:
    """The INPUT= value of an *INCLUDE line, quotes removed ("" when not given)."""
    for item in line.split(",")[1:]:
        key, equals, value = item.partition("=")
        if equals and key.strip().upper() == "INPUT":
            return value.strip().strip("'\"")
    return ""


def _missing(included: Path, including: Path, named: str, job: Path) -> str:
    """Why ``included`` cannot be read: where it was looked for, and the INPUT= that reaches a
    file of that name beside the including file, if there is one."""
    said = f"no file {str(included)!r}"
    if not Path(named).is_absolute() and including.parent != job:
        beside = including.parent / named
        if beside.is_file():
            try:
                reach = beside.relative_to(job).as_posix()
            except ValueError:
                reach = str(beside.resolve())
            return (
                f"{said}: Abaqus and CalculiX read a relative INPUT= from the folder of the "
                f"main deck ({str(job)!r}), not from the including file's; for {str(beside)!r} "
                f"write INPUT={reach}"
            )
    return f"{said} (a relative INPUT= is read from the main deck's folder, {str(job)!r})"
