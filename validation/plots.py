"""Figures for the report (matplotlib without a display)."""

from __future__ import annotations

from collections.abc import Iterator, Sequence
from contextlib import contextmanager
from pathlib import Path

import matplotlib
import numpy as np

matplotlib.use("Agg")
import matplotlib.figure
import matplotlib.pyplot as plt

__all__ = ["PNG_COMPRESSION", "figure", "mesh_convergence", "plt", "save", "segments"]

# zlib's level for the figures' PNGs: 3 encodes a report figure in about 60 % of the time of
# PIL's default (6) into a file a few per cent smaller (benchmarks/report_overhead.py).
PNG_COMPRESSION = 3


def save(fig: matplotlib.figure.Figure, path: Path, dpi: float, **kwargs) -> None:
    """Write ``fig`` as the PNG ``path`` at ``dpi`` (``savefig``'s other options in
    ``kwargs``), the same pixels as ``fig.savefig(path, dpi=dpi, **kwargs)``, cheaper.

    savefig draws a figure with a layout engine (constrained layout) or a tight box
    (``bbox_inches="tight"``) twice: once without output, to run the layout and measure the
    box, then to the file. Here the layout runs once at ``dpi`` and the box is measured from
    it, and the figure is saved without its engine, with that box: one draw. A figure with
    3D axes and a tight box is saved as it is (its z labels are placed by its drawing, which
    the box needs). The PNG is encoded at zlib level ``PNG_COMPRESSION``.
    """
    engine = fig.get_layout_engine()
    tight = kwargs.get("bbox_inches") == "tight"
    flat = not any(ax.name == "3d" for ax in fig.axes)
    if engine is not None and (flat or not tight):
        fig.set_dpi(dpi)  # the layout at the saved size of the text, as savefig computes it
        engine.execute(fig)
        fig.set_layout_engine(None)
        if tight:
            pad = kwargs.pop("pad_inches", None)
            pad = matplotlib.rcParams["savefig.pad_inches"] if pad in (None, "layout") else pad
            box = fig.get_tightbbox(fig.canvas.get_renderer())  # inches
            kwargs["bbox_inches"] = box.padded(pad)
    if Path(path).suffix.lower() == ".png":  # the PNG encoder's level (other formats have none)
        kwargs.setdefault("pil_kwargs", {"compress_level": PNG_COMPRESSION})
    fig.savefig(path, dpi=dpi, **kwargs)


def segments(starts: np.ndarray, ends: np.ndarray) -> np.ndarray:
    """The straight segments from ``starts[k]`` to ``ends[k]`` as one polyline broken by a
    row of NaN after each segment, to draw as a single line: a line per segment made the
    figures' layout and drawing visit hundreds of artists, where one line draws the same
    strokes (matplotlib starts a new piece of a line after a NaN).

    Parameters
    ----------
    starts, ends : (k, d) float
        The segments' ends (any unit, d coordinates).

    Returns
    -------
    (3 k, d) float
        ``starts[0], ends[0], nan, starts[1], ends[1], nan, ...``.
    """
    starts, ends = np.asarray(starts, dtype=float), np.asarray(ends, dtype=float)
    if starts.ndim != 2 or starts.shape != ends.shape:
        raise ValueError(
            f"segments: starts and ends must be (k, d) arrays of one shape, got "
            f"{starts.shape} and {ends.shape}"
        )
    pieces = np.full((len(starts), 3, starts.shape[1]), np.nan)
    pieces[:, 0], pieces[:, 1] = starts, ends
    return pieces.reshape(-1, starts.shape[1])


@contextmanager
def figure(
    path: Path, xlabel: str, ylabel: str, size: tuple[float, float] = (6.4, 3.6)
) -> Iterator[plt.Axes]:
    """Yield one axes; on exit add labels, grid and legend, save as PNG and close."""
    fig, ax = plt.subplots(figsize=size, constrained_layout=True)
    try:
        yield ax
        ax.set_xlabel(xlabel)
        ax.set_ylabel(ylabel)
        ax.grid(True, alpha=0.3)
        if ax.get_legend_handles_labels()[0]:
            ax.legend(fontsize="small")
        save(fig, path, dpi=110)
    finally:
        plt.close(fig)


def mesh_convergence(
    path: Path,
    meshes: Sequence[int],
    ratio: Sequence[float],
    tolerance: float,
    *,
    xlabel: str,
    ylabel: str,
    label: str,
    ylim: tuple[float, float],
) -> None:
    """Value / reference against cells per side (log 2 axis), with the reference line and the
    tolerance band of a published benchmark (MacNeal & Harder 1985)."""
    with figure(path, xlabel, ylabel) as ax:
        ax.axhline(1.0, color="0.3", label="MacNeal & Harder (1985)")
        ax.axhspan(1 - tolerance, 1 + tolerance, color="0.85", label=f"±{tolerance:.0%}")
        ax.plot(meshes, ratio, "o-", label=label)
        ax.set_xscale("log", base=2)
        ax.set_xticks(meshes, [str(n) for n in meshes])
        ax.set_ylim(*ylim)
