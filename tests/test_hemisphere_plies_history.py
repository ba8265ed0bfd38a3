"""The two-ply hemisphere's holder measures from a run's history records
(validation/studies/hemisphere_plies_run.py): read from the .csv or from the records read once
(``read_history``), the same numbers, against closed forms on made-up records."""

from __future__ import annotations

import numpy as np
import pytest

from validation.studies.hemisphere_plies_run import (
    holder_force_last_tenth,
    holder_inertia_last_tenth,
    read_history,
)
from validation.studies.hemisphere_plies_setup import DURATION

RECORDS = 201  # every 0.0005 s
FORCE, SLOPE = 20.0, 30.0  # N, N/s: the holder's reaction a + b t
ACCELERATION = 400.0  # mm/s^2: its travel a t^2 / 2


@pytest.fixture
def history(tmp_path):
    """A HistoryWriter-like .csv (a header of names, a row per record) of the holder, the
    third tool, with a reaction linear in time and a travel of constant acceleration."""
    times = np.linspace(0.0, DURATION, RECORDS)
    columns = {
        "time": times,
        "kinetic": np.zeros_like(times),
        "tool3_force_z": FORCE + SLOPE * times,
        "tool3_displacement_z": 0.5 * ACCELERATION * times**2,
    }
    path = tmp_path / "history.csv"
    np.savetxt(path, np.stack(list(columns.values()), axis=1), delimiter=",",
               header=",".join(columns), comments="", fmt="%.17g")  # fmt: skip
    return path


def test_the_records_read_once_give_the_file_s_numbers(history):
    """The measures of the records ``read_history`` made equal those of the file to the bit,
    and an array handed to ``read_history`` comes back as it is (not read again)."""
    table = read_history(history)
    assert read_history(table) is table
    assert holder_force_last_tenth(table) == holder_force_last_tenth(history)
    mass = 1e-5
    assert holder_inertia_last_tenth(table, mass) == holder_inertia_last_tenth(history, mass)


def test_the_holder_measures_against_closed_forms(history):
    """Over the records from t0, the first at or after 0.9 T (0.9 * 0.1 rounds above 0.09:
    t0 = 0.0905 s here), to T: the trapezoids' mean of a + b t is a + b (t0 + T) / 2, exact
    for a line (to 1e-12 relative: the .csv's 17 digits and the sums' round-off); m dv over
    the span of a travel a t^2 / 2 by central differences (exact inside, the last record's
    one-sided difference a (T - h / 2)) is m a (T - h / 2 - t0) / (T - t0), to 1e-9
    relative (differences of 17-digit travels over h = 5e-4 s)."""
    table = read_history(history)
    times = np.linspace(0.0, DURATION, RECORDS)
    t0 = times[times >= 0.9 * DURATION][0]
    assert holder_force_last_tenth(table) == pytest.approx(
        FORCE + 0.5 * SLOPE * (t0 + DURATION), rel=1e-12
    )
    mass, h = 1e-5, DURATION / (RECORDS - 1)
    expected = mass * ACCELERATION * (DURATION - 0.5 * h - t0) / (DURATION - t0)
    assert holder_inertia_last_tenth(table, mass) == pytest.approx(expected, rel=1e-9)
