"""MindlinShell(fabric): a Mindlin shell whose section is the fabric's own laws (docs/theory.md
§5.7). Closed forms of the section's three laws (tension, in-plane shear, non-linear bending);
the same fabric in both kinematics gives the same answer where the kinematics agree (a flat
pull); its forces and tangent are checked by the conformance suite (tests/conformance_cases.py,
cases mindlin-fabric and mindlin-fabric-nonlinear)."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from elements import FibrousShell, MindlinShell
from elements.mindlin_fabric import default_transverse_shear, default_twisting
from femcore import Mesh, Model
from materials import BendingLaw, ElasticShell, Fabric, ShearLaw, TensionLaw
from solvers import Static

# Bai et al. (2020) Table 1: the G986 bending law, bilinear with a knee at 1e-3 1/mm.
G986_BENDING = BendingLaw.bilinear(7.5, 0.5, knee=1e-3)


def _fabric(**changes) -> Fabric:
    fields = dict(
        thickness=0.3, areal_density=1e-9, tension=1200.0, shear=4.0, bending=G986_BENDING
    )
    fields.update(changes)
    return Fabric(**fields)


@pytest.mark.slow
def test_an_end_moment_rolls_the_strip_into_the_circle_of_the_non_linear_law():
    # Statics: an end moment M per unit width bends every section by the same moment, so an
    # inextensible strip becomes a circular arc of curvature kappa = M^-1(M), the inverse of
    # the bending law; its free end sits at (R sin(L/R), R (1 - cos(L/R))), R = 1 / kappa.
    # Here kappa = pi / (2 L), 16 x past the knee of the bilinear law: the linear fit of its
    # initial slope would bend it 8 x less. Measured tip errors 1.0 % / 0.8 % (x / z) on 8
    # cells, 0.23 % / 0.19 % on 16 (second order); tolerance 0.5 % on 16. The moment field
    # is the statics' M / b, uniform along the strip: 0.12 % above it on 16 cells (each cell's
    # curvature measure is that of its chords, 0.23 % high, times the law's slope past the
    # knee), tolerance 0.5 %.
    length, width = 100.0, 10.0
    fabric = _fabric()
    mesh = Mesh.rectangle(length, width, nx=16, ny=1)
    model = Model(mesh)
    model.add(MindlinShell(fabric))
    model.fix("left")
    kappa = 0.5 * np.pi / length
    moment = float(G986_BENDING.value(kappa))
    tip = mesh.nodes("right")
    model.moment(tip, (0.0, -moment * width / len(tip), 0.0), amplitude="linear")
    result = Static(increments=4, progress=False).solve(model)
    radius = 1.0 / kappa
    x, _, z = result.positions[tip].mean(axis=0)
    assert x == pytest.approx(radius * np.sin(length / radius), rel=5e-3)
    assert z == pytest.approx(radius * (1.0 - np.cos(length / radius)), rel=5e-3)
    assert np.abs(result.field("warp_moment")) == pytest.approx(np.full(32, moment), rel=5e-3)
    assert np.abs(result.field("warp_curvature")) == pytest.approx(np.full(32, kappa), rel=2e-2)


@pytest.mark.parametrize("element", ["mindlin", "fibrous"])
def test_a_pull_gives_the_tension_law_in_both_kinematics(element):
    # A flat strip pulled along the warp to a stretch lambda carries W T(log lambda) / lambda
    # (T per unit initial width is the conjugate of the log strain: the energy W L0 Phi(eps)
    # differentiated in the length lambda L0) by the non-linear tension table, whatever the
    # kinematics: a flat pull moves no director. Both shells to Newton's residual (1e-8 of the
    # force; they agree with each other to 1e-15).
    law = TensionLaw.table([0.0, 0.01, 0.05], [0.0, 5.0, 100.0])
    fabric = _fabric(tension=law, tension_weft=30.0)
    length, width, stretch = 50.0, 10.0, 1.03
    mesh = Mesh.rectangle(length, width, nx=5, ny=2)
    model = Model(mesh)
    model.add(MindlinShell(fabric) if element == "mindlin" else FibrousShell(fabric))
    model.fix("left", ["ux", "uz"])
    model.fix(mesh.nodes(lambda x, y, z: (x == 0.0) & (y == 0.0)), "uy")
    model.displace("right", ux=(stretch - 1.0) * length)
    result = Static(increments=2, progress=False).solve(model)
    pull = result.reactions[mesh.nodes("right"), 0].sum()
    expected = width * float(law.value(np.log(stretch))) / stretch
    assert pull == pytest.approx(expected, rel=1e-8)
    # the membrane_force field reports T itself, lambda times the pull per reference width
    # (README, "Output fields"; docs/theory.md §2.3)
    warp = np.asarray(result.field("membrane_force"))[:, 0]
    assert warp == pytest.approx(np.full(len(warp), stretch * expected / width), rel=1e-7)


def test_a_shear_takes_the_shear_law_and_its_angle():
    # Every node moved by the simple shear x += tan(phi) y: the fibres, warp along x and weft
    # along y, close by gamma = phi (the weft turns, the warp does not: sin gamma = the cosine
    # of the fibre angle); the section's shear angle is that and its moment the law's M_s(phi)
    # (polynomial law), to round-off.
    law = ShearLaw.polynomial(4.0, 30.0)
    mesh = Mesh.rectangle(20.0, 20.0, nx=2, ny=2)
    model = Model(mesh)
    model.add(MindlinShell(_fabric(shear=law)))
    compiled = model.compile()
    phi = 0.2
    state = compiled.initial_state()
    shear = np.eye(3)
    shear[0, 1] = np.tan(phi)
    state = dataclasses.replace(state, positions=state.positions @ shear.T)
    fields = compiled.fields(state)["triangle"]
    assert fields["shear_angle_deg"] == pytest.approx(np.full(8, np.degrees(phi)), abs=1e-10)
    assert fields["membrane_force"][:, 2] == pytest.approx(np.full(8, law.value(phi)), rel=1e-12)


def test_the_defaults_are_stated_and_the_options_checked():
    fabric = _fabric(bending=7.5, shear=4.0, thickness=6.0)
    shell = MindlinShell(fabric)
    # 5 B0 / h^2 and B0 / 2 (elements/mindlin_fabric.py: the isotropic plate, nu = 0).
    assert shell.transverse_shear == pytest.approx(5.0 * 7.5 / 36.0)
    assert default_transverse_shear(fabric) == shell.transverse_shear
    assert shell.twisting == pytest.approx(7.5 / 2.0)
    assert default_twisting(fabric) == shell.twisting
    assert shell.half_thickness == 3.0
    with pytest.raises(ValueError, match="transverse_shear"):
        MindlinShell(fabric, transverse_shear=-1.0)
    with pytest.raises(ValueError, match="twisting"):
        MindlinShell(fabric, twisting=0.0)
    with pytest.raises(ValueError, match="warp"):
        MindlinShell(fabric, warp=(0.0, 0.0, 0.0))
    with pytest.raises(ValueError, match="belong to a Fabric"):
        MindlinShell(ElasticShell(1000.0, 0.3, 1.0, 1e-9), twisting=1.0)
    with pytest.raises(ValueError, match="ElasticShell or a materials.Fabric"):
        MindlinShell("g986")


def test_a_bending_law_with_a_toe_needs_the_sections_stated_stiffnesses():
    """A bending table flat up to 1e-4 1/mm has B0 = 0: the defaults S = 5 B0 / h^2 and D_t =
    B0 / 2 (docs/theory.md §5.7) would be 0, a mechanism, as an explicit 0 is refused. The
    shell is refused until both are given; given, they are the shell's."""
    toe = BendingLaw.table([0.0, 1e-4, 1e-2], [0.0, 0.0, 0.0743])
    fabric = Fabric(thickness=0.3, areal_density=2.85e-10, tension=1200.0, shear=0.2, bending=toe)
    with pytest.raises(ValueError, match=r"zero slope.*give transverse_shear .* and twisting"):
        MindlinShell(fabric)
    with pytest.raises(ValueError, match="default twisting"):
        MindlinShell(fabric, transverse_shear=416.7)
    shell = MindlinShell(fabric, transverse_shear=416.7, twisting=3.75)
    assert (shell.transverse_shear, shell.twisting) == (416.7, 3.75)
