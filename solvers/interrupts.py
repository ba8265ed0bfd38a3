"""Runs stopped from outside the mechanics: a signal (Ctrl-C, SIGTERM) asks a solver to stop at
the next step boundary, keeping what it has; a disk that refuses a write stops it with a message
naming the path and what was kept.

Inside ``interruptible()`` the first SIGINT or SIGTERM only sets a flag (``STOP.signal``); the
solvers read it once per step (CentralDifference), per iteration (DynamicRelaxation) or per
converged increment (Static), save their checkpoint where they have one and raise
``Interrupted`` with every good frame in ``.result``. A second signal during that wind-down
raises KeyboardInterrupt as Python does by default. Outside ``interruptible()`` (or off the main
thread, where Python delivers no signal) nothing changes: Ctrl-C raises KeyboardInterrupt.
"""

from __future__ import annotations

import functools
import inspect
import os
import signal
import threading
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any, TypeVar

from femcore.mesh import Mesh
from femcore.writable import FIRST_FRAMES, OutputError, check_folder, frame_bytes, series_frames
from solvers.common import SolverError

__all__ = [
    "STOP", "Interrupted", "StopRequest", "check_outputs", "interruptible", "keeps_writes",
]  # fmt: skip


class Interrupted(SolverError):
    """A solve stopped by SIGINT or SIGTERM at a step boundary. ``result`` holds every good
    frame up to there (``result.converged`` is False); ``signal`` names the signal
    ("SIGINT", "SIGTERM"); ``checkpoint`` is the file the run was saved to (None when the
    solver has none or none was asked for): the same solve with that checkpoint continues the
    run to the same bits as a run never interrupted. ``steps``: the steps or iterations the
    solver took in the stretch it did not finish (a relaxation's increment), counted in
    ``result.steps``."""

    steps: int = 0

    def __init__(
        self,
        message: str,
        result=None,
        signal_name: str = "SIGINT",
        checkpoint: Path | None = None,
    ):
        super().__init__(message, result)
        self.signal = signal_name
        self.checkpoint = checkpoint


class StopRequest:
    """The flag the solvers read: ``signal`` is None, or the name of the signal that asked
    the run to stop."""

    signal: str | None = None


STOP = StopRequest()


@contextmanager
def interruptible(
    signals: tuple[int, ...] = (signal.SIGINT, signal.SIGTERM),
) -> Iterator[StopRequest]:
    """Within the block, the first of ``signals`` asks the running solve to stop at its next
    step boundary (``STOP.signal`` set) instead of raising KeyboardInterrupt; a second one
    raises KeyboardInterrupt. The previous handlers (and the flag) are restored on exit. Off
    the main thread it does nothing (signals only reach the main thread).

    Yields
    ------
    StopRequest
        The flag: ``.signal`` is the name of the signal received, or None.
    """
    if threading.current_thread() is not threading.main_thread():
        yield STOP
        return

    def handler(number: int, frame: Any) -> None:
        if STOP.signal is not None:  # asked twice: stop now, as Python does
            raise KeyboardInterrupt
        STOP.signal = signal.Signals(number).name

    before = STOP.signal
    previous = {number: signal.getsignal(number) for number in signals}
    STOP.signal = None
    for number in signals:
        signal.signal(number, handler)
    try:
        yield STOP
    finally:
        for number, old in previous.items():  # None: a handler not set from Python
            signal.signal(number, signal.SIG_DFL if old is None else old)
        STOP.signal = before


Solve = TypeVar("Solve", bound=Callable[..., Any])


def keeps_writes(solve: Solve) -> Solve:
    """Decorate a solver's ``solve``: an OSError from a write during the run (a full disk,
    a folder made read-only, a path that became a file) becomes one OutputError naming the
    path and what is kept on disk: the frames of the solver's ``output`` series written so
    far and the ``checkpoint`` argument's file."""
    signature = inspect.signature(solve)

    @functools.wraps(solve)
    def guarded(self, *args, **kwargs):
        try:
            return solve(self, *args, **kwargs)
        except OSError as error:  # an OutputError too: it then says what the run kept
            bound = signature.bind_partial(self, *args, **kwargs).arguments
            raise OutputError.from_error(
                error, _kept(getattr(self, "output", None), bound.get("checkpoint"))
            ) from None

    return guarded  # type: ignore[return-value]


def check_outputs(mesh: Mesh, frames: Path | None, *others: Path | None) -> None:
    """Before a run: the folder of the ``frames`` series has room for its first frames, and
    the folders of ``others`` (histories, checkpoints; None: not written) can be written
    (femcore.writable.check_folder: ValueError or OutputError)."""
    if frames is not None:
        check_folder(frames.parent, "output", needed=FIRST_FRAMES * frame_bytes(mesh), create=False)
    for path in others:
        if path is not None:
            check_folder(path.parent, "the folder of " + repr(str(path)), create=False)


def _kept(output: os.PathLike[str] | None, checkpoint: Any) -> str:
    """What a stopped run leaves on disk, in words."""
    kept = []
    if output is not None and Path(output).exists():
        kept.append(f"the {series_frames(Path(output))} frame(s) of {str(output)!r}")
    if checkpoint is not None and Path(checkpoint).exists():
        kept.append(f"the checkpoint {str(checkpoint)!r} (its last save)")
    return " and ".join(kept) if kept else "nothing written by this run"
