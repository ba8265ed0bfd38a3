"""The Mindlin cells' critical step with B2's closed-form rotary inertia and with the
element rule (docs/theory.md §6.2 B2, elements/rotary_scaling.py), against the step with the
rotations held (j x 1e4): the two-ply hemisphere's ply as ElasticShell.equivalent and as a
fabric section, and a 1-mm aluminium sheet, on 25-mm right triangles (the hemisphere-plies
case's cells), and the time the rule takes at bind.

    python benchmarks/rotary_scaling.py

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
