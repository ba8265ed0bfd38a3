"""The report's figure helpers (validation.plots) and the figures drawn with them: ``save``
writes the pixels matplotlib's own ``savefig`` writes, with one draw instead of two; the
directors and fibres drawn as NaN-broken lines are the segments and polylines drawn before as
one line each."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest
from matplotlib.image import imread

from validation import plots
from validation.plots import plt, save


def _pieces(line) -> list[np.ndarray]:
    """The pieces of a NaN-broken 2D line, each (m, 2)."""
    data = np.column_stack(line.get_data()).astype(float)
    pieces = np.split(data, np.flatnonzero(np.isnan(data).any(axis=1)))
    return [p[~np.isnan(p).any(axis=1)] for p in pieces if (~np.isnan(p).any(axis=1)).any()]


def _constrained(three_d: bool = False):
    """A figure laid out by the constrained engine: wrapped titles, a shared legend, equal
    aspect (adjusted by the data limits), and a 3D panel when asked."""
    fig = plt.figure(figsize=(6.0, 4.0), layout="constrained")
    ax = fig.add_subplot(1, 2, 1)
    s = np.linspace(0.0, 10.0, 40)
    ax.plot(s, np.sin(s), "o-", ms=3, label="sine")
    ax.plot(*plots.segments(np.column_stack([s, 0 * s]), np.column_stack([s, np.cos(s)])).T, "k")
    ax.set(xlabel="s (mm)", ylabel="z (mm)", title="a title long enough\nto take two lines")
    ax.set_aspect("equal", adjustable="datalim")
    other = fig.add_subplot(1, 2, 2, projection="3d" if three_d else None)
    other.plot(s, s**2, s) if three_d else other.plot(s, s**2)
    other.set_title("(b) the other panel")
    fig.legend(loc="outside lower center")
    fig.suptitle("a figure saved twice")
    return fig


@pytest.mark.parametrize(
    "three_d, options",
    [(False, {}), (False, {"bbox_inches": "tight", "pad_inches": 0.1}),
     (True, {"bbox_inches": "tight", "pad_inches": 0.15}), (True, {})],
)  # fmt: skip
def test_save_writes_the_pixels_savefig_writes(tmp_path, three_d, options):
    # The reference is matplotlib's savefig of the same figure (layout engine, tight box).
    reference = _constrained(three_d)
    reference.savefig(tmp_path / "savefig.png", dpi=110, **options)
    plt.close(reference)
    fig = _constrained(three_d)
    save(fig, tmp_path / "save.png", dpi=110, **options)
    plt.close(fig)
    expected, drawn = imread(tmp_path / "savefig.png"), imread(tmp_path / "save.png")
    assert drawn.shape == expected.shape
    assert np.array_equal(drawn, expected)


def test_the_heavy_cantilever_draws_each_director_through_the_thickness(tmp_path, monkeypatch):
    from validation.cases import fibrous_heavy_cantilever as case

    n = 7
    angle = np.linspace(0.0, 0.6, n)
    positions = np.column_stack([np.linspace(0.0, 90.0, n), 0 * angle, -30 * angle**2])
    directors = np.column_stack([np.sin(angle), 0 * angle, np.cos(angle)])
    thickness = np.linspace(4.0, 5.0, n)
    data = case.HeavyCantileverData(
        reference={"x": positions[:, 0], "z": positions[:, 2]}, positions=positions,
        directors=directors, thickness=thickness, cells=6,
        result=SimpleNamespace(write=lambda path: None),
    )  # fmt: skip
    kept = []
    monkeypatch.setattr(plots.plt, "close", kept.append)
    case.render(data, tmp_path)
    ax = kept[0].axes[0]
    lines = [line for line in ax.get_lines() if line.get_label() == "directors x nodal thickness"]
    assert len(lines) == 1 and len(ax.get_lines()) == 4
    ends = np.array(_pieces(lines[0]))
    half = 0.5 * thickness[:, None] * directors[:, [0, 2]]
    np.testing.assert_allclose(ends[:, 0], positions[:, [0, 2]] - half, rtol=0, atol=1e-12)
    np.testing.assert_allclose(ends[:, 1], positions[:, [0, 2]] + half, rtol=0, atol=1e-12)
    assert "directors x nodal thickness" in [t.get_text() for t in ax.get_legend().get_texts()]


def test_the_deck_of_cards_draws_both_runs_directors_and_the_closed_form(tmp_path, monkeypatch):
    from validation.cases import fibrous_deck_of_cards as case

    def run(cells: int, lean: float):
        theta = np.linspace(0.0, case.BEND, cells + 1)
        radius = 100.0
        positions = np.column_stack(
            [radius * np.sin(theta), 0 * theta, radius * (1 - np.cos(theta))]
        )
        tilt = lean * np.arctan(theta)
        directors = np.column_stack([-np.sin(theta + tilt), 0 * theta, np.cos(theta + tilt)])
        return case.DeckRun(
            cells=cells, thickness_option="nodal", rotation=theta, tilt=tilt,
            thickness=case.THICKNESS * np.hypot(1.0, theta), positions=positions,
            directors=directors, result=SimpleNamespace(write=lambda path: None),
        )  # fmt: skip

    runs = [run(4, 1.0), run(8, 1.0), run(16, 1.0)]
    data = case.DeckData(runs=runs, element=run(8, 0.0))
    kept = []
    monkeypatch.setattr(plots.plt, "close", kept.append)
    case.render(data, tmp_path)
    ax = kept[0].axes[0]
    labelled = {line.get_label(): line for line in ax.get_lines()}
    assert len(ax.get_lines()) == 5  # two sides, their directors, the closed form's
    for label, drawn in (("nodal h_m (default)", runs[1]), ("Bai Eq. 15", data.element)):
        ends = np.array(_pieces(labelled[f"directors, {label} (x8)"]))
        half = 0.5 * 8.0 * drawn.thickness[:, None] * drawn.directors[:, [0, 2]]
        centre = drawn.positions[:, [0, 2]]
        np.testing.assert_allclose(ends[:, 0], centre - half, rtol=0, atol=1e-12)
        np.testing.assert_allclose(ends[:, 1], centre + half, rtol=0, atol=1e-12)
    theta = runs[1].rotation
    exact = np.column_stack([-np.sin(theta), np.cos(theta)]) * np.cos(np.arctan(theta))[:, None]
    exact += np.column_stack([np.cos(theta), np.sin(theta)]) * np.sin(np.arctan(theta))[:, None]
    half = 0.5 * 8.0 * case.THICKNESS * np.hypot(1.0, theta)[:, None] * exact
    ends = np.array(_pieces(labelled["atan(theta) from the normal"]))
    centre = runs[1].positions[:, [0, 2]]
    np.testing.assert_allclose(ends[:, 0], centre - half, rtol=0, atol=1e-12)
    np.testing.assert_allclose(ends[:, 1], centre + half, rtol=0, atol=1e-12)
    assert labelled["atan(theta) from the normal"].get_linestyle() == ":"


def test_the_hemisphere_fibres_are_every_step_th_row_and_column_of_the_grid(tmp_path, monkeypatch):
    from femcore import Mesh
    from validation.cases import hemisphere_forming as case

    cells = 40  # a step of 2: every other fibre
    mesh = Mesh.rectangle(200.0, 200.0, nx=cells, ny=cells, origin=(-100.0, -100.0, 0.0))
    shear = np.zeros(len(mesh.triangles))
    moved = mesh.points * [0.9, 0.8, 1.0] + [0.0, 0.0, 5.0]
    run = SimpleNamespace(
        positions=np.vstack([moved, [[0.0, 0.0, 1.0]]]),  # and the holder's node
        frames=[SimpleNamespace(time=t, tool_forces=np.zeros((3, 3))) for t in (0.0, 0.3)],
        write=lambda path: None,
        # what the force figure's caption says of the run's pace (quasi_static_words)
        info={"quasi_static": {"kinetic_over_work_largest": 0.01, "exceeded_share": 0.0}},
        energies={"damping": np.array([0.0, 0.01]), "external_work": np.array([0.0, 1.0])},
    )
    data = case.HemisphereData(
        mesh=mesh, runs={"fibrous": run, "mindlin": run},
        shear={"fibrous": shear, "mindlin": shear}, net_shear=shear + 0.1,
        compared=np.ones(len(shear), bool), cells=cells,
    )  # fmt: skip
    kept = []
    monkeypatch.setattr(plt, "close", kept.append)
    case.render(data, tmp_path)
    fibres = next(fig for fig in kept if any("from above" in ax.get_title() for ax in fig.axes))
    grid = moved.reshape(cells + 1, cells + 1, 3)[..., :2]
    for ax in fibres.axes:
        by_colour = {line.get_color(): line for line in ax.get_lines()}
        warp, weft = _pieces(by_colour["C0"]), _pieces(by_colour["C3"])
        np.testing.assert_array_equal(np.array(warp), grid[::2])
        np.testing.assert_array_equal(np.array(weft), grid[:, ::2].transpose(1, 0, 2))


def test_save_writes_other_formats_than_png_too(tmp_path):
    """``save`` gives the PNG encoder its compression level alone: a PDF (whose writer takes
    no such option) is written as savefig writes it."""
    fig, ax = plt.subplots(layout="constrained")
    ax.plot([0, 1], [0, 1])
    save(fig, tmp_path / "line.pdf", dpi=100, bbox_inches="tight")
    plt.close(fig)
    assert (tmp_path / "line.pdf").read_bytes().startswith(b"%PDF")
