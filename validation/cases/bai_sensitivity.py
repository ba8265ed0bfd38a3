"""Sensitivity of the paper-stack corner test (bai-6.1.1) to the values the paper does not give.

Source: Bai et al. (2020) §6.1 gives no material data for the 130-sheet paper stack; the case
bai-6.1.1 assumes bending B = 50 N mm and in-plane shear K = 1000 N/mm
(materials.presets.paper_stack). Here the fibrous run is repeated with B halved and doubled and
K divided and multiplied by 10 (the other values as in bai-6.1.1), and the Mindlin run with B
halved and doubled (MindlinShell(fabric), the fabric's own laws, the sweep's default
calibration "laws": its bending law and its transverse shear S = 5 B0 / h^2 follow B). The
eight runs are one parameter sweep of the case file of bai-6.1.1 (fibreshell.sweep, keys
kinematics, part.0.material.bending and part.0.material.shear paired), each a Dask task on a
local cluster of as many worker processes as this process has numba threads (``sweep_workers``:
the report gives each of its workers its share of the cores, so the cluster takes that share,
not a core each beside the report's other workers); with one thread (a report of two jobs on
two cores) the runs are the sweep's in this process (``in_process``), which a cluster of one
worker process would only delay: its start, its imports and numba kernels loaded again cost
2.8 s of CPU beside the runs' 6.6 s (benchmarks/report.py).
What is compared: along side 1, the mid-surface and the director angle. The conclusion the
paper draws (fibrous directors stay nearly vertical while the Mindlin ones follow the normal)
must not depend on these choices; the check states it for every variant.
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from fibreshell.sweep import sweep
from materials.presets import paper_stack
from validation import specimens
from validation.checks import bound, check
from validation.paper import ARC_CHORDS, INCREMENTS
from validation.plots import plt, save
from validation.records import Case, Figure, Outcome

__all__ = ["CASE", "SensitivityData", "base_case", "compute", "render", "sweep_workers"]

NAME = "bai-6.1.1-sensitivity"
TITLE = "Paper stack corner test: sensitivity to the assumed bending and shear stiffness"
SOURCE = "Bai et al. (2020) §6.1.1 with the assumed data of materials.presets.paper_stack"
CELLS = {"coarse": 6, "default": 12, "fine": 20}
# (kinematics, label, B scale, K scale), in report order.
VARIANTS = [
    ("fibrous", "B, K as assumed", 1.0, 1.0),
    ("fibrous", "B / 2", 0.5, 1.0),
    ("fibrous", "B x 2", 2.0, 1.0),
    ("fibrous", "K / 10", 1.0, 0.1),
    ("fibrous", "K x 10", 1.0, 10.0),
    ("mindlin", "B, K as assumed", 1.0, 1.0),
    ("mindlin", "B / 2", 0.5, 1.0),
    ("mindlin", "B x 2", 2.0, 1.0),
]


@dataclass(frozen=True)
class SensitivityData:
    """Along side 1 (from the clamp): s, and per (kinematics, label) variant its mid-surface
    z and director angle (deg), in the order of ``VARIANTS``."""

    s: np.ndarray
    profiles: dict[tuple[str, str], tuple[np.ndarray, np.ndarray]]


def base_case(cells: int) -> dict:
    """The tables of the case file of bai-6.1.1 (cases/bai-6.1.1.toml) with ``cells`` cells
    along the specimen: its corner specimen (specimens.PAPER_STACK_SIZE), clamp, the gripped
    patch (specimens.PAPER_STACK_GRIP) lifted (specimens.CORNER_LIFT) as one with its
    directors held, gravity and the paper cases' Static solver (validation.paper)."""
    lx, ly = specimens.PAPER_STACK_SIZE
    return {
        "title": NAME,
        "mesh": {
            "corner": {"lx": lx, "ly": ly, "n": cells, "grip": list(specimens.PAPER_STACK_GRIP)}
        },
        "part": [
            {"element": "fibrous", "material": "paper_stack", "options": {"clamped": "clamp"}}
        ],  # fmt: skip
        "fix": [{"nodes": "clamp"}, {"nodes": "grip", "dofs": ["alpha", "beta"]}],
        "displace": [{"nodes": "grip", "uz": specimens.CORNER_LIFT[2]}],
        "gravity": {"acceleration": [0.0, 0.0, -specimens.GRAVITY]},
        "grip": [{"nodes": "grip", "stiffness": specimens.grip_stiffness(paper_stack())}],
        "solver": {
            "kind": "static",
            "path": "arc_length",
            "at_limit": "jump",
            "step_loads_first": True,
            "increments": INCREMENTS,
            "arc_chords": ARC_CHORDS,
            "max_iterations": 40,
            "max_cuts": 10,
        },  # fmt: skip
        "output": {"paths": {"side_1": {"y_max": 0.0}}},
    }


def sweep_workers() -> int:
    """The Dask workers of the sweep: one per numba thread this process may run (the report's
    workers set theirs to their share of the cores, validation/report.py; NUMBA_NUM_THREADS
    caps it), at most one per variant. With one worker per core instead, the sweep ran two
    processes beside the report's other worker at --jobs 2 on 2 cores: three busy processes
    on two cores."""
    import numba

    return max(1, min(len(VARIANTS), numba.get_num_threads()))


def compute(resolution: str) -> Outcome:
    """Sweep the variants of ``VARIANTS`` over the bai-6.1.1 case; check each."""
    base = paper_stack()
    b = base.bending.slope(np.array(0.0)).item()
    k = base.shear.slope(np.array(0.0)).item()
    workers = sweep_workers()
    started = time.perf_counter()
    table = sweep(
        base_case(CELLS[resolution]),
        {
            "kinematics": [kinematics for kinematics, *_ in VARIANTS],
            "part.0.material.bending": [b * b_scale for *_, b_scale, _ in VARIANTS],
            "part.0.material.shear": [k * k_scale for *_, k_scale in VARIANTS],
        },
        paired=True,
        workers=None if workers == 1 else workers,
        progress=False,
        in_process=workers == 1,
    )
    elapsed = time.perf_counter() - started
    checks, angles, profiles = [], {}, {}
    for (kinematics, label, *_), row, summary in zip(VARIANTS, table.rows, table.summaries):
        if summary is None:
            raise RuntimeError(f"{kinematics}, {label}: {row['error']}")
        side = summary["paths"]["side_1"]
        # The path runs from the corner to the clamp; the report draws it from the clamp.
        x = np.column_stack([side["x"], side["y"], side["z"]])[::-1]
        s = side["s"][-1] - side["s"][::-1]
        turned = np.radians(side["director_angle_deg"][::-1])
        angle = np.degrees(np.arctan2(np.sin(turned), -np.cos(turned)))
        run_ = np.linalg.norm(np.gradient(x[:, :2], axis=0), axis=1)
        slope = np.degrees(np.arctan2(np.abs(np.gradient(x[:, 2])), run_)).max()
        angles[(kinematics, label)] = (angle, slope)
        profiles[(kinematics, label)] = (x[:, 2], angle)
    for (kinematics, label), (angle, slope) in angles.items():
        # Tilt of the directors from the vertical against the largest mid-surface slope:
        # ~1 for a standard shell (director = normal), ~0 for Bai's fibrous shell.
        ratio = float(np.abs(angle - 90.0).max() / slope)
        if kinematics == "fibrous":
            checks.append(
                check(
                    f"fibrous, {label}: director tilt / largest slope (< 0.2)",
                    0.0,
                    ratio,
                    0.2,
                    relative=False,
                    source="the formulation's claim (Bai §6.1.1: the directors remain almost "
                    "parallel); the bound 0.2 is this project's",
                )
            )
        else:
            # Same B, same mesh: the Mindlin directors turn with the surface, the fibrous
            # ones do not.
            gap = float(np.abs(angle - angles[("fibrous", label)][0]).max())
            checks.append(
                bound(
                    f"Mindlin vs fibrous, {label}: largest director angle difference (deg, > 5)",
                    5.0,
                    gap,
                    at_least=True,
                    source="the other kinematics, same B, same mesh; the claim: Bai §6.1.1, "
                    "fibrous directors differ from standard shell normals",
                )
            )
    return Outcome(
        converged=not table.failed,
        wall_time_s=float(sum(row["wall_time_s"] for row in table.rows)),
        steps=int(sum(row["steps"] for row in table.rows)),
        solver="Static along the arc length (load steps past a limit point), each variant",
        parameters={
            "triangles": len(
                specimens.corner(
                    *specimens.PAPER_STACK_SIZE, CELLS[resolution], grip=specimens.PAPER_STACK_GRIP
                ).mesh.triangles
            ),
            "B assumed (N mm)": b,
            "K assumed (N/mm)": k,
            "variants": "B x 0.5, 2; K x 0.1, 10",
            "run as": (
                f"a sweep of {len(VARIANTS)} runs in the report's process"
                if workers == 1
                else f"a sweep of {len(VARIANTS)} Dask tasks on {workers} worker processes"
            )
            + f" (fibreshell.sweep): {elapsed:.1f} s elapsed",
        },
        checks=checks,
        data=SensitivityData(s=s, profiles=profiles),
    )


def render(data: SensitivityData, out_dir: Path) -> list[Figure]:
    """Mid-surface and director angle along side 1, every variant: one row per kinematics, one
    colour per variant (the same in both rows), each row with its own legend."""
    labels = list(dict.fromkeys(label for _, label in data.profiles))
    colour = {label: f"C{i}" for i, label in enumerate(labels)}
    rows = list(dict.fromkeys(kinematics for kinematics, _ in data.profiles))
    fig, axes = plt.subplots(
        len(rows), 2, figsize=(12, 3.6 * len(rows)), squeeze=False, constrained_layout=True
    )
    for (kinematics, label), (z, angle) in data.profiles.items():
        row = axes[rows.index(kinematics)]
        row[0].plot(data.s, z, marker="o", ms=2, color=colour[label], label=label)
        row[1].plot(data.s, angle, marker="o", ms=2, color=colour[label], label=label)
    for kinematics, row in zip(rows, axes):
        row[0].set(xlabel="s along side 1 (mm)", ylabel="mid-surface z (mm)",
                   title=f"{kinematics}: mid-surface")  # fmt: skip
        row[1].set(xlabel="s along side 1 (mm)", ylabel="director angle to horizontal (deg)",
                   title=f"{kinematics}: director")  # fmt: skip
        for ax in row:
            ax.grid(True, alpha=0.3)
        row[1].legend(fontsize="small", title="variant")
    figure = f"{NAME}.png"
    fig.suptitle(
        "bai-6.1.1, side 1: each kinematics for the varied B and K (same colour, same variant)"
    )
    save(fig, out_dir / figure, dpi=100)
    plt.close(fig)
    return [
        Figure(
            figure,
            "The paper stack corner test (bai-6.1.1) with the bending stiffness B and the "
            "in-plane shear K the paper does not give halved, doubled or scaled by 10: the "
            "mid-surface and the director angle along side 1, one row per kinematics (fibrous "
            "above, Mindlin below), one colour per variant. Look at the director panels: "
            "whatever the variant, the fibrous directors stay near vertical while the Mindlin "
            "ones follow the normal.",
        )
    ]


CASE = Case(
    name=NAME,
    title=TITLE,
    source=SOURCE,
    description=__doc__,
    group="sensitivity",
    order=10,
    compute=compute,
    render=render,
)
