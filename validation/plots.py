"""Figures for the report (matplotlib without a display)."""

from __future__ import annotations

from collections.abc import Iterator, Sequence
from contextlib import contextmanager
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt

__all__ = ["figure", "mesh_convergence", "plt"]


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
        fig.savefig(path, dpi=110)
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
