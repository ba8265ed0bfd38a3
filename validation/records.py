"""Typed records of the validation report: a case, its checks, its outcome, the report.

A case module in ``validation/cases`` declares one ``Case``: its name, title, source, description,
group and order key, a ``compute`` function (resolution -> ``Outcome``: the numbers, the checks
and, in ``Outcome.data``, what its figures draw and its VTU files hold) and a ``render`` function
(``Outcome.data``, report folder -> the ``Figure`` records of the figures it drew: each file
with its caption). The report runner calls ``compute`` then ``render`` and serialises the
records to results.json with their ``to_json`` methods (the keys and their order are those of
the report's JSON format).

A case whose computation is a few independent runs may declare them as parts: ``parts``
(resolution -> {part key: a function of no argument returning that part's data}) and
``combine`` (resolution, {part key: data} -> the ``Outcome``). With several jobs the report
runs each part as a task of its own in its worker pool and combines their data in its own
process (validation/report.py); with one job, and through ``compute``, the parts run one after
another in one process, with the same results.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

__all__ = [
    "GROUPS",
    "RESOLUTIONS",
    "Case",
    "COMPARISONS",
    "CaseResult",
    "Check",
    "ElementRun",
    "Figure",
    "ObservedOrder",
    "Outcome",
    "Report",
    "SideProfile",
    "SideSummary",
    "caption_problem",
    "compute_parts",
]

RESOLUTIONS = ("coarse", "default", "fine")
# Report order: the paper's tests, the sensitivity study, then the verification cases.
GROUPS = ("paper", "sensitivity", "verification")


@dataclass(frozen=True)
class Check:
    """A computed value against a reference with a stated tolerance (see validation.checks).

    Attributes
    ----------
    name : str
        What is checked, with its unit.
    reference, value : float
        The reference and the computed value.
    error : float
        ``|value - reference|``, divided by ``|reference|`` when ``relative``; for a one-sided
        check, how far the value lies past its bound on the wrong side (0 when it passes).
    tolerance : float
        The largest error that passes (0 for a one-sided check: its bound is the reference).
    relative : bool
        Whether ``error`` and ``tolerance`` are relative.
    passed : bool
        The verdict (True for a reported value, which has none and is not counted).
    source : str
        Where the reference comes from.
    comparison : str
        How value and reference are compared (``COMPARISONS``): "within" the tolerance
        (two-sided), "at least" or "at most" the reference (one-sided, a bound), or
        "reported" (a number shown beside the checks, without a verdict).
    """

    name: str
    reference: float
    value: float
    error: float
    tolerance: float
    relative: bool
    passed: bool
    source: str = ""
    comparison: str = "within"

    @property
    def counted(self) -> bool:
        """Whether the check has a verdict (a reported value has none)."""
        return self.comparison != "reported"


# How a check compares its value with its reference (``Check.comparison``).
COMPARISONS = ("within", "at least", "at most", "reported")

# A caption is at least this many words: what is shown, which kinematics, what to look at.
CAPTION_WORDS = 8


def caption_problem(caption: object, file: str) -> str | None:
    """What is wrong with ``caption`` as the caption of the figure ``file``, or None.

    A caption is one or two sentences a reader understands without the file name: it starts
    with a capital letter, ends with a full stop, has at least ``CAPTION_WORDS`` words and is
    not the file's name (a slug such as "bai-5.1: 3d").
    """
    if not isinstance(caption, str):
        return f"a caption is a str, got {type(caption).__name__}"
    text = caption.strip()
    stem = Path(file).stem
    if not text:
        return "the caption is empty"
    if _words(text) == _words(stem):
        return "the caption is the file's name, not a sentence"
    if len(text.split()) < CAPTION_WORDS:
        return (
            f"a caption is a sentence or two of at least {CAPTION_WORDS} words (what is shown, "
            "which kinematics, what to look at)"
        )
    if not text[0].isupper():
        return "a caption starts with a capital letter"
    if not text.endswith((".", ".)")):
        return "a caption ends with a full stop"
    return None


def _words(text: str) -> str:
    """``text`` lowercased with its dashes, underscores and colons as single spaces."""
    for mark in "-_:":
        text = text.replace(mark, " ")
    return " ".join(text.lower().split())


@dataclass(frozen=True)
class Figure:
    """A figure of the report: its file in the report folder and its caption.

    Attributes
    ----------
    file : str
        The PNG's name in the report folder.
    caption : str
        One or two sentences: what is shown, which kinematics (fibrous, Mindlin or the
        reference) and what to look at (``caption_problem`` says what it must be).
    width, height : int or None
        The image's size in pixels, read by the report runner from the file (None until then),
        so that the page reserves its place and sets small figures side by side.

    Raises
    ------
    ValueError
        When the caption is not one (empty, too short, the file's name), naming the file.
    """

    file: str
    caption: str
    width: int | None = None
    height: int | None = None

    def __post_init__(self) -> None:
        if not isinstance(self.file, str) or not self.file:
            raise ValueError(f"a figure's file is a non-empty str, got {self.file!r}")
        problem = caption_problem(self.caption, self.file)
        if problem is not None:
            raise ValueError(f"figure {self.file!r}: {problem}; got {self.caption!r}")

    def to_json(self) -> dict[str, Any]:
        """The JSON record: {"file", "caption", "width", "height"} (the size in pixels, or
        null)."""
        return {
            "file": self.file,
            "caption": self.caption,
            "width": self.width,
            "height": self.height,
        }


@dataclass(frozen=True)
class SideProfile:
    """Along one filmed side of a paper specimen, node by node from the clamp.

    Attributes
    ----------
    s : numpy.ndarray
        Distance from the clamp along the side in the reference configuration (mm).
    midsurface : numpy.ndarray
        Deformed mid-surface positions, shape (n, 3) (mm).
    director_angle_deg : numpy.ndarray
        Angle of the director to the horizontal seen facing the side (deg, 90 = vertical).
    thickness : numpy.ndarray
        Thickness along the director (mm).
    rotation_deg : numpy.ndarray
        Rotation theta of the mid-surface from the clamp's (horizontal) orientation seen facing
        the side: the slope of the side profile, positive when it rises away from the clamp
        (deg).
    side_tilt_deg : numpy.ndarray
        Tilt of the director from the normal of the side profile seen facing the side, signed
        like ``rotation_deg``: 90 + rotation - director angle (deg; 0 for a director on the
        normal, = rotation for a director that kept its vertical orientation).
    director_tilt_deg : numpy.ndarray
        Angle between the director and the area-weighted nodal normal of the deformed surface,
        in three dimensions (deg, >= 0): the shells' node field of that name.
    """

    s: np.ndarray
    midsurface: np.ndarray
    director_angle_deg: np.ndarray
    thickness: np.ndarray
    rotation_deg: np.ndarray
    side_tilt_deg: np.ndarray
    director_tilt_deg: np.ndarray

    def to_json(self) -> dict[str, Any]:
        """The JSON record (arrays are written as lists by the report's encoder)."""
        return {
            "s": self.s,
            "midsurface": self.midsurface,
            "director_angle_deg": self.director_angle_deg,
            "thickness": self.thickness,
            "rotation_deg": self.rotation_deg,
            "side_tilt_deg": self.side_tilt_deg,
            "director_tilt_deg": self.director_tilt_deg,
        }


@dataclass(frozen=True)
class SideSummary:
    """The numbers the report quotes for one element and one side of a paper case; the tilts
    away from the clamped node (the side's first), where the director is held while the
    profile's slope is a one-sided difference."""

    max_midsurface_slope_deg: float
    director_angle_min_deg: float
    director_angle_max_deg: float
    thickness_max_over_h: float
    side_tilt_max_deg: float  # largest |tilt| of the director from the normal, facing the side
    normal_tilt_max_deg: float  # largest angle of the director to the nodal normal, in 3D


@dataclass(frozen=True)
class ElementRun:
    """One kinematics of a paper case ("fibrous", "fibrous_element" or "mindlin", the keys of
    validation.paper.KINEMATICS): its solve and its sides.

    Attributes
    ----------
    label : str
        The kinematics in words, as the figures' legends name it.
    converged : bool
        Whether the solver reached the full load.
    wall_time_s : float
        Solver wall time.
    steps : int
        Increments or iterations of the solver.
    solver : str
        Which solver ran, in words.
    sides : dict of str to SideProfile
        "side_1" (and "side_2" when the specimen has it).
    fibre_strain : dict of str to float or None
        For the fibrous shell: max_fibre_strain, max_fibre_strain_away_from_support,
        max_shear_angle_deg.
    """

    label: str
    converged: bool
    wall_time_s: float
    steps: int
    solver: str
    sides: dict[str, SideProfile]
    fibre_strain: dict[str, float] | None = None

    def to_json(self) -> dict[str, Any]:
        """The JSON record: the solve, the fibre statistics, then one entry per side."""
        record: dict[str, Any] = {
            "label": self.label,
            "converged": self.converged,
            "wall_time_s": self.wall_time_s,
            "steps": self.steps,
            "solver": self.solver,
        }
        record.update(self.fibre_strain or {})
        record.update({name: side.to_json() for name, side in self.sides.items()})
        return record


@dataclass(frozen=True)
class ObservedOrder:
    """The observed order of convergence of one quantity of one kinematics on three meshes
    (``validation.checks.observed_order``).

    Attributes
    ----------
    kinematics : str
        The kinematics' key ("fibrous", "mindlin", ...).
    quantity : str
        What was measured, with its unit.
    cells : tuple of int
        The cells argument of the three meshes, coarsest first.
    sizes : tuple of float
        Their mesh sizes h (mm), decreasing.
    values : tuple of float
        The quantity on each mesh.
    order : float
        The observed order p (NaN: none, the differences change sign or vanish).
    extrapolated : float
        The Richardson value at h = 0 (NaN with p).
    converged : bool
        Whether the three runs reached the full load.
    """

    kinematics: str
    quantity: str
    cells: tuple[int, ...]
    sizes: tuple[float, ...]
    values: tuple[float, ...]
    order: float
    extrapolated: float
    converged: bool


@dataclass(frozen=True)
class Outcome:
    """What a case's ``compute`` returns: the report's numbers and the data of its figures.

    Attributes
    ----------
    converged : bool
        Whether every solve of the case converged.
    wall_time_s : float
        Wall time of the solves (or of the computation when there is no solver).
    steps : int
        Increments or iterations, summed over the solves.
    solver : str
        Which solver ran, in words.
    parameters : dict
        The stated parameters, name -> number or text.
    checks : list of Check
        The verification checks.
    figures : list of Figure
        The figures in the report folder with their captions; empty until the case's
        ``render`` ran.
    elements : dict of str to ElementRun or None
        Paper cases: one record per kinematics.
    key_numbers : dict of str to SideSummary or None
        Paper cases: per "kinematics side", the numbers the report quotes.
    discussion : str or None
        Paper cases: what the figures show, in words with numbers of the run (paragraphs
        separated by blank lines), rendered next to the figures.
    orders : list of ObservedOrder or None
        Paper cases: the observed orders of the quantities they report, on three meshes.
    error : str or None
        Set by the report runner when the case raised.
    warnings : tuple of str
        Set by the report runner: the Python warnings raised while the case ran, its parts
        and its figures included ("Category: message", each once; validation/case_warnings.py).
    data : object
        What the case's ``render`` draws and writes (arrays, solver results); not in
        results.json.
    """

    converged: bool
    wall_time_s: float
    steps: int
    solver: str
    parameters: dict[str, Any]
    checks: list[Check]
    figures: list[Figure] = field(default_factory=list)
    elements: dict[str, ElementRun] | None = None
    key_numbers: dict[str, SideSummary] | None = None
    discussion: str | None = None
    orders: list[ObservedOrder] | None = None
    error: str | None = None
    warnings: tuple[str, ...] = ()
    data: Any = field(default=None, repr=False, compare=False)

    @classmethod
    def failed(cls, error: BaseException | str) -> Outcome:
        """The outcome of a case that raised ``error`` (or the error's text: "Type: message",
        a part's error as its worker process reported it)."""
        return cls(
            converged=False,
            wall_time_s=0.0,
            steps=0,
            solver="",
            parameters={},
            checks=[],
            error=error if isinstance(error, str) else f"{type(error).__name__}: {error}",
        )


@dataclass(frozen=True)
class Case:
    """A validation case, declared as ``CASE`` by its module in ``validation/cases``.

    Attributes
    ----------
    name : str
        Unique name, used by ``--cases`` and as the report's anchor and file prefix.
    title : str
        One line for the report.
    source : str
        The reference it is validated against.
    description : str
        The full statement (the module docstring: source, geometry, parameters, assumptions).
    group : str
        "paper", "sensitivity" or "verification" (``GROUPS``, the report order).
    order : int
        Position within the group (ascending).
    compute : callable
        ``compute(resolution) -> Outcome`` with ``Outcome.figures`` empty.
    render : callable
        ``render(data, out_dir) -> list[Figure]``: draws the figures and writes the VTU files
        of ``Outcome.data`` into ``out_dir``, returns each figure's file and caption.
    parts : callable or None
        For a case made of independent runs: ``parts(resolution) -> {key: run}``, each ``run``
        a function of no argument (picklable: a module's function or a ``functools.partial``
        of one) returning its part's data (picklable too: it may come back from a worker
        process); cheap to call, as every worker that runs a part calls it. None: one task.
    combine : callable or None
        With ``parts``: ``combine(resolution, {key: data}) -> Outcome``, the outcome ``compute``
        returns (``compute(resolution)`` is ``combine`` of the parts run in order).
    """

    name: str
    title: str
    source: str
    description: str
    group: str
    order: int
    compute: Callable[[str], Outcome] = field(repr=False)
    render: Callable[[Any, Path], list[Figure]] = field(repr=False)
    parts: Callable[[str], dict[str, Callable[[], Any]]] | None = field(default=None, repr=False)
    combine: Callable[[str, dict[str, Any]], Outcome] | None = field(default=None, repr=False)

    def __post_init__(self) -> None:
        if self.group not in GROUPS:
            raise ValueError(
                f"case {self.name!r}: group must be one of {', '.join(GROUPS)}, got {self.group!r}"
            )
        if (self.parts is None) != (self.combine is None):
            raise ValueError(
                f"case {self.name!r}: parts and combine are given together (a case in parts "
                f"needs the step that combines them) or not at all, got parts "
                f"{self.parts!r} and combine {self.combine!r}"
            )

    @property
    def sort_key(self) -> tuple[int, int, str]:
        """The report order: group, then order key, then name."""
        return GROUPS.index(self.group), self.order, self.name


def compute_parts(
    parts: Callable[[str], dict[str, Callable[[], Any]]],
    combine: Callable[[str, dict[str, Any]], Outcome],
    resolution: str,
) -> Outcome:
    """The outcome of a case in parts at ``resolution``: its ``parts`` run one after another
    in this process, in their order, then ``combine``d (a case's ``compute``)."""
    return combine(resolution, {key: run() for key, run in parts(resolution).items()})


@dataclass(frozen=True)
class CaseResult:
    """A case and its outcome in the report, with the wall time of compute and render and,
    where measured, the CPU time of the process that ran them (s; its threads included, not
    its child processes: bai-6.1.1-sensitivity's Dask workers). A case in parts
    (``Case.parts``): the sums over its parts and the step that combined them and drew the
    figures, wherever they ran (its cost, as in one process, not its span beside the report's
    other tasks; a failed case's ``wall_time_s`` too), and ``parts`` each part's (wall, CPU)
    time, s, by its key."""

    case: Case
    outcome: Outcome
    case_time_s: float
    case_cpu_s: float | None = None
    parts: dict[str, tuple[float, float]] | None = None

    @property
    def passed(self) -> int:
        """Number of passed checks (the reported values, which have no verdict, left out)."""
        return sum(c.passed for c in self.outcome.checks if c.counted)

    @property
    def counted(self) -> int:
        """Number of checks with a verdict (the reported values left out)."""
        return sum(c.counted for c in self.outcome.checks)

    def to_json(self) -> dict[str, Any]:
        """The case's entry of results.json."""
        o = self.outcome
        checks = [asdict(c) for c in o.checks]
        if o.error is not None:
            record = {
                "converged": o.converged,
                "error": o.error,
                "checks": checks,
                "figures": [f.to_json() for f in o.figures],
                "parameters": dict(o.parameters),
                "steps": o.steps,
                "solver": o.solver,
                "case_time_s": self.case_time_s,
                "wall_time_s": self.case_time_s,
            }
            if self.case_cpu_s is not None:
                record["case_cpu_s"] = self.case_cpu_s
        else:
            record = {
                "converged": o.converged,
                "wall_time_s": o.wall_time_s,
                "steps": o.steps,
                "solver": o.solver,
                "parameters": dict(o.parameters),
            }
            if o.elements is not None:
                record["elements"] = {k: e.to_json() for k, e in o.elements.items()}
            if o.key_numbers is not None:
                record["key_numbers"] = {k: asdict(v) for k, v in o.key_numbers.items()}
            if o.discussion is not None:
                record["discussion"] = o.discussion
            if o.orders is not None:
                record["observed_orders"] = [asdict(order) for order in o.orders]
            record.update(
                checks=checks,
                figures=[f.to_json() for f in o.figures],
                case_time_s=self.case_time_s,
            )
            if self.case_cpu_s is not None:
                record["case_cpu_s"] = self.case_cpu_s
        record["warnings"] = list(o.warnings)
        if self.parts is not None:
            record["parts"] = {
                key: {"time_s": wall, "cpu_s": cpu} for key, (wall, cpu) in self.parts.items()
            }
        record.update(
            title=self.case.title,
            source=self.case.source,
            description=self.case.description.strip(),
        )
        return record


@dataclass(frozen=True)
class Report:
    """The whole report: when, at which resolution, on which machine, and every case."""

    generated: str
    resolution: str
    machine: str
    cases: dict[str, CaseResult]

    def to_json(self) -> dict[str, Any]:
        """The content of results.json."""
        return {
            "generated": self.generated,
            "resolution": self.resolution,
            "machine": self.machine,
            "cases": {name: r.to_json() for name, r in self.cases.items()},
        }
