"""The static tangent's assembly of the fibrous shell's node blocks (its bending's
SparseTangent, 6 x 6 blocks over two rings of cells): numpy's stacked products T_i^T K_ij T_j
of the node maps and a bincount (the reference pass, as before) against the compiled pass
that adds the 66 products per block straight into K_ff and K_fp (femcore.assembly
``_add_node_blocks``), side by side in one process, on the fibrous model of the report's
bai-6.1.1 at the meshes of its observed orders (the corner of 10, 20 and 40 cells), its
tangent at a sheet bent by a rigid rotation of the directors (curved frames); best of REPEATS,
CPU time, one thread.

Measured (2 cores shared with other jobs, load 10; best of 20, CPU): 10 cells (263 free
unknowns, 1584 node blocks) 0.49 -> 0.23 ms, 20 cells (1023, 6849) 2.16 -> 0.80 ms, 40 cells
(4025, 28479) 11.31 -> 7.70 ms a whole assembly of K_ff and K_fp (the cell parts' compiled
pass and the sparse matrices' making included); K_ff the same to 5e-18 of its largest entry
(the sums in another order: numpy's products and bincount against the compiled pass's).
The whole case (validation/cases/bai_6_1_1.py, default: 7 arc-length Static runs, 515
increments), its computation with the numpy pass and with the compiled one in one process:
see benchmarks/report.py's docstring.

Run: python benchmarks/assembly_node_blocks.py
"""

from __future__ import annotations

import os
import time
from dataclasses import replace

import numpy as np

from femcore import assembly
from femcore.assembly import FreeTangentAssembler
from validation import specimens
from validation.cases.bai_6_1_1 import SPEC
from validation.paper.kinematics import ELEMENT

REPEATS = 20


def _time(assemble, parts, frames) -> tuple[float, object]:
    best, out = np.inf, None
    for _ in range(REPEATS):
        started = time.process_time()
        out = assemble(parts, frames)
        best = min(best, time.process_time() - started)
    return best, out


def main() -> None:
    os.environ.setdefault("NUMBA_NUM_THREADS", "1")
    print(f"load {os.getloadavg()[0]:.1f}")
    for cells in (10, 20, 40):
        specimen = SPEC.make_specimen(cells)
        model = specimens.build(
            specimen, ELEMENT["fibrous"], SPEC.fabric, SPEC.displacement, SPEC.calibration
        ).compile()
        state = model.initial_state()
        x = state.positions
        turned = np.column_stack([np.sin(0.01 * x[:, 0]), np.zeros(len(x)), np.cos(0.01 * x[:, 0])])
        state = replace(state, directors=turned)
        own = [i for i in range(len(model.parts))]
        parts = model.tangent_parts(state, own)
        frames = model.dofs.frames(state.directors)
        compiled = assembly._add_node_blocks_compiled
        times = {}
        results = {}
        for label, kernel in (("numpy", None), ("compiled", compiled)):
            assembly._add_node_blocks_compiled = kernel
            assemble = FreeTangentAssembler(model.dofs)
            assemble(parts, frames)  # builds the map (and compiles once)
            times[label], results[label] = _time(assemble, parts, frames)
        assembly._add_node_blocks_compiled = compiled
        k_old, k_new = results["numpy"][0], results["compiled"][0]
        scale = np.abs(k_old.data).max()
        blocks = sum(p.matrix.nnz // 36 for p in parts if isinstance(p, assembly.SparseTangent))
        print(
            f"{cells:3d} cells, {k_old.shape[0]} free unknowns, {blocks} node blocks: "
            f"numpy {1e3 * times['numpy']:.2f} ms, compiled {1e3 * times['compiled']:.2f} ms "
            f"({times['numpy'] / times['compiled']:.1f} x); K_ff differs by "
            f"{np.abs(k_old - k_new).max() / scale:.1e} of its largest entry"
        )
    print(f"load {os.getloadavg()[0]:.1f}")


if __name__ == "__main__":
    main()
