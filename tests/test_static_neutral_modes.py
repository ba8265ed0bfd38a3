"""Static's stability search leaves zero-energy modes alone (docs/theory.md §6.5, "Neutral
modes"; solvers/neutral_modes.py): a negative pivot whose eigenvalue lies within the tangent's
round-off of zero is a neutral mode, not an instability, and is neither counted, turned along
nor pushed along.

The reference: a flat fibrous strip pulled along its warp. Nothing turns the directors of a
flat sheet in in-plane tension, so the exact solution keeps them normal to the sheet and
stretches the strip uniformly, x -> lambda x; the warp's reaction is b T(ln lambda) / lambda
with T = C ln(lambda) (docs/theory.md §2.3, the tension conjugate to the log strain), and the
weft carries nothing. That state is stable: its tension stiffens every out-of-plane motion,
and its tangent's two lowest eigenvalues are the uniform tilt of every director (§1.7: each
fibre level moved in its own plane, no fibre stretched), zero in exact arithmetic and 1e-14
.. 5e-13 of a tangent whose diagonal reaches 1e3 .. 5e3 once rounded, either sign.
"""

from __future__ import annotations

import json

import numpy as np
import pytest
import scipy.sparse as sp

from elements import FibrousShell
from femcore import Mesh, Model
from fibreshell.cli import main
from materials import Fabric
from solvers import Static
from solvers.linear import LinearSolver
from solvers.neutral_modes import judge_pivots, unstable_modes

LENGTH, WIDTH, WARP = 40.0, 10.0, 1200.0  # mm, mm, N/mm
STRETCH = 1.05
# b C ln(lambda) / lambda, N: 557.6019 (docs/theory.md §2.3)
REACTION = WIDTH * WARP * np.log(STRETCH) / STRETCH
# A flat sheet's directors stay normal to it: a tilt is round-off, 1e-6 rad at most (the
# solution is reached in one or two Newton updates from directors exactly normal; the mode
# the search turned along before took them to 51 deg).
TILT = 1e-6  # rad
# Newton iterations an increment may take: the problem is linear in the warp's log strain
# along the imposed motion, and Newton reaches the uniform stretch in one update (plain
# Newton, Static(seek_stable=False): 1); a second for the round-off floor.
ITERATIONS = 2


def pulled_strip(weft: float) -> tuple[Model, np.ndarray]:
    """(the 40 x 10 mm strip of 4 x 2 cells pulled 5 % along the warp, its left nodes): the
    left end's translations held, the right end's imposed, every director free; fabric 1 mm
    thick, warp C = 1200 N/mm, weft ``weft`` N/mm, shear 0.2 N/mm, bending 7.5 N mm."""
    mesh = Mesh.rectangle(LENGTH, WIDTH, nx=4, ny=2)
    model = Model(mesh)
    fabric = Fabric(1.0, 1e-12, WARP, 0.2, 7.5, tension_weft=weft)
    model.add(FibrousShell(fabric))
    model.fix("left", ["ux", "uy", "uz"])
    model.displace("right", ux=(STRETCH - 1.0) * LENGTH, uy=0.0, uz=0.0)
    return model, mesh.nodes("left")


@pytest.mark.parametrize("weft", [500.0, 1200.0])
@pytest.mark.parametrize("increments", [1, 2, 4])
def test_a_flat_strip_in_tension_converges_at_once_with_its_directors_normal(increments, weft):
    # Before: weft 500 stopped after 8 cuts at 1 and 2 increments (the downhill turn divided
    # the residual's round-off along the tilt mode by its eigenvalue's, 1e-14) and at 4 it
    # converged with every director tilted 51.2 deg (57 iterations in the first increment);
    # weft 1200 converged flat but counted 1 or 2 negative eigenvalues at every increment,
    # an "unstable equilibrium".
    model, left = pulled_strip(weft)
    result = Static(increments=increments, progress=False).solve(model)
    reaction = -result.reactions[left, 0].sum()
    assert reaction == pytest.approx(REACTION, rel=1e-9)
    tilt = np.arccos(np.clip(result.directors[:, 2], -1.0, 1.0))
    assert tilt.max() < TILT
    assert max(result.info["iterations_per_increment"]) <= ITERATIONS
    assert result.info["negative_eigenvalues"] == [0] * increments
    assert result.info["saddles_kept"] == [] and result.info["cuts"] == 0


CASE = """
title = "flat fibrous strip pulled 5 % along the warp"
[mesh]
rectangle = { lx = 40.0, ly = 10.0, nx = 4, ny = 2 }
[[part]]
element = "fibrous"
[part.material]
thickness = 1.0
areal_density = 1e-9
tension = 1200.0
tension_weft = 500.0
shear = 0.2
bending = 7.5
[[fix]]
nodes = "left"
dofs = ["ux", "uy", "uz"]
[[displace]]
nodes = "right"
ux = 2.0
uy = 0.0
uz = 0.0
[solver]
kind = "static"
increments = INCREMENTS
[output]
history = { reactions = ["left"] }
"""


@pytest.mark.parametrize("increments", [2, 4])
def test_the_case_file_s_summary_reports_the_strip_flat(tmp_path, increments):
    # The same strip (weft 500) through `fibreshell run`: it stopped at 2 increments and
    # reported director_tilt_deg min = max = 51.20 deg at 4.
    path = tmp_path / "strip.toml"
    path.write_text(CASE.replace("INCREMENTS", str(increments)))
    out = tmp_path / "run"
    assert main(["run", str(path), "--out", str(out), "--quiet"]) == 0
    summary = json.loads((out / "summary.json").read_text())
    assert summary["status"] == "done"
    assert summary["director_tilt_deg"]["max"] < np.degrees(TILT)
    assert -summary["reactions"]["left"][0] == pytest.approx(REACTION, rel=1e-9)


def test_a_pivot_within_round_off_of_zero_is_neutral_and_one_beyond_it_negative():
    # K = Q diag(lambda) Q^T, its spectrum set by construction: 1e2 .. 1e3 and two negative
    # eigenvalues, -1e-12 (a zero mode's rounding) and -1e-7 (an instability). Q turns each
    # pair of unknowns by 45 deg, so each mode moves two unknowns whose diagonal is the mean
    # of the pair's eigenvalues, 60 and 130: the rounding of the second variation,
    # ROUND_OFF sum phi^2 |K_ii|, is 1.4e-11 and 2.9e-11, above the first and 3e3 times
    # below the second. Both are negative pivots of K's LDL^T (Sylvester); only the second
    # is a negative mode.
    n = 40
    values = np.geomspace(1e2, 1e3, n)
    values[[5, 17]] = [-1e-12, -1e-7]
    turn = np.sqrt(0.5) * np.array([[1.0, -1.0], [1.0, 1.0]])
    rotation = sp.block_diag([turn] * (n // 2), format="csc")
    k = (rotation @ sp.diags(values) @ rotation.T).tocsc()
    factor = LinearSolver().factorise(k)
    assert factor.negative == 2
    judged = judge_pivots(LinearSolver(), k, factor)
    assert (judged.negative, judged.neutral) == (1, 1)
    found, modes = np.linalg.eigh(k.toarray())
    kept, _ = unstable_modes(k, (found[:2], modes[:, :2]))
    assert kept == pytest.approx([-1e-7], rel=1e-6)


def test_the_noise_of_a_stiff_part_does_not_hide_a_soft_parts_instability():
    # A stiff tridiagonal part (4e6, -1e6 N/mm) with finite-difference noise of 1e-9 of its
    # entries (within SYMMETRY_TOLERANCE = 1e-7, so taken as a tangent meant symmetric), and
    # an uncoupled soft part diag(1, -1e-3) N/mm: its eigenvalue -1e-3 moves only the last
    # unknown, whose row has no noise, so its rounding is ROUND_OFF x 1e-3 = 2e-16 N/mm:
    # negative, by construction. Before: the stiff part's largest noisy row (2.4e-3 N/mm),
    # taken as the noise of every mode, called it neutral.
    n = 30
    stiff = 1e6 * (4.0 * np.eye(n) - np.eye(n, k=1) - np.eye(n, k=-1))
    noise = np.random.default_rng(0).standard_normal(stiff.shape) * (stiff != 0.0)
    k = sp.csc_matrix(sp.block_diag([stiff + 1e-3 * noise, np.diag([1.0, -1e-3])]))
    factor = LinearSolver().factorise(k)
    assert factor.negative == 1
    judged = judge_pivots(LinearSolver(), k, factor)
    assert (judged.negative, judged.neutral) == (1, 0)
    mode = np.zeros(n + 2)
    mode[-1] = 1.0
    kept, _ = unstable_modes(k, (np.array([-1e-3]), mode[:, None]))
    assert kept == pytest.approx([-1e-3])
