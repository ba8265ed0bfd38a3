"""Figures for the report (matplotlib without a display)."""

from __future__ import annotations

from contextlib import contextmanager
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt


@contextmanager
def figure(path: Path, xlabel: str, ylabel: str, size=(6.4, 3.6)):
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
