"""What the report says of a paper case's runs, read as its reader reads it: the summary's tilt of
the directors from the normal is the one the paragraph under the figures quotes (in three
dimensions, away from the clamped node), the paragraph says where the side view's angles are a
projection, and Bai's claims are checks that can fail, one-sided where they are bounds, with the
thickness that is at least h by construction reported, not checked. Fake runs, no solver."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np

from femcore import Mesh
from fibreshell.calibration import Calibration
from materials.presets import g986_stack
from validation.paper.discussion import discussion
from validation.paper.invariants import invariant_checks
from validation.paper.kinematics import KINEMATICS
from validation.paper.profiles import key_numbers, out_of_plane
from validation.records import ElementRun, SideProfile

LENGTH, WIDTH, H = 120.0, 30.0, 6.0  # H: g986_stack()'s 20 plies


def _profile(x, angle_deg, side_tilt, normal_tilt, thickness=H):
    n = len(x)
    return SideProfile(
        s=x[:, 0].copy(),
        midsurface=x,
        director_angle_deg=np.asarray(angle_deg, dtype=float),
        thickness=np.full(n, thickness),
        rotation_deg=np.zeros(n),
        side_tilt_deg=np.asarray(side_tilt, dtype=float),
        director_tilt_deg=np.asarray(normal_tilt, dtype=float),
    )


def _strip(drift=0.0):
    """A strip's side y = 0 from the clamp (x = 0) outwards, its last node moved ``drift`` mm
    sideways (out of the side's vertical plane)."""
    mesh = Mesh.rectangle(LENGTH, WIDTH, nx=4, ny=1)
    nodes = np.flatnonzero(np.abs(mesh.points[:, 1]) < 1e-9)
    nodes = nodes[np.argsort(mesh.points[nodes, 0])]
    x = mesh.points[nodes].copy()
    x[:, 2] -= 0.1 * x[:, 0]
    x[-1, 1] += drift
    specimen = SimpleNamespace(
        mesh=mesh,
        sides={"side_1": (nodes, mesh.points[nodes, 0])},
        clamp=nodes[:1],
        loaded=nodes[-1:],
    )
    return specimen, x


def _run(side, label="run", strain=1e-6):
    return ElementRun(
        label=label,
        converged=True,
        wall_time_s=1.0,
        steps=3,
        solver="Static",
        sides={"side_1": side},
        fibre_strain={"max_fibre_strain_away_from_support": strain},
    )


def test_the_summary_quotes_the_tilt_in_three_dimensions_away_from_the_clamped_node():
    # bai-5.1's Mindlin strip on main: 27.7 deg facing the side at the clamped node (the
    # director held, the slope a one-sided difference), 13.4 at the next, 18.1 in 3D there.
    _, x = _strip()
    side = _profile(x, [90.0] * 5, [-27.7, 13.4, 0.2, -1.9, -0.2], [27.7, 18.1, 0.3, 3.1, 0.2])
    numbers = key_numbers({"mindlin": _run(side)}, H)["mindlin side_1"]
    assert numbers.normal_tilt_max_deg == 18.1
    assert numbers.side_tilt_max_deg == 13.4


def test_a_side_leaving_its_vertical_plane_is_measured_and_named_in_the_paragraph():
    # bai-6.1.2's Mindlin sheet: the pushed corner 21 mm sideways, 21 deg facing the side where
    # the director is 2 deg from the normal in three dimensions.
    specimen, x = _strip(drift=21.5)
    assert out_of_plane(specimen, _run(_profile(x, [90] * 5, [0] * 5, [0] * 5))) == 21.5
    mindlin = _profile(x, [90.0] * 5, [-1.3, -0.7, 3.8, 11.5, 21.0], [2.3, 0.8, 2.4, 2.5, 2.1])
    fibrous = _profile(x, [90.0] * 5, [-1.7, -3.8, -8.4, -13.5, -18.6], [3, 5, 12, 20, 28])
    elements = {k: _run(mindlin if k == "mindlin" else fibrous) for k in KINEMATICS}
    case = SimpleNamespace(
        calibration=Calibration(),
        fabric=g986_stack(),
        comparison_note="",
        slip_sides=(),
        slip_note="",
    )
    text = discussion(case, specimen, elements, H).split("\n\n")[0]
    assert "at most 2.5 deg (in three dimensions)" in text
    assert "up to 21.5 mm out of it" in text and "differ by up to 21.0 deg" in text
    specimen, x = _strip()
    flat = {k: _run(_profile(x, [90] * 5, [0, 1.2, 0, 0, 0], [0, 2, 0, 0, 0])) for k in KINEMATICS}
    text = discussion(case, specimen, flat, H).split("\n\n")[0]
    assert "here it does, and the two differ by up to 1.2 deg" in text


def _invariants(fibrous_angle, thickness=H):
    specimen, x = _strip()
    fibrous = _profile(x, fibrous_angle, [0] * 5, [0] * 5, thickness=thickness)
    mindlin_x = x.copy()
    mindlin_x[:, 2] = -0.5 * mindlin_x[:, 0]  # slope 27 deg: strongly bent everywhere
    fibrous = SideProfile(**{**vars(fibrous), "midsurface": mindlin_x})
    mindlin = _profile(mindlin_x, [63.4] * 5, [0] * 5, [0] * 5)
    elements = {
        "fibrous": _run(fibrous),
        "fibrous_element": _run(_profile(mindlin_x, [90.0] * 5, [0] * 5, [0] * 5)),
        "mindlin": _run(mindlin),
    }
    case = SimpleNamespace(
        source="§0",
        midsurface_tolerance=0.25,
        slip_tolerance_deg=None,
        calibration=SimpleNamespace(name="laws"),
    )
    return {c.name: c for c in invariant_checks(case, specimen, elements, H, "coarse")}


def test_the_director_gap_is_a_bound_that_fails_below_it_and_the_thickness_is_reported():
    apart = _invariants([90.0] * 5)  # 26.6 deg from the Mindlin directors
    close = _invariants([65.0] * 5)  # 1.6 deg: the fibrous directors follow the normal
    name = "fibrous vs Mindlin director angle where the slope > 20 deg (deg, > 10)"
    assert apart[name].comparison == "at least" and apart[name].passed
    assert not close[name].passed and abs(close[name].error - (10.0 - 1.6)) < 1e-9
    thinnest = [c for c in apart.values() if "thinnest thickness" in c.name]
    assert len(thinnest) == 2 and all(c.comparison == "reported" for c in thinnest)
    assert all("Bai §" not in c.source or "set-up" in c.source or "claim" in c.source
               or "invariant" in c.source for c in apart.values())  # fmt: skip
