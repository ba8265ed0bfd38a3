"""Progress of a run: one bar on stderr (rich) with the share done and an estimate of the time
left from a smoothed rate, or plain lines a few seconds apart where stderr is a log file.

The estimate (``RemainingTime``) ignores the start of a run, whose first steps compile the
kernels (numba) and would make the run look many times longer than it is, and follows the
recent rate (an average over the last part of the run, weighted by time) rather than the
rate since the start.
"""

from __future__ import annotations

import importlib.util
import math
import os
import sys
import time
from collections.abc import Callable
from typing import IO, Any

__all__ = ["ProgressLine", "RemainingTime", "relaxed_share", "resolve_progress"]

# The share of the run treated as warm-up: the time up to the first sample past it never
# enters the rate (numba compiles on the first steps of a run; a resumed run compiles again
# before its first sample).
WARM_UP = 0.02
# The rate is an average over the recent part of the run: samples older than this share of
# the time since warm-up weigh e times less (short enough to follow a run that slows down,
# long enough to smooth the scatter of the step times).
MEMORY = 0.3
# Plain lines (stderr not a terminal nor a notebook): at most one every this many seconds.
LINE_EVERY = 5.0
# The bar: redrawn with the caller's numbers at most this often (s), and by rich's own thread
# between calls (a long increment: the time taken and the time left keep counting); the cost
# of a call in between is a clock read and a comparison, small beside a time step.
PUSH_EVERY = 0.25
# The estimate's samples: at least this far apart (s), or a percent of the run.
SAMPLE_EVERY = 0.1


def resolve_progress(progress: bool | None) -> bool:
    """Whether a run shows its progress. ``progress`` True or False decides; None (the
    default) shows it on a terminal, in a notebook and in a log alike (a log gets a line every
    few seconds), except with the environment variable FIBRESHELL_PROGRESS=0 (the validation
    report, which prints a line per case, sets it) and under pytest (a test's output is
    noise)."""
    if progress is not None:
        return bool(progress)
    if os.environ.get("FIBRESHELL_PROGRESS", "1") == "0":
        return False
    return "PYTEST_CURRENT_TEST" not in os.environ


class RemainingTime:
    """The time left in a run from the share done, sample by sample.

    The rate (share per second) is the ratio of two sums over the samples since warm-up, the
    share gained and the time taken, each sample weighted by exp(-age / (MEMORY x the time
    since warm-up)): the recent rate, smoothed over a window that grows with the run.

    Parameters
    ----------
    warm_up : float
        The share of the run treated as warm-up: the time up to the first sample at or past
        it never enters the rate (a run resumed past it: the time up to its first sample).
    memory : float
        The window of the average, as a share of the time since warm-up.
    """

    def __init__(self, warm_up: float = WARM_UP, memory: float = MEMORY):
        self.warm_up, self.memory = warm_up, memory
        self._anchor: float | None = None  # the time warm-up ended, s
        self._last = (0.0, 0.0)  # the last sample's (time s, share)
        self._share_sum = self._time_sum = 0.0

    def update(self, now: float, fraction: float) -> None:
        """Take a sample: the share of the run done (0 to 1) at time ``now`` (s, any origin,
        not decreasing)."""
        if self._anchor is None:
            if fraction >= self.warm_up:
                self._anchor = now
                self._last = (now, fraction)
            return
        before, done = self._last
        elapsed = now - before
        if elapsed <= 0.0:
            return
        window = self.memory * (now - self._anchor)
        decay = math.exp(-elapsed / window)
        self._share_sum = decay * self._share_sum + max(fraction - done, 0.0)
        self._time_sum = decay * self._time_sum + elapsed
        self._last = (now, max(fraction, done))

    def remaining(self, now: float | None = None) -> float | None:
        """The time left (s) at the last sample, or at ``now`` (counting down since it);
        None while warming up or before the run has moved."""
        if self._share_sum <= 0.0:
            return None
        at, done = self._last
        left = (1.0 - done) * self._time_sum / self._share_sum
        return max(left - (now - at if now is not None else 0.0), 0.0)


def relaxed_share(start: float, ratio: float, tol: float) -> float:
    """How far a relaxation has come from its first residual ratio ``start`` to the
    tolerance ``tol``, on a log scale (the ratio falls about geometrically): log(start /
    ratio) / log(start / tol), in [0, 1]; 0 for a ratio that is not finite or above start."""
    if not math.isfinite(ratio):
        return 0.0
    if ratio <= tol:
        return 1.0
    if not math.isfinite(start) or start <= tol:
        return 0.0
    return min(max(math.log(start / ratio) / math.log(start / tol), 0.0), 1.0)


def duration_text(seconds: float) -> str:
    """ "42 s", "3 min 20 s", "2 h 05 min"."""
    if seconds < 60:
        return f"{seconds:.0f} s"
    if seconds < 3600:
        return f"{int(seconds // 60)} min {int(seconds % 60):02d} s"
    return f"{int(seconds // 3600)} h {int(seconds % 3600 // 60):02d} min"


class ProgressLine:
    """The progress of one run on stderr: a rich bar (label, bar, share, time taken, time
    left, the caller's status text) on a terminal or in a notebook, plain lines at most every
    ``every`` seconds elsewhere (a log file, a pipe). The time left is ``RemainingTime``'s.

    Use it as a context manager (or call ``close``): the bar stays on screen with its last
    status; a log gets the last status as its final line.

    Parameters
    ----------
    enabled : bool
        False: every call does nothing (``resolve_progress`` decides it).
    label : str
        What runs ("static", "central difference").
    every : float, optional
        Plain lines: the least time between two lines, s (default LINE_EVERY).
    stream : file, optional
        Where to write (default: sys.stderr when the bar starts).
    clock : callable, optional
        Seconds from any origin (default ``time.perf_counter``); a test's own clock.
    """

    def __init__(
        self,
        enabled: bool,
        label: str,
        every: float | None = None,
        stream: IO[str] | None = None,
        clock: Callable[[], float] = time.perf_counter,
    ):
        self.enabled, self.label = enabled, label
        self.every = LINE_EVERY if every is None else every
        self._stream, self._clock = stream, clock
        self._estimate = RemainingTime()
        self._started = clock()
        self._fraction: float | None = None  # the largest share reported
        self._text: str | Callable[[], str] = ""
        self._shown = True  # the last status is on screen or in the log
        self._sampled = self._pushed = -math.inf
        self._at = 0.0  # the share at the last sample
        self._printed = self._started  # plain lines: the time of the last one
        self._bar: Any = None  # rich.progress.Progress once started; False: plain lines
        self._task: Any = None

    def __enter__(self) -> ProgressLine:
        return self

    def __exit__(self, *exc_info: object) -> None:
        self.close()

    def __call__(
        self, text: str | Callable[[], str], force: bool = False, fraction: float | None = None
    ) -> None:
        """The run's status: ``text`` (or a function making it, called only when it is shown)
        and the share done ``fraction`` in [0, 1] (None: unchanged). ``force``: an event that
        gets a line of its own at once (a limit point, a negative eigenvalue), kept above the
        bar and in a log."""
        if not self.enabled:
            return
        now = self._clock()
        if fraction is not None:
            fraction = min(max(float(fraction), 0.0), 1.0)
            self._fraction = max(fraction, self._fraction or 0.0)
            # Samples a tenth of a second or a percent apart: a time step's call costs a
            # clock read, and a static increment is never missed.
            if now - self._sampled >= SAMPLE_EVERY or self._fraction - self._at >= 0.01:
                self._estimate.update(now, self._fraction)
                self._sampled, self._at = now, self._fraction
        self._text, self._shown = text, False
        if self._bar is None:
            self._start()
        if force:
            self._note(now)
        elif self._bar is False:
            if now - self._printed >= self.every:
                self._line(now)
        elif now - self._pushed >= PUSH_EVERY:
            self._push(now)

    def close(self) -> None:
        """End the display: the bar drawn a last time and left on screen, or the last status
        written as the log's final line (if not written yet)."""
        if not self.enabled or self._bar is None:
            return
        now = self._clock()
        if self._bar is False:
            if not self._shown:
                self._line(now)
        else:
            self._push(now)
            self._bar.stop()
        self._bar = None
        self.enabled = False

    # ------------------------------------------------------------------ display
    def _start(self) -> None:
        from rich.console import Console

        console = Console(file=self._stream or sys.stderr)
        if not (console.is_terminal and not console.is_dumb_terminal) and not (
            console.is_jupyter and _widgets()
        ):
            self._bar = False
            return
        from rich.progress import BarColumn, Progress, TextColumn, TimeElapsedColumn
        from rich.table import Column

        self._bar = Progress(
            TextColumn("[bold]{task.fields[label]}"),
            BarColumn(bar_width=24, finished_style="green"),
            TextColumn("{task.percentage:>3.0f} %"),
            TimeElapsedColumn(),
            _time_left_column(self),
            TextColumn(
                "{task.description}",
                markup=False,
                table_column=Column(no_wrap=True, overflow="ellipsis", ratio=1),
            ),
            console=console,
            expand=True,
            refresh_per_second=2,
            get_time=self._clock,
            # Prints during the run go above the bar; stdout only when it is a terminal too
            # (the console writes to stderr: a piped stdout must keep its lines).
            redirect_stdout=_is_terminal(sys.stdout),
        )
        self._task = self._bar.add_task("", total=1.0, label=self.label)
        self._bar.start()

    def _status(self) -> str:
        self._shown = True
        return self._text() if callable(self._text) else self._text

    def _push(self, now: float) -> None:
        self._pushed = now
        self._bar.update(
            self._task, description=self._status(), completed=self._fraction or 0.0, refresh=True
        )

    def _note(self, now: float) -> None:
        if self._bar is False:
            self._line(now)
        else:
            self._push(now)
            self._bar.console.print(
                f"[{self.label}] {self._status()}", markup=False, highlight=False
            )

    def _line(self, now: float) -> None:
        self._printed = now
        elapsed = now - self._started
        if self._fraction is None:
            numbers = f"{elapsed:.1f} s"
        elif self._fraction >= 1.0:
            numbers = f"100 %, {elapsed:.1f} s"
        else:
            left = self._estimate.remaining(now)
            eta = "" if left is None else f", ETA {duration_text(left)}"
            numbers = f"{100 * self._fraction:.0f} %, {duration_text(elapsed)}{eta}"
        stream = self._stream or sys.stderr
        print(f"[{self.label}] {self._status()} [{numbers}]", file=stream, flush=True)

    @property
    def finished(self) -> bool:
        """The run reported its whole share done."""
        return self._fraction is not None and self._fraction >= 1.0

    def time_left(self) -> float | None:
        """The estimated time left now (s), None while not known."""
        return 0.0 if self.finished else self._estimate.remaining(self._clock())


def _is_terminal(stream: Any) -> bool:
    try:
        return bool(stream.isatty())
    except (AttributeError, ValueError):  # no isatty, or a closed file
        return False


def _widgets() -> bool:
    """A notebook draws the bar with ipywidgets; without them it gets plain lines."""
    return importlib.util.find_spec("ipywidgets") is not None


def _time_left_column(line: ProgressLine) -> Any:
    from rich.progress import ProgressColumn
    from rich.text import Text

    class TimeLeft(ProgressColumn):
        """ "ETA 0:01:05" from the line's estimate (rich's own is the rate since the start)."""

        def render(self, task: Any) -> Text:
            if line.finished:
                return Text("")
            left = line.time_left()
            if left is None:
                return Text("ETA -:--:--", style="progress.remaining")
            seconds = round(left)
            clock = f"{seconds // 3600}:{seconds % 3600 // 60:02d}:{seconds % 60:02d}"
            return Text(f"ETA {clock}", style="progress.remaining")

    return TimeLeft()
