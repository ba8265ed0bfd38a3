"""The two-ply hemisphere's kinetic energy split between the plies and the blank holder
(validation/studies/hemisphere_plies.py): the run's KE / W check counts every mass of the
model, the holder's rigid node among them, so a holder thrown up by the flange fails it while
the plies themselves move slowly. ``kinetic_shares`` says which (at the run's frames: 1/2 m v^2
over the plies' lumped masses and the holder's node; the rest of the recorded kinetic energy is
the directors' rotation).

Whose kinetic energy: Mindlin [0/90], 8 cells, 10 N (rerun on the current code, one thread,
8116 steps, 97 s of CPU, load 2.6-5.5; frames every 0.0005 s). As before: to the end, KE / W
0.260 at t = 0.047 s (above 0.1 over 37 % of the judged time), the holder 8.30 N over the last
tenth. At t = 0.046 s the run's 21.7 N mm of kinetic energy are the holder's 16.7 (rising at
0.58 m/s) and the plies' translations' 4.2; after the first tenth the holder's kinetic energy
alone reaches 0.182 of W (t = 0.0465 s), the plies' 0.056 up to t = 0.065 s and 0.068 at most
(t = 0.0745 s, as the flange folds). The check fails on the holder's.

When and where. The holder leaves the flange at t = 0.014 s, the punch 1.2 mm down: the plies'
nodes over the die's entry radius (r = 50-56 mm) stand 0.1 mm above the flange and those under
the ring alternate between the die and the holder, a wrinkle of the mesh's own wavelength
(25-mm cells) 0.2 mm high at 0.02 s, 1.0 at 0.03 s, 2.9 at 0.04 s; the holder rises at 0.63 m/s
at t = 0.05 s, 14.0 mm up at 0.064 s, falls back to 10.3 mm at 0.08 s and is thrown again, 22.2
mm up at the end.

What it is not. Nothing in the contacts acts on the Mindlin directors (the tools' contacts act
on the nodes, the ply contact's faces lie along the nodal normals). The calibration's
transverse shear is the S3 homogeneous section's, 5/6 G13 h = 5 B0 / h^2 = 20.8 N/mm
(tests/test_hemisphere_plies.py; Abaqus may scale a thin shell's transverse shear down by a
slenderness factor of the element's area over h^2, which this shell does not have: not checked
against Abaqus here). A 10 x softer transverse shear (``ElasticShell.equivalent``'s shear_ratio
0.05: a diagnosis, not the comparison's section) delays the lift to t = 0.032 s and passes KE /
W (0.088 at t = 0.081 s, the plies' 0.079 at most; 3789 steps, 60 s) but the flange throws the
holder late in the stroke all the same (21.9 mm up at the end, 6.50 N over the last tenth): the
stiff transverse shear resists the kinks the 25-mm facets make over the 5-mm entry radius and
lifts the flange early, but the Mindlin flange wrinkles and lifts the 100-g holder at 10 N
whatever its transverse shear. At 20 N (8185 steps, 155 s, load 6.6-7.8) the same: to the end,
KE / W 0.218 at t = 0.048 s (above 0.1 over 19 %; the holder's 10.3 of 13.2 N mm at t = 0.044
s, rising at 0.45 m/s; the plies' KE / W 0.083 at most), the holder 18.61 N over the last tenth
and 11.3 mm up at the end; rms of shear - net 3.62 and 3.11 deg (26 and 13 cells in the die),
draw-in of the edge middle 25.5 and 29.0 mm (corner 5.7 and 17.9), 11 and 13 crests up to 13.0
mm, the least radial gap in the die -0.36 mm, punch force 104 N.

The directors' tilt. Against the nodal normals the tilt misleads on 25-mm facets: the plies'
strain energy is 1.16 + 1.17 N mm at t = 0.02 s with their own directors and 67 + 72 with the
directors set on the nodal normals (3468 + 3421 against 30 + 29 at 0.045 s): the transverse
shear holds the directors near their facets' normals, not the nodes' averages. Against the
nearest of each node's own cells' normals the largest tilt is 20-40 deg up to t = 0.065 s;
after it, as the flange folds (nodes at 5-8 m/s), 111 of the 128 cells of ply 1 have a corner
director more than 30 deg off the cell's normal at t = 0.075 s while each ply stores 345-355 N
mm in all, where one flat 25-mm cell with one corner director turned by 89 deg stores 542 N mm.
The element's energy goes as sin^2 of a director's turn (16, 136, 407, 542, 407, 136 and 0.17 N
mm at 10, 30, 60, 89, 120, 150 and 179 deg on that cell): a director turned half round is
unstrained (the thickness fixed, E33 dropped), and the tilt read with |cos| calls it upright;
how the folded flange's tilted directors store so little is not looked into.

At 10 cells Mindlin [0/90] (8300 steps, 125 s, load 4.7-6.3) stops at 82.2 % of the stroke on
the energy balance (0.108 of the largest energy against 0.05; the Mindlin block +25.7 N mm in
the step), KE / W 0.143 at the stop (above 0.1 over 32 % of the judged time), the holder thrown
24 mm up (1.09 m/s at t = 0.062 s, 58.9 of the run's 74.6 N mm then; the plies' KE / W 0.080 at
most), its reaction 11.84 N at the stop; at the stop rms of shear - net 5.71 deg (ply 1, 5
cells in the die; ply 2 none), draw-in of the edge middle 24.9 and 24.8 mm, 11 and 10 crests up
to 28.4 mm, the least radial gap in the die -0.49 mm.

Mindlin [0/45], 8 cells, 10 N (rerun, 8448 steps, 163 s, load 5-8): to the end, KE / W 0.1012
at t = 0.0441 s (above 0.1 over 0.3 % of the judged time), the holder 9.70 N over the last
tenth and 23.9 mm up at the end, as before. At t = 0.044 s the run's 11.5 N mm of kinetic
energy are the holder's 7.5 (rising at 0.39 m/s) and the plies' 3.6: the holder's kinetic
energy alone 0.065 of W at most (t = 0.0435 s), the plies' 0.052 (t = 0.0685 s). The check
fails by 1 % on the two together, the holder's the larger.

Mindlin [0/45], 8 cells, 20 N (8444 steps, 150 s, load 3-8): now to the end (an earlier run of
the study stopped at 83.4 % of the stroke), the holder 19.79 N over the last tenth (within 5 %)
and 11.7 mm up at the end, but KE / W 0.121 at t = 0.0594 s (above 0.1 over 1.2 % of the judged
time). There the peak is the directors': at t = 0.059 s the run's 44.7 N mm of kinetic energy
are the rotation's 24.2 (0.061 of W), the plies' translations' 17.2 (0.044) and the holder's
3.3 (0.008); half a millisecond later the rotation's 16.7 and the translations' 25.7, the
flange snapping. The rotary inertia the rotation carries is the Mindlin shell's scaled one
(docs/theory.md §6.2, B2: j = kappa L_e^2 / 16, 16 mm^2 on the 0-deg ply's cells against the
physical h^2 / 12 = 0.0075 mm^2), which keeps the membrane's step but lends the directors'
turns a kinetic energy the check counts: not changed here (the physical inertia's step, 2 h
sqrt(rho / (6 kappa G13)) = 0.9 us, is 1/13 of this run's). Rms of shear - net 2.94 and 4.56
deg (20 and 28 cells in the die), draw-in of the edge middle 24.3 and 12.4 mm (corner 21.3 and
26.8), 9 and 9 crests up to 26.5 and 11.8 mm, the top ply's least radial gap in the die +0.38
mm, punch force 282 N. At 10 N and 8 cells the directors' share was 0.003 of W at the peak (t =
0.044 s), at Mindlin [0/90]'s 0.022-0.029."""

from __future__ import annotations

from typing import Any

import numpy as np

from elements.layup import Layup

__all__ = ["kinetic_shares", "ply_masses"]


def ply_masses(layup: Layup) -> np.ndarray:
    """(n,) the plies' lumped nodal masses, t: a third of each cell's rho_A A0 at each corner
    (the lumped mass of both kinematics, docs/theory.md §1.6), the reference areas A0 of the
    layup's mesh."""
    points, triangles = layup.mesh.points, layup.mesh.triangles
    edges = points[triangles[:, 1:]] - points[triangles[:, :1]]
    area = 0.5 * np.linalg.norm(np.cross(edges[:, 0], edges[:, 1]), axis=1)
    share = np.repeat(layup.fabric.areal_density * area / 3.0, 3)
    return np.bincount(triangles.ravel(), weights=share, minlength=layup.mesh.n_nodes)


def kinetic_shares(
    layup: Layup, result: Any, holder_mass: float, holder: int = 0
) -> dict[str, np.ndarray]:
    """The translational kinetic energies of each ply and of the holder at each frame.

    Parameters
    ----------
    layup : Layup
        The layup (its mesh's nodes first in the model, the tools' rigid nodes after them).
    result : femcore.results.Result
        The run's frames (``velocities`` (N, 3), mm/s, N >= the mesh's nodes).
    holder_mass : float
        The holder's mass, t.
    holder : int
        The holder's index among the model's rigid nodes (0: the first force-driven tool).

    Returns
    -------
    dict
        "time" (f,) s; "plies" (f, plies) N mm, 1/2 sum m v^2 over each ply's nodes (the
        directors' rotary part left out); "holder" (f,) N mm, 1/2 m_h v_h^2.
    """
    mass = ply_masses(layup)
    n = layup.mesh.n_nodes
    times, plies, lifted = [], [], []
    for frame in result.frames:
        v = np.asarray(frame.velocities)
        energy = 0.5 * mass * np.sum(v[:n] ** 2, axis=1)
        plies.append([float(energy[nodes].sum()) for nodes in layup.ply_nodes])
        lifted.append(0.5 * holder_mass * float(np.sum(v[n + holder] ** 2)))
        times.append(frame.time)
    return {"time": np.array(times), "plies": np.array(plies), "holder": np.array(lifted)}
