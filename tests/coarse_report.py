"""The coarse validation report run in the background beside the tests
(tests/conftest.py, the ``coarse_report`` fixture): ``python -m validation`` in a process group
of its own, and whether numba's cache already holds the kernels its cases call first."""

import json
import os
import shutil
import signal
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


class CoarseReport:
    """``python -m validation --resolution coarse --jobs 2`` (the README's main job) running
    in its own process group, writing into a temporary folder: ``out`` the report, ``log``
    its printed lines."""

    def __init__(self) -> None:
        self.folder = Path(tempfile.mkdtemp(prefix="fibreshell-coarse-report-"))
        self.out = self.folder / "report"
        self.log = self.folder / "report.log"
        with open(self.log, "wb") as log:
            self.process = subprocess.Popen(
                [sys.executable, "-m", "validation", "--resolution", "coarse",
                 "--out", str(self.out), "--jobs", "2"],
                cwd=ROOT, stdout=log, stderr=subprocess.STDOUT, start_new_session=True,
            )  # fmt: skip

    def result(self) -> tuple[Path, dict]:
        """The report folder and its results.json, once the run has ended."""
        status = self.process.wait()
        assert status == 0, self.log.read_text()[-4000:]
        return self.out, json.loads((self.out / "results.json").read_text())

    def stop(self) -> None:
        """The run and its workers ended (asked to stop, as Ctrl-C would: each finishes its
        step; killed if still there after 30 s), the folder removed."""
        if self.process.poll() is None:
            os.killpg(self.process.pid, signal.SIGTERM)
            self.process.wait()
        for _ in range(300):
            try:
                os.killpg(self.process.pid, 0)
            except ProcessLookupError:
                break
            time.sleep(0.1)
        else:
            os.killpg(self.process.pid, signal.SIGKILL)
        shutil.rmtree(self.folder, ignore_errors=True)


# The kernels the report's cases call first: its run starts once the tests have compiled
# them into numba's cache (``cache=True``), or once a third of the tests have run, so that its
# two workers do not compile them again beside the tests in a fresh checkout.
REPORT_KERNELS = ("kernels._cells_pass", "kernels._mindlin_cells",
                  "tangent_kernels._membrane_product", "mindlin_tangent._tangent_cells",
                  "facet_search._closest_facets", "band._factorise")  # fmt: skip


def report_kernels_cached() -> bool:
    """Whether numba's cache (``NUMBA_CACHE_DIR``, or ``__pycache__`` beside each module)
    holds a build of each of ``REPORT_KERNELS``."""
    folder = os.environ.get("NUMBA_CACHE_DIR")
    if folder:
        indices = Path(folder).glob("**/*.nbi")
    else:
        packages = ("elements", "elements/fibrous", "femcore", "solvers")
        indices = (i for p in packages for i in (ROOT / p / "__pycache__").glob("*.nbi"))
    cached = {index.name.rsplit("-", 1)[0] for index in indices}
    return all(kernel in cached for kernel in REPORT_KERNELS)
