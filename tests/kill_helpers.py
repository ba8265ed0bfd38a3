"""Run a script in a child process and kill it with SIGKILL once its checkpoint says it is far
enough: what the checkpoint tests of the explicit solver and of dynamic relaxation share."""

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from solvers.output import load_checkpoint

ROOT = Path(__file__).resolve().parents[1]


def kill_when(script: Path, checkpoint: Path, far_enough, timeout: float) -> None:
    """Start ``script`` (the project on its path), poll ``checkpoint`` until
    ``far_enough(payload)``, then SIGKILL it. Fails if the run ends first or nothing is far
    enough within ``timeout`` seconds."""
    child = subprocess.Popen(
        [sys.executable, str(script)], env=dict(os.environ, PYTHONPATH=str(ROOT))
    )
    deadline = time.monotonic() + timeout
    try:
        while time.monotonic() < deadline:
            payload = load_checkpoint(checkpoint) if checkpoint.exists() else None
            if payload is not None and far_enough(payload):
                return
            assert child.poll() is None, "the run ended before it could be killed"
            time.sleep(0.01)
        pytest.fail(f"the checkpoint was not far enough within {timeout:g} s")
    finally:
        child.send_signal(signal.SIGKILL)
        child.wait()
