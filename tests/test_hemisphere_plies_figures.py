"""The two-ply hemisphere's figures (validation/studies/hemisphere_plies_run.py ``render``)
read on an 800-px page, and their captions say what the runs drawn show."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest
from matplotlib.image import imread

from femcore import Mesh
from validation.studies import hemisphere_plies_run as plies


def _data(kinematics: tuple[str, ...], rotation: float) -> plies.PliesData:
    """Both layups on a 4 x 4 blank, a run per layup and kinematics at the first holder
    force: shears and slips that vary over the blank, KE / W rising to 0.05, the Mindlin
    runs' rotational part to ``rotation`` (the fibrous runs' to 1e-7 of the work)."""
    mesh = Mesh.rectangle(200.0, 200.0, nx=4, ny=4, origin=(-100.0, -100.0, 0.0))
    cells = np.arange(len(mesh.triangles))
    nodes = np.arange(mesh.n_nodes)
    time = np.linspace(0.0, 0.4, 41)
    work = time**2
    layups, runs, shear, net = {}, {}, {}, {}
    for name, angles in plies.LAYUPS.items():
        for kind in kinematics:
            key = plies.run_key(name, kind, plies.HOLDER_FORCES[0])
            layups[key] = SimpleNamespace(
                mesh=mesh, count=2, angles=angles, ply_cells=[cells, cells],
                ply_nodes=[nodes, nodes],
            )  # fmt: skip
            slip = {"ply_slip": np.linspace(0.0, 2.0, mesh.n_nodes)}
            energies = {
                "time": time,
                "external_work": work,
                "kinetic": 0.05 * work,
                "kinetic_rotational": (rotation if kind == "mindlin" else 1e-7) * work,
            }
            runs[key] = SimpleNamespace(
                frames=[SimpleNamespace(fields={"point": slip})], energies=energies
            )
            shear[key] = [np.linspace(-0.5, 0.5, len(cells))] * 2
            net[key] = [np.linspace(-0.6, 0.6, len(cells))] * 2
    in_die = {key: [np.ones(len(cells), bool)] * 2 for key in runs}
    return plies.PliesData(layups, runs, shear, net, in_die, 4)


def test_the_layup_figures_are_two_rows_that_read_on_an_800_px_page(tmp_path):
    # Two rows (a ply each) of three, 990 px wide: shown at about 780 px on an 800-px page
    # their 10-pt text still reads as 9 pt (a row of five was 2,000 x 420 px, its text 6-7
    # px on the report's page).
    drawn = plies.render(_data(("fibrous",), 0.0), tmp_path)
    layups = [f.file for f in drawn if not f.file.endswith("-kinetic.png")]
    assert len(layups) == len(plies.LAYUPS)
    sizes = {
        plies.LAYUP_FIGURE_SIZE: layups,
        plies.KINETIC_FIGURE_SIZE: [f"{plies.NAME}-kinetic.png"],
    }
    for size, files in sizes.items():
        for file in files:
            height, width = imread(tmp_path / file).shape[:2]
            assert (width, height) == (
                round(size[0] * plies.FIGURE_DPI),
                round(size[1] * plies.FIGURE_DPI),
            )
            assert width <= 1000 and height < 1.2 * width
    smallest_pt = 10  # ticks, titles, axis labels and legends
    assert (
        smallest_pt / 72 * 780
    )  # in points at 72 per inch; px at 96 / plies.LAYUP_FIGURE_SIZE[0] >= 12


@pytest.mark.parametrize(
    ("kinematics", "rotation"), [(("fibrous",), 0.0), (("fibrous", "mindlin"), 0.01)]
)
def test_the_kinetic_figures_caption_names_the_runs_and_curves_it_draws(
    tmp_path, kinematics, rotation
):
    # The coarse report runs the fibrous stacks alone, whose rotational part stays below a
    # thousandth of the work (1.7e-7 and 7.6e-7): its caption spoke of dotted rotation
    # curves and the Mindlin shell's rotary inertia, which it did not draw.
    caption = plies.render(_data(kinematics, rotation), tmp_path)[-1].caption
    for kind in ("fibrous", "mindlin"):
        assert (f"[0/45] {kind} 20 N" in caption) is (kind in kinematics)
    assert ("dotted" in caption) is (rotation > 1e-3)
    assert ("Mindlin" in caption) is ("mindlin" in kinematics)
