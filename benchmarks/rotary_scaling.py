"""The Mindlin cells' critical step with B2's closed-form rotary inertia and with the
element rule (docs/theory.md §6.2 B2, elements/rotary_scaling.py), against the step with the
rotations held (j x 1e4): the two-ply hemisphere's ply as ElasticShell.equivalent and as a
fabric section, and a 1-mm aluminium sheet, on 25-mm right triangles (the hemisphere-plies
case's cells), and the time the rule takes at bind.

    python benchmarks/rotary_scaling.py

The validation's two hemisphere cases (``python -m validation --cases
hemisphere-plies,hemisphere-forming --jobs 1``, one thread, nice 5, load 4-9), main 5ccbb7d
beside this code with "element" taken for their Mindlin plies (ElasticShell.equivalent; not
their default, which keeps the closed form and every number of results.json to the bit):
all 29 checks pass both ways; Mindlin steps hemisphere-forming 46967 -> 23655, plies [0/90]
8429 -> 4510, [0/45] 8991 -> 4673 (the cases' steps 60807 -> 37495 and 26376 -> 18139);
but the Mindlin plies' results move far beyond a scatter: [0/90] ply 1 cells in the die 20
-> 9, rms shear - net 3.14 -> 3.95 deg, corner draw-in 17.0 -> 13.4 mm, the plies' largest
slip 2.5 -> 23.8 mm, largest KE / W 0.115 -> 0.169 (its rotational part 0.057 -> 0.107);
[0/45] ply 1 rms 3.02 -> 1.78 deg, punch force 289 -> 123 N; hemisphere-forming's Mindlin
draw-ins within 1.1 %, its rms shear - net 2.09 -> 1.88 deg, punch force 78.3 -> 56.4 N.
Mostly not through j itself (benchmarks/mindlin_rotary_inertia.py): the tool contacts'
penalty then followed the model's step, softer as j lengthened it, and the two-ply [0/90]
Mindlin run at its pace then was not quasi-static; with the penalties held and the stroke
slowed x4, j x4 gave the closed form's slow answer. Since, the penalty is sized on the step at
the closed j whatever j a shell is given (docs/theory.md §6.2, "The penalty's step"), and the
[0/90] Mindlin stroke is slowed x2; these figures are of the code before.

Measured (one thread): the step over the held step, closed form / element rule, and the
rule's factor on j: equivalent 0.465 / 0.950 (x8.26, j 16.3 -> 134.4 mm^2), fabric section
0.510 / 0.950 (x5.66), aluminium 0.597 / 0.950 (x3.02). The rotations' block's largest
omega^2 over the translations': 3.99 / 0.48, 3.33 / 0.59, 2.54 / 0.84. Binding 8 x 8 / 32 x 32
structured cells (two reference shapes): 0.003 / 0.009 s with the rule, 0.002 / 0.007 s without
(load 9.2); an unstructured mesh solves one bisection (13 eigenproblems) per cell.
"""

from __future__ import annotations

import os
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # run from anywhere, no install

from elements import MindlinShell  # noqa: E402
from femcore import Mesh, Model  # noqa: E402
from materials import ElasticShell, Fabric  # noqa: E402

PLY = Fabric(thickness=0.3, areal_density=2.85e-10, tension=60.0, shear=0.2, bending=0.375)


def block(material, scaling: str, cells: int = 2, size: float = 25.0):
    """The bound Mindlin block of a ``cells`` x ``cells`` square of ``size``-mm cells."""
    mesh = Mesh.rectangle(cells * size, cells * size, nx=cells, ny=cells)
    model = Model(mesh)
    model.add(MindlinShell(material, rotary_scaling=scaling))
    return next(p for p in model.compile().parts if hasattr(p, "rotary_factor"))


def first_step(shell, factor: float = 1.0) -> float:
    """The first cell's element step 2 / omega_max, s, with j times ``factor``."""
    x0, v0 = shell._reference_cells()
    own = shell.rotary_factor.copy()
    try:
        shell.rotary_factor = own * factor
        return float(2.0 / np.sqrt(shell.element_omega2(x0[:1], v0[:1], np.arange(1))[0]))
    finally:
        shell.rotary_factor = own


def main() -> None:
    print(f"load: {os.getloadavg()}")
    sections = {
        "equivalent": ElasticShell.equivalent(PLY),
        "fabric": PLY,
        "aluminium": ElasticShell(E=70000.0, nu=0.33, thickness=1.0, density=2.7e-9),
    }
    for name, material in sections.items():
        closed, element = block(material, "closed"), block(material, "element")
        held = first_step(closed, 1e4)
        j_closed, j_element = closed.rotary_factor[0], element.rotary_factor[0]
        print(
            f"{name}: held step {held:.4e} s; closed form {first_step(closed) / held:.3f}, "
            f"element rule {first_step(element) / held:.3f} of it; j {j_closed:.2f} -> "
            f"{j_element:.2f} mm^2 (x{j_element / j_closed:.2f})"
        )
    for cells in (8, 32):  # the rule's cost at bind, congruent cells sharing one problem
        start = time.process_time()
        block(sections["equivalent"], "element", cells)
        rule = time.process_time() - start
        start = time.process_time()
        block(sections["equivalent"], "closed", cells)
        closed_s = time.process_time() - start
        print(f"bind {cells}x{cells}: element {rule:.3f} s, closed {closed_s:.3f} s")


if __name__ == "__main__":
    main()
