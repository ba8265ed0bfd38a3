"""What each part of the hemisphere forming blank's stable step weighs, and how far a selective
mass scaling could lengthen it: the evidence for choosing how to run the 20k-triangle stroke
in fewer steps.

At states of an unscaled run of the case (validation/cases/hemisphere_forming.py; ``--at``
fractions of the stroke, saved and read again by benchmarks/hemisphere_step_bounds.py
``states``), printed:

* the cells' bound split into its parts at the cell that governs it (docs/theory.md §6.2,
  ``FibrousShellBlock.cell_stable_dt``): the fibres' tension (A1), the in-plane shear (A4) with
  the shear law's largest slope over |gamma| <= 1 rad (the library's) and, beside it, with its
  slope at the cell's current angle, the bending (A3), the nodal normals' margin 1.1; and the
  tools' penalty springs as the solver bounds them (sum over the tools of max k / m,
  ``penalty_frequency_squared``), each as a share of the cells' omega^2;
* ``--eigen`` (dense, so at most some 30 cells): the exact 2 / omega_max of the elements and of
  the elements with every blank node pressed along z by every tool (the springs' worst case),
  with the lumped masses and with the selective mass scaling of Olovsson, Simonsson and
  Unosson (IJNME 63 (2005) 1436) at each ``--beta``: each cell adds beta m_e (I - 1/3 e e^T)
  on each translation, m_e its nodes' share rho_A A0 / 3, so that a cell's rigid translation
  keeps its inertia and only its deformation gets heavier (the rotary inertia scaled by 1 +
  beta, or not: ``--rotary``); and the lowest frequencies of the blank as the tools hold it
  then (the elements and the springs of the nodes touching), with and without the scaling.

    python benchmarks/hemisphere_step_parts.py --cells 100 --at 0.01
    python benchmarks/hemisphere_step_parts.py --cells 20 --at 0.01,0.5,0.9 --eigen
    python benchmarks/hemisphere_step_parts.py --cells 100 --at 0.01 --eigen --sparse --rotary 0

Measured (main c0b0822, one thread; load 5-11, two of these beside each other; the 20-cell
eigen study 190-205 s of CPU a state, the 20k one's about 20 min):

What sets the step. 20k triangles (100 cells), 0.01 of the stroke: the cells' bound 2.853e-6
s (omega^2 4.916e11 1/s^2 at its governing cell), of which the fibres' tension 0.707, the
shear 0.287, the bending 0.006 (each with the nodal normals' margin 1.1 on it); the tools'
springs add 0.311 of the cells' omega^2 (three tools at PENALTY_SHARE 0.1 each, the holder's
share of its tool node besides): 2 / sqrt(cells + springs) 2.491e-6 s, the run's 2.24e-6 s
after the safety 0.9 and the damping. The shear's share comes from the locking law's largest
slope over |gamma| <= 1 rad (``max_slope``: 0.2 + 5 x 2.4 = 12.2 N/mm, 61 times its slope at
gamma = 0, where the blank starts); with each cell's slope at its current angle the cells' bound
would be 3.368e-6 s, 2.812e-6 s with the springs (1.129 times the step). 20 cells, at 0.01 / 0.5
/ 0.9 of the stroke (the largest shear angle 0.0 / 11.3 / 39.6 deg): tension 0.711 / 0.730 /
0.766, shear 0.289 / 0.270 / 0.234, bending 2.4e-4 / 2.3e-4 / 2.0e-4, the springs 0.311 / 0.291
/ 0.252 of the cells' omega^2; the shear's slope at the current angle would lengthen the step
1.130 / 1.123 / 1.083 times. The bending never limits (as docs/theory.md §6.2 A3 says, below
about 0.2 mm cells); the fibres' tension sets the step, the shear's bound second, and the
penalty springs take it down by a further 12-13 %.

Selective mass scaling (Olovsson et al.), the exact 2 / omega_max (s) with the lumped masses,
then with the scaling (times the lumped one in brackets):

* 20 cells, 0.01 of the stroke: the elements 2.051e-5, every node pressed by every tool
  2.051e-5 (at the start the springs do not reach the fibres' in-plane top mode). beta 3:
  the elements 3.870e-5 (x1.887) with the rotary inertia scaled by 1 + beta, 3.553e-5 (x1.732)
  with it kept; pressed 2.612e-5 (x1.273) either way. beta 8 and 15: the elements 5.672e-5 and
  7.465e-5 (x2.765, x3.639) scaled, 3.553e-5 kept (x1.732: the director modes, whose inertia
  is the rotary one, §6.2 A2); pressed 2.612e-5 at every beta.
* 0.5 of the stroke: the elements 2.047e-5, pressed 1.875e-5; beta 3, 8, 15: the elements
  x1.887, x2.765, x3.640 scaled, x1.732 kept; pressed 2.612e-5 (x1.393) at every beta.
* 0.9: the elements 1.818e-5, pressed 1.567e-5; beta 3: the elements x1.880 scaled, x1.803
  kept; pressed 2.612e-5 (x1.666).
* 20k triangles, 0.01 of the stroke (``--sparse --rotary 0``; 197 s of CPU): the elements
  4.103e-6, pressed 4.103e-6; beta 3 and 8, the rotary inertia kept: the elements 7.106e-6
  (x1.732), pressed 5.208e-6 (x1.269) at both.

Why the pressed step stops at 2.612e-5 s: a blank pressed between tools moves as a whole
against their springs, omega^2 = sum k / m, a mode the scaling leaves alone by design (it
keeps each cell's rigid translation at its mass); 2 / sqrt(sum over the tools of max k / m),
the springs' bound the solver adds, is 2.565e-5 s there (0.98 of that exact step: the bound is
tight). So in the solver's own rule, 2 / sqrt(omega_cells^2 / (1 + beta) + springs), the step
at 20 cells and 20k alike would grow 1.53 times at beta 3, 1.76 at 8, 1.88 at 15 and at most
2.05 times (beta without end) at 0.01 of the stroke (2.23 at 0.9, the springs' share
0.252), each still below 0.9 of the exact pressed step above; the
rotary inertia kept, the elements' own exact step grows 1.73-1.80 times at most (the director
modes), which the springs' cap lies below.

What it does to the slow dynamics, the lowest frequencies of the blank as the tools hold it
(the elements and the springs of the nodes touching): 20 cells, 0.5 of the stroke, 9.49,
11.22, 52.2, 71.9, 72.5, 78.0, 80.6 Hz lumped; beta 3 with the rotary inertia kept x1.00,
1.00, 0.83, 0.62, 0.72, 0.92, 0.90; beta 8 x1.00, 1.00, 0.56, 0.42, 0.72, 0.70, 0.68; with the
rotary inertia scaled all of them x1 / sqrt(1 + beta) (0.50, 0.33): those modes are the
directors' (fibre slip) with cell-by-cell translations, none a rigid drape motion. At 0.01
of the stroke: 49.3, 75.5, 75.5, 108, 118 Hz at 20 cells and 49.25, 75.36, 75.36, 108.6, 119.0
at 20k (the same modes, the mesh converged on them); there beta 3 with the rotary inertia
kept gave x1.00, 1.00, 1.00, 0.78, 0.77 at 20 cells, and at 20k x1.000 on all five at beta 3
and 8 (the held blank's three rigid modes, 2e-4 Hz, within 0.8 %): what the scaling weighs is
each cell's deformation, the cells' rotation within a slow mode among it, which shrinks with
the cells. At 0.9 of the stroke the held
blank's tangent has negative eigenvalues (its wrinkles), no low frequency to compare.

So: uniform mass scaling is time scaling by another name (density x s^2 is the stroke in
DURATION / s, the mass-proportional damping apart), and the library's ``mass_scaling_dt``,
which raises the density of the cells below the target, raises every cell of this uniform
blank alike (2.4e-5 s at 20 cells: x3.5, 2.5 times the blank's mass; benchmarks/
hemisphere_forming.py). A selective scaling that keeps the translations' inertia leaves the
20k blank's slow modes where they are (beta 3-8, the rotary inertia kept; the coarse 20-cell
blank's director modes move by up to 0.42-0.62 times) but cannot pass the tools' springs: at
most 2.05 times the step (1.76 at beta 8) with the penalty as it is. The 3-minute stroke:
unscaled, 133.8k steps at 5.4-5.7 ms of the main thread's CPU a step on two threads
(benchmarks/hemisphere_forming.py), 12-13 min; at beta 8, 76k steps plus a linear solve of
the non-diagonal mass at each step (a conjugate gradient on the cells' pattern), 7 min at
least; with time scaling x2 on top (measured safe to 40 cells) 38k steps, 3.5 min at least.
Not implemented: the solve goes into the fused velocity update (solvers/dynamics.py: the
reactions, the kinetic energy and the energy account all take M as a diagonal), and with the
rotary inertia kept the cells' bound would have to stop at the director modes' cap (x1.73 on
the elements alone: a model without tools would otherwise be run past its step).
"""

from __future__ import annotations

import argparse
import math
import os
import sys
import time
from pathlib import Path

import numpy as np
import scipy.linalg as la
import scipy.sparse as sp
from scipy.sparse.linalg import eigsh

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # run from anywhere, no install
sys.path.insert(0, str(Path(__file__).resolve().parent))
os.environ.setdefault("FIBRESHELL_PROGRESS", "0")

from hemisphere_step_bounds import states  # noqa: E402

from elements.fibrous.block import _BENDING_DT_COEFFICIENT  # noqa: E402
from validation.cases import hemisphere_forming as case  # noqa: E402


def parts(compiled, saved: dict) -> dict[str, float]:
    """omega^2 (1/s^2) of each part of the cells' bound at its governing cell, the springs'."""
    state, mass = saved["state"], saved["mass"]
    block = compiled.blocks[0]
    x = state.positions[block.connectivity]
    g1, g2 = x[:, 1] - x[:, 0], x[:, 2] - x[:, 0]
    len1, len2 = np.linalg.norm(g1, axis=1), np.linalg.norm(g2, axis=1)
    cosine = np.abs(np.sum(g1 * g2, axis=1)) / (len1 * len2)
    shortest = np.minimum(len1, len2)
    rho, a0 = block.fabric.areal_density, block.reference_area
    m = rho * a0 / 3.0
    tension = (2.0 + cosine) * block.max_tension_stiffness * a0 / (shortest**2 * m)
    per_slope = 2.0 * a0 * (1 / len1**2 + 1 / len2**2) / m
    shear = block.max_shear_stiffness * per_slope
    # the law's slope at each cell's current angle: gamma = the warp-weft angle's departure
    gamma = np.abs(np.arcsin(np.clip(cosine, 0.0, 1.0)))
    shear_now = block.fabric.shear.slope(gamma) * per_slope
    root = math.sqrt(rho / block.max_bending_stiffness)
    bending = (2.0 / (_BENDING_DT_COEFFICIENT * shortest**2 * root)) ** 2
    margin = 1.1 if block.nodal_normals else 1.0
    total = margin * (tension + shear + bending)
    c = int(np.argmax(total))
    total_now = margin * (tension + shear_now + bending)
    return {
        "cells": float(total[c]),
        "tension": margin * float(tension[c]),
        "shear": margin * float(shear[c]),
        "bending": margin * float(bending[c]),
        "margin": margin,
        "gamma_deg": float(np.degrees(gamma.max())),
        "cells_now": float(total_now.max()),
        "springs": compiled.penalty_frequency_squared(mass, state),
    }


def added_mass(compiled, beta: float, rotary: bool, saved: dict) -> sp.csr_matrix:
    """The selective mass scaling's added mass over all slots (module docstring)."""
    block = compiled.blocks[0]
    conn = block.connectivity
    share = beta * block.fabric.areal_density * block.reference_area / 3.0  # (cells,)
    local = np.eye(3) - 1.0 / 3.0  # (3, 3): I - e e^T / 3
    rows, cols, vals = [], [], []
    for d in range(3):  # each translation, slot 5 n + d
        slots = 5 * conn + d
        rows.append(np.repeat(slots, 3, axis=1).ravel())
        cols.append(np.tile(slots, (1, 3)).ravel())
        vals.append((share[:, None, None] * local[None]).ravel())
    n = compiled.dofs.n_slots
    added = sp.coo_matrix(
        (np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))), shape=(n, n)
    ).tocsr()
    if rotary:
        inertia = np.zeros(n)
        for d in (3, 4):
            inertia[5 * np.arange(compiled.n_nodes) + d] = beta * saved["inertia"]
        added = added + sp.diags(inertia)
    return added


def spectrum(k, m: sp.spmatrix, low: bool, count: int) -> np.ndarray:
    """The lowest 4 x ``count`` eigenvalues of K phi = omega^2 M phi (1/s^2; ``count`` of them
    with ``k`` sparse), or the largest alone, ``k`` dense (an array) or sparse."""
    if isinstance(k, np.ndarray):
        values = la.eigh(k, m.toarray(), eigvals_only=True)
        return values[: count * 4] if low else values[-1:]
    m = sp.csc_matrix(m)
    if low:  # shift-invert below zero: the held blank's rigid modes sit at 0
        sigma = -((2 * np.pi) ** 2)  # (1 Hz)^2 below
        values = eigsh(sp.csc_matrix(k), k=count, M=m, sigma=sigma, which="LM",
                       return_eigenvectors=False)  # fmt: skip
        return np.sort(values)
    return eigsh(sp.csc_matrix(k), k=1, M=m, which="LA", tol=1e-6, return_eigenvectors=False)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cells", type=int, default=100)
    parser.add_argument("--at", default="0.01", help="fractions of the stroke")
    parser.add_argument("--states", default="/tmp", help="where the run's states are kept")
    parser.add_argument("--eigen", action="store_true", help="the exact steps (dense)")
    parser.add_argument("--beta", default="3,8,15", help="the scaling's factors, a list")
    parser.add_argument("--rotary", default="1,0", help="scale the rotary inertia too: 1, 0")
    parser.add_argument("--sparse", action="store_true", help="eigsh, not dense (large)")
    parser.add_argument("--low", type=int, default=8, help="the lowest frequencies printed")
    args = parser.parse_args()
    fractions = [float(f) for f in args.at.split(",")]
    folder = Path(args.states)
    folder.mkdir(parents=True, exist_ok=True)
    saved = states(args.cells, fractions, folder)
    compiled = case.model(args.cells, "fibrous", rim=case.DIE_RIM)[1].compile()
    for fraction, at in saved.items():
        cpu = time.process_time()
        p = parts(compiled, at)
        w = p["cells"]
        print(
            f"{args.cells} cells, {fraction:g} of the stroke (t = {at['state'].time:.4g} s): "
            f"the cells' bound {2 / math.sqrt(w):.4g} s, omega^2 {w:.4g}: tension "
            f"{p['tension'] / w:.3f}, shear {p['shear'] / w:.3f} (the law's largest slope), "
            f"bending {p['bending'] / w:.2e} (margin {p['margin']} included); the springs "
            f"{p['springs'] / w:.3f} of it; the step's rule 2 / sqrt(cells + springs) "
            f"{2 / math.sqrt(w + p['springs']):.4g} s; with the shear law's slope at the "
            f"current angle (largest {p['gamma_deg']:.1f} deg) the cells' bound "
            f"{2 / math.sqrt(p['cells_now']):.4g} s, with the springs "
            f"{2 / math.sqrt(p['cells_now'] + p['springs']):.4g} s",
            flush=True,
        )
        if not args.eigen:
            continue
        dofs = compiled.dofs
        free = dofs.free_slots
        state, mass, inertia = at["state"], at["mass"], at["inertia"]
        lumped = np.column_stack([mass, mass, mass, inertia, inertia]).ravel()
        blocks = list(range(len(compiled.blocks)))
        k_el = compiled.stiffness(state, parts=blocks)
        k_el = 0.5 * (k_el + k_el.T)
        k_all = compiled.stiffness(state)
        k_all = 0.5 * (k_all + k_all.T)
        pressed = np.zeros(dofs.n_slots)
        for interaction in compiled.interactions:
            np.add.at(pressed, 5 * interaction.connectivity[:, 0] + 2, interaction.stiffness)
        matrices = {
            "elements": k_el[free][:, free],
            "all pressed": (k_el + sp.diags(pressed))[free][:, free],
            "touching": k_all[free][:, free],
        }
        if not args.sparse:
            matrices = {name: k.toarray() for name, k in matrices.items()}

        base = sp.diags(lumped).tocsr()
        reference = {
            name: spectrum(k, base[free][:, free], name == "touching", args.low)
            for name, k in matrices.items()
        }
        omega = {name: np.sqrt(np.maximum(v, 0.0)) for name, v in reference.items()}
        print(
            f"  lumped: exact 2 / omega_max, elements {2 / omega['elements'][-1]:.4g} s, "
            f"every node pressed by every tool {2 / omega['all pressed'][-1]:.4g} s; the lowest "
            f"frequencies held as touching (Hz) "
            f"{np.array2string(omega['touching'][: args.low] / (2 * np.pi), precision=4)}",
            flush=True,
        )
        for beta in (float(b) for b in args.beta.split(",")):
            for rotary in (bool(int(r)) for r in args.rotary.split(",")):
                m_sms = (base + added_mass(compiled, beta, rotary, at))[free][:, free]
                scaled = {
                    name: np.sqrt(np.maximum(spectrum(k, m_sms, name == "touching", args.low), 0.0))
                    for name, k in matrices.items()
                }
                with np.errstate(divide="ignore", invalid="ignore"):  # the rigid modes: 0 / 0
                    low = scaled["touching"][: args.low] / omega["touching"][: args.low]
                print(
                    f"  beta {beta:g}, rotary inertia {'scaled' if rotary else 'kept'}: "
                    f"elements {2 / scaled['elements'][-1]:.4g} s "
                    f"(x{omega['elements'][-1] / scaled['elements'][-1]:.3f}), every node "
                    f"pressed {2 / scaled['all pressed'][-1]:.4g} s "
                    f"(x{omega['all pressed'][-1] / scaled['all pressed'][-1]:.3f}); the lowest "
                    f"frequencies over the lumped ones "
                    f"{np.array2string(low, precision=4)}",
                    flush=True,
                )
        print(f"  {time.process_time() - cpu:.0f} s CPU", flush=True)


if __name__ == "__main__":
    main()
