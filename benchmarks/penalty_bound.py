"""The explicit step's bound of the contact springs, per node against the rule before, on the
forming cases' models (validation/studies/hemisphere_plies_setup.py, validation/cases/
hemisphere_forming.py) at the start of the stroke.

Printed per model: the elements' omega_e^2 (the smaller step of the cells' and the assembled
bounds, 1/s^2), the springs' omega^2 as a multiple of it by the library's rule (femcore/
compiled.py ``penalty_frequency_squared``: max over the nodes of sum k / m over every spring
of every interaction at the node) and by the reference rule (the sum over the interactions of
each one's largest k / m, the rule before), the critical steps both give and their ratio, and
each interaction's own largest k / m, and each ply pass's springs' CPU a call (the springs held
until the next evaluation, elements/ply_springs.py, against the rule before's springs of the
state alone). For the ply contacts, the lower nodes' figure of the rule before (2 max times
the ratio of node counts) against the one the points facing them at the start give, 2 sum_p
lambda_k k_p (docs/theory.md §6.2, "The penalty springs").

Measured (one thread, load 10-11 from other work): two-ply hemisphere at the start, per node
with the springs held 3.50 / 3.42 omega_e^2 ([0/90] fibrous / Mindlin), 3.32 / 3.47 ([0/45]),
against 2.93 / 2.86 and 2.04 / 2.13 by the rule before: the critical step x0.93 and x0.84 (the
mirrored pass's bottom-ply outline nodes, on the top ply's outline, take the fade's beside
figure they may reach); the springs 0.5-0.6 ms a call (the upper pass) and 0.3-0.4 ms (the
mirrored one) where the rule before's took under 0.1 ms (the facing kept), once in ten steps
of some 3 ms; hemisphere-forming 0.31 both ways.

    python benchmarks/penalty_bound.py
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # this tree's packages

from elements.ply_block import PlyContactBlock
from elements.ply_fade import stiffness_factor
from validation.cases import hemisphere_forming
from validation.studies import hemisphere_plies_setup as plies


def springs_before(interaction, state):
    """The springs the explicit step took before: the ply contact's at ``state`` alone (each
    point's fade factor where it is, every point counted, the lower nodes 2 max of the upper
    ones times the node-count ratio), every other interaction's ``springs_at``."""
    if not isinstance(interaction, PlyContactBlock) or interaction.curved:
        return interaction.springs_at(state)
    facing = interaction.facing(state)
    past = np.any((facing.reach > 0.0) & (facing.weights < 0.0), axis=1)
    reached = np.where(
        facing.touching, np.maximum(interaction.depth, -facing.gap), interaction.depth
    )
    beside = facing.on_growth
    if facing.joined is not None:
        past |= facing.joined
        beside = beside & ~facing.joined
    factor = stiffness_factor(past, beside, reached, interaction.fade_length)
    return interaction._springs(interaction.stiffness * factor)


def reference_rule(compiled, mass: np.ndarray, state) -> float:
    """The rule before: sum over the interactions of max k / m of ``springs_before``, 1/s^2."""
    total = 0.0
    for interaction in compiled.interactions:
        springs = springs_before(interaction, state)
        if springs is not None and len(springs[0]):
            nodes, stiffness = springs
            total += float(np.max(np.asarray(stiffness) / mass[nodes]))
    return total


def lower_nodes_at(block: PlyContactBlock, state) -> tuple[float, float]:
    """(the largest lower-node figure ``springs`` reports, the largest 2 sum_p lambda_k k_p
    over the lower nodes of the points facing them at ``state``), N/mm."""
    facing = block.facing(state)
    corners = block.cells[facing.triangle]  # (P, 3) lower node ids
    weights = np.clip(facing.weights, 0.0, None)
    load = np.bincount(
        corners.ravel(), (2.0 * weights * block.stiffness[:, None]).ravel(), block.n_nodes
    )
    nodes, springs = block.springs()
    lower = np.isin(nodes, block.lower_nodes)
    return float(springs[lower].max()), float(load.max())


def figures(name: str, built) -> None:
    compiled = built.compile()
    state = compiled.initial_state()
    mass, inertia = compiled.lumped_mass(state)
    elements = min(compiled.stable_dt(state), compiled.assembled_stable_dt(state, mass, inertia))
    omega_e2 = (2.0 / elements) ** 2
    per_node = compiled.penalty_frequency_squared(mass, state)
    before = reference_rule(compiled, mass, state)
    step_now = 2.0 / np.sqrt(omega_e2 + per_node)
    step_before = 2.0 / np.sqrt(omega_e2 + before)
    own = []
    for interaction in compiled.interactions:
        nodes, stiffness = interaction.springs_at(state)
        own.append(f"{type(interaction).__name__} {np.max(stiffness / mass[nodes]) / omega_e2:.3f}")
    print(
        f"{name}: omega_e^2 {omega_e2:.4e}; springs per node {per_node / omega_e2:.3f}, "
        f"before {before / omega_e2:.3f} (x omega_e^2); critical step {step_now:.4e} s against "
        f"{step_before:.4e} s: x{step_now / step_before:.4f}"
    )
    print("    each interaction's largest k / m over omega_e^2: " + "; ".join(own))
    for interaction in compiled.interactions:
        if isinstance(interaction, PlyContactBlock):
            times = {}
            for label, call in (("held", interaction.springs_at), ("before", None)):
                best = np.inf
                for _ in range(5):
                    start = time.process_time()
                    if call is None:
                        springs_before(interaction, state)
                    else:
                        call(state)
                    best = min(best, time.process_time() - start)
                times[label] = best
            print(
                f"    ply pass {'lower' if interaction.mirrored else 'upper'} springs: held "
                f"{1e3 * times['held']:.1f} ms a call, before {1e3 * times['before']:.1f} ms "
                "(the facing kept: best of 5, CPU)"
            )
    for interaction in compiled.interactions:
        if isinstance(interaction, PlyContactBlock) and not interaction.curved:
            reported, facing = lower_nodes_at(interaction, state)
            print(
                f"    ply pass {'lower' if interaction.mirrored else 'upper'}: lower nodes "
                f"reported {reported:.4g} N/mm, the facing points' 2 sum lambda k_p {facing:.4g}"
            )


def main() -> None:
    for layup in ("0/90", "0/45"):
        for kinematics in ("fibrous", "mindlin"):
            _, built = plies.model(
                plies.CELLS["coarse"], plies.LAYUPS[layup], kinematics, plies.HOLDER_FORCES[0]
            )
            figures(f"hemisphere-plies {layup} {kinematics}, 8 cells", built)
    for resolution in ("coarse", "default"):
        cells = hemisphere_forming.CELLS[resolution]
        for kinematics in ("fibrous", "mindlin"):
            _, built = hemisphere_forming.model(cells, kinematics, rim=hemisphere_forming.DIE_RIM)
            figures(f"hemisphere-forming {kinematics}, {cells} cells", built)


if __name__ == "__main__":
    main()
