"""A series' timesteps keep rising, so that ParaView (whose PVD and XDMF readers sort the
frames by timestep) plays the frames in the order they were computed: a frame's timestep is
its time where the times rise (explicit: s; relaxation and Static under load control: the
load factor), else its index, and always its index along a Static arc-length path, whose
load factor falls past a limit point. Each VTU frame keeps its time and load factor as field
data.

Before, the von Mises truss's arc-length path (tests/test_static.py) wrote its load factors
as timesteps: 0 ... 0.706, 0.695 ... -0.374, -0.373 ... 1.0, which ParaView sorted into a mix
of the three branches."""

from xml.etree import ElementTree

import meshio
import numpy as np
import pytest
from test_static import _von_mises_truss

from femcore.results import series_timesteps
from solvers import Static


def pvd_entries(path):
    return [
        (float(entry.get("timestep")), path.parent / entry.get("file"))
        for entry in ElementTree.parse(path).getroot().iter("DataSet")
    ]


def test_an_arc_length_series_plays_in_the_order_of_the_path(tmp_path):
    model, *_ = _von_mises_truss()
    result = Static(increments=12, path="arc_length", output=tmp_path / "arc.pvd").solve(model)
    lam = result.load_factors
    assert np.diff(lam).min() < 0.0 and lam.min() < 0.0  # the path does fold back
    for series in (tmp_path / "arc.pvd", result.write(tmp_path / "written.pvd")):
        entries = pvd_entries(series)
        assert [step for step, _ in entries] == list(range(len(lam)))
        frames = [meshio.read(file) for _, file in entries]
        assert [f.field_data["load_factor"][0] for f in frames] == list(lam)
        assert [f.field_data["time"][0] for f in frames] == list(result.times)
    result.write(tmp_path / "arc.xdmf")
    with meshio.xdmf.TimeSeriesReader(tmp_path / "arc.xdmf") as reader:
        reader.read_points_cells()
        times = [reader.read_data(k)[0] for k in range(reader.num_steps)]
    assert times == list(range(len(lam)))


def test_a_load_controlled_series_keeps_the_load_factor_as_its_timestep(tmp_path):
    model, *_ = _von_mises_truss()
    with pytest.warns(UserWarning, match="load control jumped"):  # (the truss snaps)
        result = Static(increments=12, output=tmp_path / "load.pvd").solve(model)
    lam = list(result.load_factors)
    assert lam == pytest.approx(np.linspace(0.0, 1.0, 13), abs=1e-12)
    for series in (tmp_path / "load.pvd", result.write(tmp_path / "written.pvd")):
        entries = pvd_entries(series)
        assert [step for step, _ in entries] == lam
        assert meshio.read(entries[6][1]).field_data["load_factor"][0] == lam[6]


@pytest.mark.parametrize(
    "times, by_index, steps",
    [
        ([0.0, 0.1, 0.3], False, [0.0, 0.1, 0.3]),
        ([0.0, 0.1, 0.3], True, [0.0, 1.0, 2.0]),
        ([0.0, 0.7, 0.6, 1.0], False, [0.0, 1.0, 2.0, 3.0]),  # falls: indices
        ([0.0, 0.5, 0.5], False, [0.0, 1.0, 2.0]),  # repeats: ParaView would merge them
    ],
)
def test_series_timesteps_are_the_times_while_they_rise_else_the_indices(times, by_index, steps):
    assert series_timesteps(times, by_index) == steps
