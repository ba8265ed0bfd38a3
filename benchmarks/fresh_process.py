"""Run a benchmark's measurement in a fresh Python process (one numba thread), so that its
figures (build time, peak memory) are not those of the models the calling process built."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path


def fresh_output(module: str, call: str) -> str:
    """The standard output of ``call`` (Python source, e.g. ``"_build_child('fibrous', 400)"``)
    on the benchmark ``module`` (a file of benchmarks/, imported as ``b``) run in a fresh
    process with one numba thread, from the repository's root; a RuntimeError with the end of
    its stderr when it fails."""
    script = f"import sys; sys.path.insert(0, 'benchmarks'); import {module} as b; b.{call}"
    root = Path(__file__).resolve().parents[1]
    env = {**os.environ, "PYTHONPATH": str(root), "NUMBA_NUM_THREADS": "1"}
    out = subprocess.run(
        [sys.executable, "-c", script], cwd=root, env=env, capture_output=True, text=True
    )
    if out.returncode != 0:
        raise RuntimeError(out.stderr[-2000:])
    return out.stdout
