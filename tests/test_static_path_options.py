"""Static's load-path options are refused with path="arc_length", whose steps never read
them (it has its own predictor, solvers.arc_length.arc_predictor), as the arc-length options are
refused with path="load"; with at_limit="jump" load steps follow a limit point, and they pass."""

import pytest

from solvers import Static


@pytest.mark.parametrize(
    "option",
    [
        {"ply_penalty_start": 0.5},
        {"first_turn": 0.1},
        {"predictor": True},
        {"follow_tools": True},
        {"follow_tools_after_cut": True},
    ],
)
def test_the_load_path_options_are_refused_on_the_arc_length_path(option):
    ((name, value),) = option.items()
    with pytest.raises(
        ValueError, match=rf"{name}={value!r} given with path='arc_length'.*expected path='load'"
    ):
        Static(path="arc_length", **option)
    Static(path="load", **option)
    Static(path="arc_length", at_limit="jump", **option)  # the load steps after a limit read it


def test_the_load_path_options_at_their_defaults_pass_on_the_arc_length_path():
    Static(
        path="arc_length",
        ply_penalty_start=None,
        first_turn=None,
        predictor=False,
        follow_tools=False,
        follow_tools_after_cut=False,
    )


def test_all_refused_options_are_named_at_once():
    with pytest.raises(ValueError, match="predictor=True, first_turn=0.1 given"):
        Static(path="arc_length", predictor=True, first_turn=0.1)
