"""Where a step of the report's hemisphere-forming runs goes: one run of the case
(validation/cases/hemisphere_forming.py ``run``, its mesh, tools, time scaling and solver) with
a wall-clock timer round each part of the step (inclusive: a part's time holds the parts it
calls; the timers add about 1 us a call, some 25 us a step), printed in us a step beside the
calls a step, the run's CPU, the machine's load and a reference pass (one norm per node).

    NUMBA_NUM_THREADS=1 python benchmarks/hemisphere_forming_parts.py --kinematics mindlin
    NUMBA_NUM_THREADS=1 python benchmarks/hemisphere_forming_parts.py --kinematics fibrous

Measured (one thread, load 1.1-1.7, the default resolution: 20 cells, 441 blank nodes; the timers'
share included), us a step:

* fibrous, x2 time-scaled, 13840 steps, 736: the element forces about 310 (43 %), the contacts
  199 (the meshed die 149: its candidate lists' upkeep 43, the kept-facet search and the force
  pass the rest; the punch and the holder 25 each), the energy check every 10 steps 19 (its
  contacts' strain energy 16), the stable step and the rotary inertia every 10 steps 27, the
  rotations' pass 30, the tools' work 26, the external loads 19, the rest of the loop some 70.
* Mindlin, 47270 steps, 428: the contacts 168 (the die 123: the lists 22; the punch and the
  holder 22 each), the element forces about 90, the energy check 18 (contacts 16), the
  rotations 28, the tools' work 23, the external loads 17, the stable step and the inertia 13.

The die's kept-facet search (elements/facet_search.py ``closest_facets_kept``) scans every
candidate of a point that moved past its room: over the Mindlin run's second half 182 of the
441 points a call (84 % of them within 1 mm of the die), on the first tenth 24. On the bowl's
facets, 48 rings 0.034 rad apart, the nearest facet and the next are nearly equidistant from a
point pressed on them, so its room is microns and lasts a few steps.
"""

from __future__ import annotations

import argparse
import collections
import os
import sys
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # this tree's packages

import elements.contact as contact
import elements.rigid_surface as rigid_surface
import elements.tool_contact as tool_contact
import femcore.compiled as compiled
import solvers.dynamics as dynamics
import solvers.explicit as explicit
import solvers.step as step
from validation.cases import hemisphere_forming as case
from validation.forming_scaling import TIME_SCALING

TOTAL: collections.defaultdict[str, float] = collections.defaultdict(float)
CALLS: collections.Counter[str] = collections.Counter()

# (owner, attribute, label): the parts timed, the step's first.
PARTS = [
    (explicit, "explicit_step", "the step (explicit_step)"),
    (compiled.CompiledModel, "internal_force", "internal forces (elements and contacts)"),
    (compiled.CompiledModel, "internal_force_and_energy", "internal forces with the energy"),
    (contact.ContactBlock, "add_internal_force", "contact forces (3 tools)"),
    (contact.ContactBlock, "strain_energy", "contacts' strain energy"),
    (tool_contact, "surface_forces", "the meshed die's forces"),
    (rigid_surface.RigidSurface, "_prepared", "the die's candidate lists"),
    (step, "turn", "rotations' pass"),
    (step, "_tool_work", "tools' work"),
    (compiled.CompiledModel, "external_load", "external loads"),
    (explicit.CentralDifference, "_step_size", "stable step"),
    (compiled.CompiledModel, "lumped_mass", "lumped masses (rotary inertia)"),
    (dynamics.EnergyAccount, "record", "energy records"),
]


def timed(function: Callable, label: str) -> Callable:
    """``function`` with its wall time and calls added to TOTAL and CALLS under ``label``."""

    def wrapper(*args: Any, **kwargs: Any) -> Any:
        start = time.perf_counter()
        out = function(*args, **kwargs)
        TOTAL[label] += time.perf_counter() - start
        CALLS[label] += 1
        return out

    return wrapper


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--kinematics", choices=("fibrous", "mindlin"), default="mindlin")
    parser.add_argument("--resolution", choices=tuple(case.CELLS), default="default")
    args = parser.parse_args()
    cells = case.CELLS[args.resolution]
    scaling = TIME_SCALING[args.kinematics][args.resolution]
    case.run(min(case.CELLS.values()), args.kinematics, time_scaling=scaling)  # warm kernels
    for owner, name, label in PARTS:
        setattr(owner, name, timed(getattr(owner, name), label))
    load = os.getloadavg()[0]
    wall, cpu = time.perf_counter(), time.process_time()
    record = case.run(cells, args.kinematics, time_scaling=scaling)
    wall, cpu = time.perf_counter() - wall, time.process_time() - cpu
    steps = CALLS["the step (explicit_step)"]
    positions = record["result"].positions
    start = time.perf_counter()
    for _ in range(1000):
        np.linalg.norm(positions, axis=1)
    reference = (time.perf_counter() - start) / 1000
    print(f"{args.kinematics}, {cells} cells ({len(positions)} nodes), {steps} steps: "
          f"{wall / steps * 1e6:.0f} us a step wall, {cpu:.1f} s CPU; reference pass "
          f"{reference * 1e6:.1f} us; load {load:.1f} -> {os.getloadavg()[0]:.1f}")  # fmt: skip
    for label, total in sorted(TOTAL.items(), key=lambda item: -item[1]):
        print(f"  {label:42s} {total / steps * 1e6:8.1f} us a step  "
              f"{CALLS[label] / steps:5.2f} calls a step")  # fmt: skip


if __name__ == "__main__":
    main()
