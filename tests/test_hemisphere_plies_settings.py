"""The two-ply hemisphere case's solver settings: each run over its own stroke (the study's
DURATION times its STROKE_SLOWING, validation/studies/hemisphere_plies_setup.py), the same
settings the study's runs and the benchmarks that time them are given."""

import pytest

from validation.studies import hemisphere_plies_run as run
from validation.studies.hemisphere_plies_setup import DAMPING, DURATION, STROKE_SLOWING


@pytest.mark.parametrize("name", ["0/90", "0/45"])
@pytest.mark.parametrize("kinematics", ["fibrous", "mindlin"])
def test_each_run_lasts_its_own_stroke_with_a_frame_every_hundredth(name, kinematics):
    settings = run.case_settings(name, kinematics)
    stroke = DURATION * STROKE_SLOWING.get((name, kinematics), 1.0)
    assert settings == {
        "duration": stroke,
        "damping": DAMPING,
        "progress": False,
        "output_interval": stroke / 100,
    }


def test_the_mindlin_0_90_run_is_the_one_slowed_to_its_quasi_static_pace():
    # x4 on [0/90] Mindlin, none elsewhere: x2 (docs/hemisphere_forming.md "the two plies'
    # pace") snapped late in the stroke (validation/studies/hemisphere_plies_pace_scatter.py)
    assert run.case_settings("0/90", "mindlin")["duration"] == pytest.approx(4 * DURATION)
    assert run.case_settings("0/45", "mindlin")["duration"] == pytest.approx(DURATION)
    assert run.case_settings("0/90", "fibrous")["duration"] == pytest.approx(DURATION)


def test_a_share_and_options_shorten_or_replace_the_settings():
    settings = run.case_settings("0/45", "fibrous", share=0.25, output_interval=None)
    assert settings["duration"] == pytest.approx(0.25 * DURATION)
    assert settings["output_interval"] is None


@pytest.mark.parametrize(
    ("name", "kinematics", "share", "match"),
    [
        ("0/60", "fibrous", 1.0, "no run of layup '0/60'"),
        ("0/90", "kirchhoff", 1.0, "'kirchhoff' plies"),
        ("0/90", "fibrous", 0.0, "share is the part of the stroke"),
        ("0/90", "fibrous", 1.5, "share is the part of the stroke"),
    ],
)
def test_an_unknown_run_or_share_is_refused(name, kinematics, share, match):
    with pytest.raises(ValueError, match=match):
        run.case_settings(name, kinematics, share=share)


def test_the_holder_s_force_amplitude_of_a_float_is_numpy_s_clip_to_the_bit():
    """The explicit step asks the holder's amplitude every step with a float (Python's
    comparisons, not numpy's clip of a 0-d array): the same number, bit for bit, over the
    ramp, either side of it, at its ends, at -0 and for NaN; an array keeps numpy's clip."""
    import numpy as np

    from validation.studies.hemisphere_plies_setup import HOLDER_RAMP, _holder_amplitude

    taus = np.concatenate([
        np.random.default_rng(3).uniform(-0.5, 1.5, 2000),
        [0.0, -0.0, HOLDER_RAMP, np.nextafter(HOLDER_RAMP, 1.0), np.nextafter(HOLDER_RAMP, 0.0),
         5e-324, -5e-324, np.inf, -np.inf, np.nan],
    ])  # fmt: skip
    expected = np.clip(taus / HOLDER_RAMP, 0.0, 1.0)
    found = np.array([_holder_amplitude(float(tau)) for tau in taus])
    assert found.tobytes() == expected.tobytes()
    assert np.asarray(_holder_amplitude(taus)).tobytes() == expected.tobytes()
