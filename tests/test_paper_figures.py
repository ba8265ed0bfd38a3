"""The paper cases' figures read on an 800-px page: 9 to 10 in wide at 100-110 dpi (at most
1,100 px), so that shown at about 780 px their 10-pt text still reads as 9 pt; the 3D view
labels z only in its left column, where no panel hides the label."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest
from matplotlib.image import imread

from femcore import Mesh
from fibreshell.calibration import Calibration
from materials.presets import g986_stack
from validation.paper import figures
from validation.paper.kinematics import KINEMATICS
from validation.records import SideProfile

LENGTH, WIDTH = 120.0, 30.0


def _bent_strip(sides: int):
    """A strip bent into an arc, as each kinematics' result, with one or two filmed sides."""
    mesh = Mesh.rectangle(LENGTH, WIDTH, nx=6, ny=2)
    p = mesh.points
    angle = p[:, 0] / LENGTH * np.pi / 2
    radius = 2 * LENGTH / np.pi
    positions = np.column_stack([radius * np.sin(angle), p[:, 1], radius * (np.cos(angle) - 1)])
    directors = np.column_stack([np.sin(angle), 0 * angle, np.cos(angle)])
    fabric = g986_stack()
    h = fabric.thickness
    result = SimpleNamespace(positions=positions, directors=directors, thickness=np.full(len(p), h))
    edges = {"side_1": np.flatnonzero(np.abs(p[:, 1]) < 1e-9)}
    if sides == 2:
        edges["side_2"] = np.flatnonzero(np.abs(p[:, 1] - WIDTH) < 1e-9)
    specimen = SimpleNamespace(mesh=mesh, sides={k: (n, p[n, 0]) for k, n in edges.items()})
    case = SimpleNamespace(
        name="strip", title="a bent strip", source="§0", fabric=fabric, calibration=Calibration()
    )
    profile = {
        side: SideProfile(
            s=p[n, 0],
            midsurface=positions[n],
            director_angle_deg=90 - np.degrees(angle[n]),
            thickness=np.full(len(n), h),
            rotation_deg=-np.degrees(angle[n]),
            side_tilt_deg=0 * angle[n],
            director_tilt_deg=0 * angle[n],
        )  # fmt: skip
        for side, n in edges.items()
    }
    return case, specimen, {k: result for k in KINEMATICS}, {k: profile for k in KINEMATICS}


@pytest.mark.parametrize("sides", [1, 2])
def test_the_paper_figures_are_at_most_1100_px_wide_and_at_least_900(tmp_path, sides):
    case, specimen, results, profiles = _bent_strip(sides)
    drawn = [
        figures.side_figure(case, profiles, tmp_path),
        figures.side_elevation(case, profiles, tmp_path),
        figures.view_3d(case, specimen, results, tmp_path),
    ]
    for figure in drawn:
        height, width = imread(tmp_path / figure.file).shape[:2]
        # wider than the report's half-width figures (800 px), narrower than its page
        assert 800 < width <= 1100, (figure.file, width)
        assert height < 1.2 * width, (figure.file, height)


def test_the_3d_view_labels_z_in_its_left_column_only(tmp_path, monkeypatch):
    case, specimen, results, _ = _bent_strip(2)
    drawn = []
    monkeypatch.setattr(figures.plt, "close", drawn.append)
    figures.view_3d(case, specimen, results, tmp_path)
    panels = [ax for ax in drawn[0].axes if ax.name == "3d"]
    assert [ax.get_zlabel() for ax in panels] == ["z (mm)", "", "z (mm)"]
    assert all(ax.get_xlabel() == "x (mm)" and ax.get_ylabel() == "y (mm)" for ax in panels)
