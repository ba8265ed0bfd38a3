"""The hemisphere forming case's draw-in range: the closed forms of the paths a centre-line
fibre can take through the tools' gap at the end of the stroke, against a numerical shortest
path (a string pulled taut between the tools)."""

import math

import numpy as np
import pytest

from validation.cases import hemisphere_forming as case


def _pulled_string(points: int, sweeps: int) -> float:
    """The length (mm) of a polyline from the pole on the punch side of the clearance to the
    flange's start, pulled taut: each interior point moved to the middle of its neighbours
    and pushed back out of the tools (the punch, the die's bowl and round, the holder's
    plane), refined by halving the segments. Its chords cut the tools a little, so it
    converges from below, at the rate of the chords' shortfall (segment squared)."""
    punch = case.PUNCH + 0.5 * case.THICKNESS
    bowl = case.DIE - 0.5 * case.THICKNESS
    round_ = case.DIE_RIM + 0.5 * case.THICKNESS
    start = case.flange_start()
    centre = np.array([start, -case.DIE_RIM])
    turn = math.atan2(start, case.DIE_RIM)  # the polar angle where the round begins
    level = 0.5 * case.THICKNESS

    def push_out(p: np.ndarray) -> np.ndarray:
        r = np.linalg.norm(p, axis=1, keepdims=True)
        p = np.where(r < punch, p * punch / r, p)
        r = np.linalg.norm(p, axis=1, keepdims=True)
        polar = np.arctan2(p[:, 0], -p[:, 1])[:, None]
        p = np.where((polar < turn) & (r > bowl), p * bowl / r, p)
        off = p - centre
        d = np.linalg.norm(off, axis=1, keepdims=True)
        p = np.where((polar >= turn) & (d < round_), centre + off * round_ / d, p)
        p[:, 1] = np.minimum(p[:, 1], level)
        return p

    # Start on the die's side (the cornered path's sphere): the string must find the punch.
    polar = np.linspace(0.0, 0.5 * math.pi, 20)
    p = np.column_stack([bowl * np.sin(polar), -bowl * np.cos(polar)])
    p[0], p[-1] = (0.0, -punch), (start, level)
    while True:
        for _ in range(sweeps * len(p)):
            p[1:-1] = push_out(0.5 * (p[:-2] + p[2:]))
        if len(p) >= points:
            return float(np.linalg.norm(np.diff(p, axis=0), axis=1).sum())
        finer = np.empty((2 * len(p) - 1, 2))
        finer[::2], finer[1::2] = p, push_out(0.5 * (p[:-1] + p[1:]))
        p = finer


def test_the_taut_fibres_closed_form_is_the_shortest_path_through_the_tools_gap():
    # 305 points (0.3-mm segments): the pulled string is 5e-4 mm short of its limit (measured
    # 24.97298 at 305, 24.97336 at 609, 24.97345 at 1217 points against 24.97348); 1e-3 mm
    # is a tenth of a percent of the range's width and far below its 1 % strain allowance.
    draw_in, on_punch, on_round = case.taut_centre_line_draw_in()
    pulled = _pulled_string(300, sweeps=20) - case.flange_start()
    assert pulled == pytest.approx(draw_in, abs=1e-3)
    assert pulled <= draw_in  # the chords cut the tools: a polyline is never longer
    # The fibre lying on the die's side of the clearance is longer by the clearance's arc.
    assert case.centre_line_draw_in() > draw_in + 0.3
    assert on_punch + on_round < draw_in + case.flange_start()


def test_the_draw_in_range_runs_from_the_taut_fibre_to_the_cornered_one():
    cornered, path = case.cornered_centre_line_draw_in()
    # The sharp die's corner, on the die's side of the clearance: (DIE - h / 2)(pi / 2 - 1)
    # plus the little rise to the flange's level over the round's width.
    bowl = case.DIE - 0.5 * case.THICKNESS
    assert cornered == pytest.approx(bowl * (0.5 * math.pi - 1.0), abs=2e-3)
    assert path - case.flange_start() == pytest.approx(cornered)
    low, high = case.centre_line_draw_in_range(20)
    taut = case.taut_centre_line_draw_in()[0]
    assert low < taut < case.centre_line_draw_in() < cornered < high
    # Finer cells cut the round less: the range's low end rises towards the taut fibre's
    # stretched by the strain allowance alone.
    lows = [case.centre_line_draw_in_range(n)[0] for n in (12, 20, 32, 1000)]
    assert lows == sorted(lows)
    stretched = taut - case.FIBRE_STRAIN * (taut + case.flange_start())
    assert lows[-1] == pytest.approx(stretched, abs=1e-3)


def test_a_chord_through_a_round_covers_more_of_it_than_its_length():
    # Three chords of 10 mm inscribed in a circle of 10.15 mm span 3 theta of arc.
    theta = 2.0 * math.asin(5.0 / 10.15)
    arc = 3.0 * 10.15 * theta
    assert case.chord_shortfall(10.15, arc, 10.0) == pytest.approx(arc - 30.0, rel=1e-12)
    assert case.chord_shortfall(10.15, arc, 1e-4) == pytest.approx(0.0, abs=1e-9)
