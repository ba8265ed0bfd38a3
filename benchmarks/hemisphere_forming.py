"""Speed of an explicit forming run: the hemisphere forming case of the validation report
(validation/cases/hemisphere_forming.py) with a blank of about 20k triangles.

The blank (200 x 200 mm, fibrous shell, ``--cells`` squares along a side, two triangles each)
is pressed by the rigid spherical punch into the meshed die (elements.RigidSurface) over
``--duration`` s of simulated time. Printed: the wall time, the steps, the step size, the mass
scaling asked (``--mass-scaling-dt``) and the mass it added, the kinetic energy at the end
over the work done (a quasi-static run keeps it small), the time spent in the contact blocks
(their forces, per node and step) against the element's force, and a reference pass over the
same positions (one norm per node), all in one run.

Run from the project root:

    python benchmarks/hemisphere_forming.py                       # 100 x 100 x 2 = 20k
    python benchmarks/hemisphere_forming.py --cells 40 --duration 0.05
"""

from __future__ import annotations

import argparse
import os
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # run from anywhere, no install
os.environ.setdefault("FIBRESHELL_PROGRESS", "0")

from contact_search import best  # noqa: E402

from solvers import CentralDifference  # noqa: E402
from validation.cases import hemisphere_forming as case  # noqa: E402


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cells", type=int, default=100)
    parser.add_argument("--duration", type=float, default=case.DURATION)
    parser.add_argument("--mass-scaling-dt", type=float, default=None)
    parser.add_argument("--safety", type=float, default=0.9, help="the solver's default 0.9")
    args = parser.parse_args()
    mesh, model = case.model(args.cells, "fibrous")
    compiled = model.compile()
    print(f"blank: {mesh.n_triangles} triangles, {mesh.n_nodes} nodes; punch travel "
          f"{case.PUNCH + case.THICKNESS} mm in {args.duration} s")  # fmt: skip

    # The pieces of one step, timed on the reference state: the element, the contacts, a
    # reference pass.
    state = compiled.initial_state()
    shell = list(range(len(compiled.blocks)))  # compiled.parts: the blocks, then the contacts
    contact_blocks = list(range(len(compiled.blocks), len(compiled.parts)))

    compiled.internal_force(state)  # compiles the kernels and fills the tools' caches
    element = best(lambda: compiled.internal_force(state, shell), 20)
    contact = best(lambda: compiled.internal_force(state, contact_blocks), 20)
    reference = best(lambda: np.linalg.norm(state.positions, axis=1), 20)
    n = mesh.n_nodes
    print(f"per step: element force {element * 1e3:.2f} ms ({element / mesh.n_triangles * 1e6:.3f} "
          f"us/triangle), contact forces of {len(contact_blocks)} tools {contact * 1e3:.2f} ms "
          f"({contact / n / len(contact_blocks) * 1e6:.3f} us per node and tool), reference pass "
          f"{reference * 1e3:.3f} ms")  # fmt: skip

    solver = CentralDifference(
        duration=args.duration,
        safety=args.safety,
        damping=case.DAMPING,
        mass_scaling_dt=args.mass_scaling_dt,
        progress=False,
    )
    start = time.perf_counter()
    result = solver.solve(compiled)
    wall = time.perf_counter() - start
    energies = {key: values[-1] for key, values in result.energies.items()}
    ratio = energies["kinetic"] / max(abs(energies["external_work"]), 1e-300)
    print(f"run: {wall:.1f} s wall, {result.steps} steps ({wall / result.steps * 1e3:.2f} ms "
          f"per step), dt {result.info.get('dt', float('nan')):.3g} s, mass scaling "
          f"{args.mass_scaling_dt} (added {result.info.get('added_mass', 0.0):.3g} t on "
          f"{compiled.mass0.sum():.3g} t), kinetic / work at the end {ratio:.3f}, "
          f"converged {result.converged}")  # fmt: skip
    print(f"punch force at the end {result.tool_forces[-1, 1, 2]:.3g} N")


if __name__ == "__main__":
    main()
