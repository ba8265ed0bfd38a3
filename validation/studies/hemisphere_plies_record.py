"""One run of the two-ply hemisphere (validation/studies/hemisphere_plies_run.py ``run``)
kept as a record on disk for the convergence study (validation/studies/
hemisphere_plies_convergence.py): the layup's reference mesh, each frame's node positions
and tool forces, the run's history records (about one every other step) and its
parameters, in one ``.npz``. The measures are taken from records, so a new measure needs no
new run.

Run it with ``python -m validation.studies.hemisphere_plies_record fibrous 0/90 20 12
folder`` (kinematics, stack, holder force N, cells across the blank, where the record goes;
a sixth argument, the die's entry radius in mm, for a run on another die).
"""

from __future__ import annotations

import json
import tempfile
import time
from pathlib import Path
from typing import Any

import numpy as np

__all__ = ["load", "record"]


def record(
    kinematics: str,
    name: str,
    force: float,
    cells: int,
    folder: str | Path,
    rim: float | None = None,
) -> Path:
    """Run the study's run of ``cells`` and write its record to ``folder``; returns its path
    (``<kinematics>_<stack>_<force>N[_rim<rim>]_<cells>.npz``); ``rim`` the die's entry
    radius, mm (None: the study's, DIE_RIM).

    Raises
    ------
    ValueError
        Fibrous runs of cells that have no rms tolerance (``RMS_TOLERANCE_DEG``): their check
        would fail only after the solve.
    """
    from validation.studies.hemisphere_plies_run import RMS_TOLERANCE_DEG, run

    if kinematics == "fibrous" and cells not in RMS_TOLERANCE_DEG:
        raise ValueError(
            f"fibrous runs are checked at {sorted(RMS_TOLERANCE_DEG)} cells "
            f"(RMS_TOLERANCE_DEG), got {cells}"
        )

    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    tag = "" if rim is None else f"_rim{rim:g}"
    stem = f"{kinematics}_{name.replace('/', '-')}_{force:g}N{tag}_{cells}"
    with tempfile.TemporaryDirectory() as scratch:
        history = Path(scratch) / "history.csv"
        start = time.process_time()
        parameters, checks, layup, result, *_ = run(
            cells, name, kinematics, force, history=str(history), rim=rim
        )
        cpu = time.process_time() - start
        records = np.genfromtxt(history, delimiter=",", names=True)
    names = list(records.dtype.names or ())
    n = layup.mesh.n_nodes
    frames = result.frames
    path = folder / f"{stem}.npz"
    np.savez_compressed(
        path,
        reference=layup.mesh.points,
        triangles=layup.mesh.triangles,
        ply_cells=np.concatenate([[len(c) for c in layup.ply_cells]]),
        ply_node_counts=np.array([len(c) for c in layup.ply_nodes]),
        angles=layup.angles,
        warps=layup.warps,
        heights=layup.heights,
        times=np.array([f.time for f in frames]),
        positions=np.stack([f.positions[:n] for f in frames]),
        tool_forces=np.stack([f.tool_forces for f in frames]),
        tool_displacements=np.stack([f.tool_displacements for f in frames]),
        history_names=np.array(names),
        history=np.stack([records[k] for k in names], axis=1),
        parameters=json.dumps(parameters, default=str),
        checks=json.dumps([(c.name, bool(c.passed)) for c in checks]),
        cells=cells,
        cpu_s=cpu,
    )
    return path


def load(path: str | Path) -> dict[str, Any]:
    """A record written by ``record``: its arrays, its parameters and checks decoded, each
    ply's cells and nodes as index arrays (``ply_cells``, ``ply_nodes``) and the history as
    {column: (r,) array}."""
    with np.load(path) as data:
        out: dict[str, Any] = {k: data[k] for k in data.files}
    out["parameters"] = json.loads(str(out["parameters"]))
    out["checks"] = json.loads(str(out["checks"]))
    for key, sizes in (("ply_cells", out["ply_cells"]), ("ply_nodes", out["ply_node_counts"])):
        starts = np.concatenate([[0], np.cumsum(sizes)])
        out[key] = [np.arange(starts[k], starts[k + 1]) for k in range(len(sizes))]
    names = [str(s) for s in out.pop("history_names")]
    out["history"] = dict(zip(names, out["history"].T))
    out["cells"] = int(out["cells"])
    return out


if __name__ == "__main__":
    import sys

    kinematics, name, force, cells, folder = sys.argv[1:6]
    rim = float(sys.argv[6]) if len(sys.argv) > 6 else None
    written = record(kinematics, name, float(force), int(cells), folder, rim)
    print(f"{written}: cpu {np.load(written)['cpu_s']:.1f} s", flush=True)
