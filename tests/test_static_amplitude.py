"""Static follows each load's and each prescribed displacement's quasi-static amplitude a(lambda)
on the load path (docs/theory.md §6.5, "How the loads are ramped"); the arc-length path, which
scales one load pattern, refuses an amplitude that is not proportional."""

import numpy as np
import pytest

from elements import MindlinShell
from femcore import Mesh, Model
from materials import ElasticShell
from solvers import DynamicRelaxation, Static

LENGTH, WIDTH, THICKNESS, MODULUS = 40.0, 20.0, 1.0, 1e4  # mm, mm, mm, MPa
NODE_FORCE = 0.01  # N on each node of the free edge


def half_sine(lam):
    return np.sin(np.pi * lam / 2)


def load_then_unload(lam):
    return np.sin(np.pi * lam)


def cantilever(amplitude, ny=2):
    """The strip 40 x 20 (4 x ny), clamped at x = 0, NODE_FORCE down on each node of x = 40;
    Poisson's ratio 0, so that it bends as a beam."""
    mesh = Mesh.rectangle(LENGTH, WIDTH, nx=4, ny=ny)
    model = Model(mesh)
    model.add(MindlinShell(ElasticShell(MODULUS, 0.0, THICKNESS, 1e-9)))
    model.fix("left")
    model.force("right", (0.0, 0.0, -NODE_FORCE), amplitude=amplitude)
    return model, mesh.nodes("right")


def tips(result, tip):
    """The free edge's mean deflection (mm) at each frame."""
    return np.array([frame.positions[tip, 2].mean() for frame in result.frames])


def test_static_follows_a_user_amplitude_as_beam_theory_does():
    # Small deflection (tip / L ~ 1e-3): tip(lambda) = a(lambda) P L^3 / (3 E I), P the
    # edge's total force, I = b t^3 / 12 (shear adds P L / (k G A), 4e-4 of it). The coarse
    # strip's own error against the beam is 1.5 % (the linear ramp's tip at lambda = 1): 3 %
    # holds it. Against a(lambda) times the linear ramp's answer on the same mesh, only the
    # geometric non-linearity differs, (tip / L)^2 ~ 1e-6: 1e-5.
    model, tip = cantilever(half_sine)
    result = Static(increments=4, progress=False).solve(model)
    lams = np.linspace(0.0, 1.0, 5)
    assert np.allclose(result.load_factors, lams)
    moment_of_area = WIDTH * THICKNESS**3 / 12.0
    beam = NODE_FORCE * len(tip) * LENGTH**3 / (3.0 * MODULUS * moment_of_area)
    deflections = -tips(result, tip)
    assert deflections[1:] == pytest.approx(half_sine(lams[1:]) * beam, rel=0.03)
    linear = -tips(Static(increments=1, progress=False).solve(cantilever("linear")[0]), tip)[-1]
    assert deflections == pytest.approx(half_sine(lams) * linear, rel=1e-5, abs=1e-12)
    # Not the linear ramp of a(1) it gave before (0.38 a(1) at lambda = 1/4 against 0.25).
    assert deflections[1] > 1.4 * 0.25 * linear


def test_static_and_dynamic_relaxation_agree_on_a_user_amplitude():
    # Both quasi-static solvers apply a(lambda) at lambda = i / n: the same frames, within
    # DynamicRelaxation's tolerance (1e-4 of the force reference).
    model, tip = cantilever(half_sine, ny=1)
    static = tips(Static(increments=4, progress=False).solve(model), tip)
    relaxed = tips(DynamicRelaxation(increments=4, progress=False).solve(model), tip)
    assert static == pytest.approx(relaxed, rel=1e-3, abs=1e-9)


def test_a_load_then_unload_comes_back_to_the_flat_strip():
    # a = sin(pi lambda): the load peaks at lambda = 1/2 and is gone at 1, where an elastic
    # strip is flat again (a force reference of zero load alone judged round-off against
    # round-off: the last converged frame's loads and reactions floor it).
    model, tip = cantilever(load_then_unload)
    result = Static(increments=4, progress=False).solve(model)
    linear = -tips(Static(increments=1, progress=False).solve(cantilever("linear")[0]), tip)[-1]
    deflections = -tips(result, tip)
    lams = np.asarray(result.load_factors)
    assert deflections == pytest.approx(load_then_unload(lams) * linear, rel=1e-5, abs=1e-9)
    assert abs(deflections[-1]) <= 1e-9 * linear


def test_dynamic_relaxation_also_comes_back_from_a_load_then_unload():
    # The same floor of the force reference in DynamicRelaxation: the unloaded strip is flat
    # again within its tolerance (1e-4 of the last frame's force scale: 1e-3 of the peak).
    model, tip = cantilever(load_then_unload, ny=1)
    relaxed = tips(DynamicRelaxation(increments=2, progress=False).solve(model), tip)
    static = tips(Static(increments=2, progress=False).solve(model), tip)
    assert relaxed[1] == pytest.approx(static[1], rel=1e-3)
    assert abs(relaxed[-1]) <= 1e-3 * abs(relaxed[1])


@pytest.mark.parametrize("share", [1e-3, 1e-5])
def test_a_partial_unload_is_converged_against_its_own_load_not_the_one_before(share):
    # Full load to lambda = 1/2, then `share` of it: each level is judged against its own
    # loads (the floor of the force reference is a millionth of the frame before), so the
    # small end deflection is the linear one within the solvers' tolerance (Static 1e-6,
    # DynamicRelaxation 1e-4 of its own force reference, the deflection to 1e-3). With the
    # whole frame before as the floor DynamicRelaxation ended 2.4 % off at 1e-3 and with the
    # wrong sign at 1e-5 (+1.76e-5 mm where -1.26e-5 is right).
    model, tip = cantilever(lambda lam: 1.0 if lam <= 0.5 else share, ny=1)
    static = tips(Static(increments=2, progress=False).solve(model), tip)
    relaxed = tips(DynamicRelaxation(increments=2, progress=False).solve(model), tip)
    assert static[-1] == pytest.approx(share * static[1], rel=1e-3)  # linear at that load
    assert relaxed[-1] == pytest.approx(static[-1], rel=1e-3)


def test_a_prescribed_displacement_follows_its_user_amplitude():
    # The free edge pulled down by 2 sin(pi lambda) mm: the edge's reaction follows the same
    # amplitude (small deflection: linear in the displacement), a(lambda) times the reaction
    # of the linear ramp's full displacement.
    def pulled(amplitude):
        mesh = Mesh.rectangle(LENGTH, WIDTH, nx=4, ny=2)
        model = Model(mesh)
        model.add(MindlinShell(ElasticShell(MODULUS, 0.0, THICKNESS, 1e-9)))
        model.fix("left")
        model.displace("right", uz=-0.2, amplitude=amplitude)
        return model, mesh.nodes("right")

    model, edge = pulled(load_then_unload)
    result = Static(increments=4, progress=False).solve(model)
    full = Static(increments=1, progress=False).solve(pulled("linear")[0])
    full_reaction = full.frames[-1].reactions[edge, 2].sum()
    lams = np.asarray(result.load_factors)
    reactions = np.array([frame.reactions[edge, 2].sum() for frame in result.frames])
    assert reactions == pytest.approx(load_then_unload(lams) * full_reaction, rel=1e-4, abs=1e-12)
    edge_z = np.array([frame.positions[edge, 2].mean() for frame in result.frames])
    assert edge_z == pytest.approx(-0.2 * load_then_unload(lams), abs=1e-12)


def test_the_arc_length_path_refuses_an_amplitude_that_is_not_proportional():
    model, _ = cantilever(half_sine, ny=1)
    with pytest.raises(ValueError, match="half_sine.*path='arc_length'.*expected path='load'"):
        Static(increments=4, path="arc_length", progress=False).solve(model)


def test_the_arc_length_path_takes_a_proportional_user_amplitude():
    model, tip = cantilever(lambda lam: 2.0 * lam, ny=1)
    doubled = tips(Static(increments=2, path="arc_length", progress=False).solve(model), tip)
    named = tips(Static(increments=1, progress=False).solve(cantilever("linear", ny=1)[0]), tip)
    assert doubled[-1] == pytest.approx(2.0 * named[-1], rel=1e-5)
