"""More bad input at the API boundary: solver options, loads, tools a body starts inside,
sweeps and comparisons too large or wrong before anything runs, models held only by
frictionless contact, relaxations that stall. Each is a ValueError (or a ConvergenceError for
a run that cannot progress) that names what was wrong, never a raw traceback, a hang or a
silent wrong answer."""

import warnings
from pathlib import Path

import numpy as np
import pytest

from elements import Cable, FibrousShell, RigidCylinder, RigidPlane, RigidSurface
from femcore import Mesh, Model
from fibreshell.case import CaseError, load_case
from fibreshell.compare import compare_case
from fibreshell.identify import read_measurements
from fibreshell.sweep import MAX_VARIANTS, parse_vary, sweep, variants
from materials import presets
from solvers import CentralDifference, ConvergenceError, DynamicRelaxation, Static
from solvers.common import check_held

CASES = Path(__file__).resolve().parent.parent / "cases"


def cable(amplitude="step") -> Model:
    """A 10 mm cable of 4 elements pinned at its start, pulled at its end (dt ~ 2.5e-6 s)."""
    model = Model(Mesh.line((0.0, 0.0, 0.0), (10.0, 0.0, 0.0), 4))
    model.add(Cable(1.0e3, 1.0e-9))
    model.fix("start")
    model.force("end", (1.0, 0.0, 0.0), amplitude=amplitude)
    return model


def strip(tool, lift: float = 0.0, friction: float = 0.0) -> Model:
    """A 100 x 20 mm G986 stack (6 mm) under gravity, its mid-surface ``lift`` mm above
    z = 0, in contact with ``tool`` and held by nothing else."""
    flat = Mesh.rectangle(100.0, 20.0, nx=4, ny=1)
    model = Model(flat.with_points(flat.points + [0.0, 0.0, lift]))
    model.add(FibrousShell(presets.g986_stack()))
    model.contact(tool, friction=friction)
    model.gravity((0.0, 0.0, -9810.0))
    return model


# ------------------------------------------------------------------ loads
def test_a_word_where_a_force_vector_belongs_is_a_value_error():
    model = Model(Mesh.rectangle(10.0, 10.0, nx=2, ny=2))
    with pytest.raises(ValueError, match=r"force must be 3 finite numbers .*got 'down'"):
        model.force("right", "down")
    with pytest.raises(ValueError, match=r"moment must be 3 finite numbers .*got \[1, 'x', 0\]"):
        model.moment("right", [1, "x", 0])


def spike(tau):
    """Finite at tau = 1 (where the load is checked when it is added), NaN mid-run."""
    return np.nan if 0.4 < tau < 0.6 else tau


@pytest.mark.parametrize(
    "solver, where",
    [
        (CentralDifference(duration=1e-3, progress=False), r"tau = t / duration = 0\.4"),
        (DynamicRelaxation(increments=4, progress=False), "load factor 0.5"),
    ],
    ids=["explicit", "relaxation"],
)
def test_an_amplitude_that_returns_nan_is_named_with_where_it_failed(solver, where):
    with pytest.raises(ValueError, match=rf"amplitude 'user' \(spike\) returned nan at {where}"):
        solver.solve(cable(amplitude=spike))


# ------------------------------------------------------------------ solver options
def test_a_word_for_a_damping_is_a_value_error_naming_the_option():
    with pytest.raises(ValueError, match="damping must be a non-negative number .*'high'"):
        CentralDifference(duration=1.0, damping="high")
    with pytest.raises(ValueError, match="unknown damping 'high'"):
        DynamicRelaxation(damping="high")
    with pytest.raises(ValueError, match="safety must be in"):
        CentralDifference(duration=1.0, safety="high")


@pytest.mark.parametrize(
    "kind, option, value, message",
    [
        ("explicit", 'damping = "high"', "damping", "non-negative number"),
        ("relaxation", 'damping = "high"', "damping", "unknown damping"),
        ("explicit", "max_steps = 2.5", "max_steps", "integer >= 1, got 2.5"),
        ("static", "max_cuts = true", "max_cuts", "integer >= 0, got True"),
        # the unit in its brackets, never "()"
        ("explicit", "dt = -0.001", "dt", r"positive finite number \(s\), got -0\.001"),
    ],
)
def test_a_bad_solver_option_in_a_case_file_names_the_file_table_and_key(
    tmp_path, kind, option, value, message
):
    text = (CASES / "g1151_strip.toml").read_text()
    duration = "duration = 0.1\n" if kind == "explicit" else ""
    text = text.replace('kind = "static"\nincrements = 3', f'kind = "{kind}"\n{duration}{option}')
    path = tmp_path / "bad.toml"
    path.write_text(text)
    with pytest.raises(CaseError, match=rf"bad\.toml: \[solver\.{value}\]: .*{message}"):
        load_case(path)


INTEGER_OPTIONS = [
    (lambda **o: CentralDifference(duration=1.0, **o), "max_steps"),
    *[(DynamicRelaxation, name) for name in ("increments", "max_iterations", "refresh",
                                              "stall_iterations", "plateau_iterations")],
    *[(Static, name) for name in ("increments", "max_iterations", "max_cuts", "max_increments",
                                  "chords", "stall_iterations")],
]  # fmt: skip


@pytest.mark.parametrize("make, option", INTEGER_OPTIONS)
@pytest.mark.parametrize("value", [float("nan"), 2.5, 3.0, True, "3"])
def test_every_integer_option_of_every_solver_refuses_what_is_not_an_integer(make, option, value):
    """2.5 would be truncated to 2, NaN has no count, True is not a count."""
    with pytest.raises(ValueError, match=rf"{option} must be an integer >= \d, got"):
        make(**{option: value})


def test_flags_refuse_words_that_bool_would_take_for_true():
    with pytest.raises(ValueError, match="line_search must be true or false, got 'no'"):
        Static(line_search="no")


@pytest.mark.parametrize("solver", [CentralDifference(duration=1.0), DynamicRelaxation(), Static()])
def test_solve_refuses_what_is_not_a_model(solver):
    name = type(solver).__name__
    with pytest.raises(ValueError, match=rf"{name}\.solve expects a femcore Model .*got str"):
        solver.solve("model")


# ------------------------------------------------------------------ explicit limits
def test_a_step_count_above_max_steps_is_refused_before_the_first_step():
    with pytest.raises(ValueError, match=r"1e\+12 steps, more than max_steps = 50000000"):
        CentralDifference(duration=1.0, dt=1e-12, progress=False).solve(cable())
    with pytest.raises(ValueError, match="more than max_steps = 100"):
        CentralDifference(duration=1e-3, max_steps=100, progress=False).solve(cable())


def test_mass_scaling_that_would_add_many_times_the_mass_is_refused_naming_the_factor():
    """The cable's stable step is 2.5e-6 s and the step taken 0.9 of it: a target of 1e-3 s
    would multiply its mass by 2e5, one of 1e-5 s add (1e-5 / 0.9 / 2.5e-6)^2 - 1 = 18.8
    times it (above the default cap of 10, below a cap of 20), one of 4e-6 s 2.2 times."""
    with pytest.raises(ValueError, match=r"would add 1\.\d+e\+05 times the elements' mass"):
        CentralDifference(duration=1e-3, mass_scaling_dt=1e-3, progress=False).solve(cable())
    with pytest.raises(ValueError, match=r"would add 18\.\d times .* max_added_mass = 10"):
        CentralDifference(duration=1e-4, mass_scaling_dt=1e-5, progress=False).solve(cable())
    heavier = CentralDifference(duration=1e-4, mass_scaling_dt=1e-5, max_added_mass=20.0)
    assert heavier.solve(cable()).info["added_mass_ratio"] == pytest.approx(18.75, rel=1e-2)
    modest = CentralDifference(duration=1e-4, mass_scaling_dt=4e-6, progress=False)
    assert modest.solve(cable()).info["added_mass_ratio"] == pytest.approx(2.16, rel=1e-2)


# ------------------------------------------------------------------ tools
@pytest.mark.parametrize(
    "tool, hint",
    [
        (RigidPlane((0.0, 0.0, 0.0), (0.0, 0.0, -1.0)), r"normal = \(0.0, 0.0, -1.0\) must"),
        (RigidCylinder((50.0, 10.0, 0.0), (1.0, 0.0, 0.0), 5.0, side="inside"), "side = inside"),
        (
            RigidSurface(Mesh.rectangle(140.0, 60.0, nx=2, ny=2).with_points(
                Mesh.rectangle(140.0, 60.0, nx=2, ny=2).points - [20.0, 20.0, 0.0]), flip=True),
            r"flip = true",
        ),
    ],
    ids=["plane-normal-away", "cylinder-inside", "surface-flipped"],
)  # fmt: skip
def test_a_body_that_starts_inside_a_tool_is_refused_naming_the_tool_and_nodes(tool, hint):
    model = strip(tool, lift=3.0)
    model.fix("left")
    with pytest.raises(ValueError, match=r"tool 1\): the body starts inside .*nodes 0, 1, 2"):
        model.compile()
    with pytest.raises(ValueError, match=hint):
        model.compile()


def test_the_refusal_states_the_penetration_it_compares_with_the_offset():
    """Mid-surface 3 mm past a plane whose normal points away: a penetration of 3 + h / 2 =
    6 mm, deeper than h / 2 = 3 mm (it read "up to 3 mm past ... deeper than 3 mm")."""
    model = strip(RigidPlane((0.0, 0.0, 0.0), (0.0, 0.0, -1.0)), lift=3.0)
    model.fix("left")
    with pytest.raises(ValueError, match=r"3 mm past its surface, a penetration of 6 mm, deeper "
                       r"than the contact offset h / 2 = 3 mm"):  # fmt: skip
        model.compile()


@pytest.mark.parametrize("lift", [3.0, 3.0 - 1e-6, 3.0 + 1e-6], ids=["on", "round-off", "above"])
def test_a_body_laid_on_a_tool_starts_fine_and_silently(lift):
    """Mid-surface half the thickness above the plane: touching, not inside, and a
    millionth of a millimetre either way is no overlap to report."""
    model = strip(RigidPlane((0.0, 0.0, 0.0), (0.0, 0.0, 1.0)), lift=lift)
    model.fix("left")
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        model.compile()


def test_a_body_that_starts_overlapping_a_tool_is_warned_naming_the_tool_depth_and_remedy():
    """The 6 mm stack 2 mm into the plane (less than h / 2, so not refused): the penalty
    would push it out at the first load with forces far above its weight, silently (a 15 mm
    laminate 2.5 mm into a plane: 19 kN on the tool against a weight of 0.14 N)."""
    model = strip(RigidPlane((0.0, 0.0, 0.0), (0.0, 0.0, 1.0)), lift=1.0)
    model.fix("left")
    with pytest.warns(UserWarning, match=r"tool 1\): the body starts overlapping the RigidPlane: "
                      r"10 of 10 contact nodes lie up to 2 mm into it .* Move the tool or the "
                      r"blank 2 mm apart"):  # fmt: skip
        model.compile()


# ------------------------------------------------------------------ held by contact only
@pytest.mark.parametrize("solver", [Static(), DynamicRelaxation()], ids=["static", "relaxation"])
def test_a_strip_on_a_frictionless_plane_is_refused_naming_its_free_motions(solver):
    model = strip(RigidPlane((0.0, 0.0, 0.0), (0.0, 0.0, 1.0)), lift=3.0)
    with pytest.raises(
        ValueError,
        match=r"nothing holds the model against translation along x, translation along y and "
        r"rotation about z: interaction 0 \(Contact, tool 1\) .*frictionless",
    ):
        solver.solve(model)


def test_a_sideways_load_on_a_body_on_a_frictionless_plane_names_the_contact_too():
    model = strip(RigidPlane((0.0, 0.0, 0.0), (0.0, 0.0, 1.0)), lift=3.0)
    model.force("right", (1.0, 0.0, 0.0))
    with pytest.raises(
        ValueError, match=r"net force along .*\(translation along x\); interaction 0"
    ):
        check_held(model.compile())


def test_friction_or_a_support_holds_what_a_frictionless_contact_leaves_free():
    plane = RigidPlane((0.0, 0.0, 0.0), (0.0, 0.0, 1.0))
    check_held(strip(plane, lift=3.0, friction=0.3).compile())
    pinned = strip(plane, lift=3.0)
    pinned.fix("left", ["ux", "uy"])
    check_held(pinned.compile())


def test_a_frictionless_cylinder_leaves_the_slide_along_and_the_turn_about_its_axis_free():
    cylinder = RigidCylinder((50.0, 0.0, -20.0), (0.0, 1.0, 0.0), 20.0)
    free = strip(cylinder, lift=3.0).compile().unheld_rigid_motions(loaded_only=False)
    assert free == [
        "translation along y",
        "rotation about the axis along (0, 1, 0) through (50, 10, -20)",
    ]


# ------------------------------------------------------------------ a stalled relaxation
def test_a_relaxation_that_makes_no_progress_stops_keeping_the_converged_frames():
    """A tolerance below the round-off floor of the residual: the smallest ratio stops
    falling, and the run stops within a window instead of running max_iterations."""
    model = cable()
    model.fix("end", ["uy", "uz"])
    solver = DynamicRelaxation(tol=1e-15, plateau_iterations=500, progress=False)
    with pytest.raises(ConvergenceError, match=r"stalled .* in the last 500 iterations") as error:
        solver.solve(model)
    result = error.value.result
    assert not result.converged and len(result.frames) == 1  # the reference state
    assert DynamicRelaxation(progress=False).solve(model).converged


# ------------------------------------------------------------------ sweeps, compare, identify
def test_a_sweep_of_too_many_variants_is_refused_with_its_count(tmp_path):
    with pytest.raises(ValueError, match="whole count"):
        parse_vary("mesh.rectangle.lx=linspace(100, 200, 1e9)")
    with pytest.raises(ValueError, match=f"1000000000 values, more than the {MAX_VARIANTS}"):
        parse_vary("mesh.rectangle.lx=linspace(100, 200, 1000000000)")
    listed = "solver.increments=" + ",".join(map(str, range(1, 10_002)))
    with pytest.raises(ValueError, match=f"10001 values, more than the {MAX_VARIANTS}"):
        parse_vary(listed)
    many = {"a": list(range(200)), "b": list(range(200))}
    with pytest.raises(ValueError, match=r"40000 variants \(200 x 200 values\), more than"):
        variants(many)
    assert len(variants(many, max_variants=40_000)) == 40_000
    out = tmp_path / "sweep"
    with pytest.raises(ValueError, match="40000 variants"):
        sweep(CASES / "g1151_strip.toml", many, out=out)
    assert not out.exists()  # refused before anything was written or run


def test_compare_checks_its_options_before_the_first_run(tmp_path):
    case = load_case(CASES / "g1151_strip.toml")
    with pytest.raises(ValueError, match=r"shear_ratio must be a positive .*-1"):
        compare_case(case, tmp_path, calibration="initial-slope", shear_ratio=-1.0)
    with pytest.raises(ValueError, match="no path 'nowhere'"):
        compare_case(case, tmp_path, calibration="fit", fit_path="nowhere")
    assert not (tmp_path / "fibrous").exists()


def test_a_binary_data_file_is_a_value_error_naming_it(tmp_path):
    path = tmp_path / "measured.csv"
    path.write_bytes(bytes(range(256)) * 4)
    with pytest.raises(ValueError, match=r"measured\.csv: not a text CSV file"):
        read_measurements(path)


def test_the_command_line_refuses_these_before_anything_runs(tmp_path, capsys):
    from fibreshell.cli import main

    case = str(CASES / "g1151_strip.toml")
    out = tmp_path / "out"
    vary = ["--vary", "mesh.rectangle.nx=1,2,3", "--vary", "mesh.rectangle.ny=1,2"]
    assert main(["sweep", case, *vary, "--max-variants", "5", "--out", str(out)]) == 2
    assert "the sweep has 6 variants (3 x 2 values), more than" in capsys.readouterr().err
    huge = ["--vary", "mesh.rectangle.lx=linspace(100, 200, 20000)"]
    assert main(["sweep", case, *huge, "--out", str(out)]) == 2
    assert "20000 values, more than the 10000 variants" in capsys.readouterr().err
    compare = ["compare", case, "--calibration", "initial-slope", "--shear-ratio", "-1"]
    assert main([*compare, "--out", str(out), "--quiet"]) == 2
    assert "shear_ratio must be a positive" in capsys.readouterr().err
    assert not out.exists()
    data = tmp_path / "measured.csv"
    data.write_bytes(bytes(range(256)) * 4)
    fit = ["--fit", "part.0.material.areal_density", "--out", str(out), "--quiet"]
    assert main(["identify", case, "--data", str(data), *fit]) == 2
    assert "measured.csv: not a text CSV file" in capsys.readouterr().err


def test_the_errors_that_name_an_entry_or_a_setting_cross_a_process_pool_as_raised():
    # pickled and read back (a sweep's or a report's worker hands its errors back so): before,
    # unpickling raised TypeError for the missing arguments.
    import pickle

    from femcore.entry_error import EntryError, EntryWarning
    from solvers.common import SettingError

    for error in (
        EntryError("load", 2, "no DOF", prefix="model.loads[2]: "),
        EntryWarning("interaction", 0, "starts inside", prefix="model.interactions[0]: "),
        SettingError("max_steps", "too many steps"),
    ):
        back = pickle.loads(pickle.dumps(error))
        assert type(back) is type(error) and str(back) == str(error)
        assert vars(back) == vars(error)


# ------------------------------------------------------------ options that act through another
@pytest.mark.parametrize(
    "make, named",
    [
        (lambda: CentralDifference(duration=1.0, dt=1e-3, safety=0.5), "safety = 0.5"),
        (lambda: CentralDifference(duration=1.0, max_added_mass=3.0), "max_added_mass = 3.0"),
        (lambda: DynamicRelaxation(masses="lumped", refresh=5), "refresh = 5"),
    ],
    ids=["safety-with-dt", "max_added_mass-without-scaling", "refresh-with-lumped-masses"],
)
def test_an_option_that_nothing_would_use_is_refused_naming_what_it_needs(make, named):
    # Accepted, each was ignored: a fixed dt takes no safety, nothing adds mass without
    # mass_scaling_dt, and lumped masses are never re-estimated.
    with pytest.raises(ValueError, match=named):
        make()


def test_options_that_act_together_are_taken():
    # safety with a fixed dt still scales mass scaling's target (solvers/explicit_step_size.py)
    solver = CentralDifference(duration=1.0, dt=1e-3, safety=0.5, mass_scaling_dt=1e-4)
    assert solver.safety == 0.5
    assert CentralDifference(duration=1.0).safety == 0.9
    assert DynamicRelaxation(masses="gershgorin", refresh=5).refresh == 5
    assert DynamicRelaxation(masses="lumped").refresh == 100


@pytest.mark.parametrize("nodes, named", [([-1], ">= 0, got -1"), ([99], "has node 99")])
def test_a_history_node_the_model_does_not_have_is_refused_before_the_run(tmp_path, nodes, named):
    # -1 was recorded as the last node under the name "node-1"; 99 on a 5-node cable was an
    # IndexError from the history writer, after the run had started.
    with pytest.raises(ValueError, match=named):
        CentralDifference(
            duration=1e-5, history=tmp_path / "h.csv", history_nodes=nodes, progress=False
        ).solve(cable())


def test_a_displacement_prescribed_at_the_start_of_an_explicit_run_is_refused():
    # "step" puts the whole displacement at t = 0: the node jumps in one step, an infinite
    # velocity. Measured on a 10-cell Mindlin cantilever with its tip lifted 0.1 mm so: the
    # run completed with KE + U = 327 N mm against an external work of 2359 (the records did
    # not close); at 1 mm the step fell 40-fold and the run diverged on its last step.
    model = cable()
    model.displace("end", uy=0.1, amplitude="step")
    with pytest.raises(ValueError, match=r"1 node\(s\) have a displacement prescribed at t = 0"):
        CentralDifference(duration=1e-5, progress=False).solve(model)
    # the same displacement ramped from zero runs; and Static and relaxation ramp any
    # amplitude with the load factor, a step included
    ramped = cable()
    ramped.displace("end", ux=0.01, amplitude="smooth")
    CentralDifference(duration=1e-4, progress=False, kinetic_bound=None).solve(ramped)
    DynamicRelaxation(progress=False).solve(model)
