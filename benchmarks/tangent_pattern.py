"""What a new sparsity pattern of K_ff costs before the numeric work: the assembler's map
(femcore.assembly.FreeTangentAssembler._build) and the linear solver's upper-triangle plan
(solvers.linear._UpperPlan.of), each against the way it was done before (the reference pass,
kept here): the map by np.unique over every entry of every part, the plan by a search of each
entry's mirror among the sorted keys.

The model: plies-bai-5.1's stack at the default resolution (cases/bai-5.1.toml, 30 x 2 cells,
8 Mindlin plies, 744 nodes, 3720 unknowns free) with, on each of the 7 interfaces, one contact
part of 6-node blocks per upper-ply triangle (its 3 nodes and those of a triangle of the ply
below: the shape of elements/ply_block_tangent.py's tangent with every point touching). The ply
contact changes this pattern at almost every Newton iteration (benchmarks/report.py, "The
plies' increments cut once": 989 new patterns in 1076 tangents of the 8-ply run). Prints the
CPU time of each pass (best of the repeats), and whether the two give the same arrays.

Measured (one thread, CPU, 2 cores shared with other jobs, load 12.2-12.5): the map of
972 000 entries (3528 unknowns free) 94.2 ms by np.unique -> 32.3 ms per node pair; the plan
of 275 790 entries: the mirrors' search alone 6.9 ms, the whole plan by the transpose 3.0 ms
(the whole plan before 18.7 ms -> 8.1 ms in another timing at load 15); the same arrays to the
bit. The parts' places then gathered from the pair tables by one flat index for both K_ff and
K_fp (where three broadcast index arrays were taken twice): the map 30.8-32.2 -> 23.3-24.4 ms
(np.unique 85-87 ms; load 4.7-6.9, the two versions alternated). A profile of the plies run
of plies-bai-5.1 at the default resolution (code before; cProfile, wall 604 s at load 14-16
for 136 s of CPU) put 27 % of the solve in the map's rebuilds (755 of them) and 4 % in the
plan's. That run and the two ply cases before / after: benchmarks/report.py.

Then each new pattern's passes compiled against their numpy references, in the same run (the
same arrays, checked): the map's build (femcore/tangent_pattern.py ``pattern``: a counting
sort of the pairs by column node, then one pass over them; the parts keep each node pair's
pair and the assembly reads the pairs' tables, where numpy's build, the one before, listed
each entry's place) against ``pattern_numpy`` with the places and the flat map it made; the
upper plan (``_UpperPlan.of`` against ``of_numpy``); the band plan of the symmetrised upper
triangle (solvers.band.BandPlan, compiled against ``compiled=False``; reverse Cuthill-McKee
is scipy's either way). Measured (one thread, CPU, best of 9, load 1.8-4.2, the machine
shared): the map 28.4-30.4 ms -> 2.5-3.3 ms (9-11 x), the upper plan 2.4-2.7 -> 1.3 ms, the
band plan (139 659 entries) 4.5 -> 2.4 ms. The plies-bai-5.1 case's profile before (cProfile,
its 1167 tangents): 304 builds of the map, 10.7 s of 52 s profiled; after, 1.5 s (the
table-reading assembly not yet in), the upper and band plans 1.06 and 1.48 s. The case's CPU
side by side: benchmarks/report.py, or the validation command in each tree.

Run: python benchmarks/tangent_pattern.py [--repeats 5]
"""

from __future__ import annotations

import argparse
import os
import sys
import time
from pathlib import Path

import numpy as np
import scipy.sparse as sp

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # this tree's packages

from femcore.assembly import (  # noqa: E402
    CellTangent,
    FreeTangentAssembler,
    _components,
    _split,
    entry_slots,
)
from fibreshell.plies import ply_stack, stack_model  # noqa: E402
from solvers.band import BandPlan  # noqa: E402
from solvers.linear import _UpperPlan  # noqa: E402
from validation.cases.plies_bai_5_1 import BEFORE_STALL_RULE, CELLS, FILE, PLIES  # noqa: E402
from validation.ground_truth import _case  # noqa: E402


def reference_map(assemble: FreeTangentAssembler, parts: list[CellTangent]):
    """(K_ff's rows, indptr, each entry's place in K_ff) by np.unique over every entry, as
    FreeTangentAssembler._build did before."""
    rows, cols = [], []
    for part in parts:
        r, c = entry_slots(part.nodes, _components(part))
        rows.append(r)
        cols.append(c)
    rows_all, cols_all = np.concatenate(rows), np.concatenate(cols)
    r_f, c_f = assemble._position[rows_all], assemble._position[cols_all]
    ff = (r_f >= 0) & (c_f >= 0)
    keys, places = np.unique(c_f[ff] * assemble.n_free + r_f[ff], return_inverse=True)
    columns, ff_rows = np.divmod(keys, assemble.n_free)
    return ff_rows, np.searchsorted(columns, np.arange(assemble.n_free + 1)), places


def reference_mirrors(k: sp.csc_matrix) -> np.ndarray:
    """Each entry's mirror by a search among the sorted keys, as _UpperPlan.of did before."""
    n = k.shape[0]
    columns = np.repeat(np.arange(n), np.diff(k.indptr))
    keys = columns.astype(np.int64) * n + k.indices
    return np.searchsorted(keys, k.indices.astype(np.int64) * n + columns)


def best(call, repeats: int) -> float:
    times = []
    for _ in range(repeats):
        start = time.process_time()
        call()
        times.append(time.process_time() - start)
    return min(times)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=5)
    args = parser.parse_args()
    print(f"load before: {os.getloadavg()[0]:.1f}")
    case = _case(FILE, CELLS["default"], {"solver": BEFORE_STALL_RULE})
    stack = ply_stack(case, PLIES["default"])
    model = stack_model(case, stack).compile()
    state = model.initial_state()
    plies, _ = _split(model.tangent_parts(state, list(range(stack.count)), False))
    rng = np.random.default_rng(0)
    contact = []
    for k in range(stack.count - 1):  # each upper triangle on a triangle of the ply below
        lower = np.roll(plies[k + 1].nodes, int(rng.integers(1, 4)), axis=0)
        nodes = np.concatenate([plies[k].nodes, lower], axis=1)
        contact.append(CellTangent(nodes, rng.standard_normal((len(nodes), 6, 6, 6, 6))))
    parts = plies + contact
    assemble = FreeTangentAssembler(model.dofs)
    entries = sum(entry_slots(p.nodes, _components(p))[0].size for p in parts)
    assemble._build(parts, [])  # the compiled pass's first call compiles or loads it
    compiled = best(lambda: assemble._build(parts, [], compiled=True), args.repeats)
    reference = FreeTangentAssembler(model.dofs)

    def numpy_build() -> None:
        """The build before: numpy's pattern, each entry's place and the flat map."""
        reference._build(parts, [], compiled=False)
        assert reference._flat_map is not None  # made at its first use

    new = best(numpy_build, args.repeats)
    same = all(
        np.array_equal(getattr(assemble, name), getattr(reference, name))
        for name in ("ff_indptr", "ff_rows", "fp_indptr", "fp_rows", "fp_cols")
    ) and all(
        np.array_equal(a[0], b[0]) and np.array_equal(a[1], b[1])
        for a, b in zip(assemble._destinations, reference._destinations)
    )
    print(f"the map's build, numpy per node pair {1e3 * new:.1f} ms, compiled {1e3 * compiled:.1f}")
    print(f"  ms ({new / compiled:.1f} x); the same arrays and places: {same}")
    old = best(lambda: reference_map(assemble, parts), args.repeats)
    ff_rows, indptr, places = reference_map(assemble, parts)
    same = (
        np.array_equal(ff_rows, assemble.ff_rows)
        and np.array_equal(indptr, assemble.ff_indptr)
        and np.array_equal(places, assemble.ff_map)
    )
    print(f"map of {entries} entries ({assemble.n_free} unknowns): np.unique {1e3 * old:.1f} ms,")
    print(f"  numpy per node pair {1e3 * new:.1f} ms; the same K_ff structure and places: {same}")
    k = sp.csc_matrix(
        (rng.standard_normal(assemble.ff_rows.size), assemble.ff_rows, assemble.ff_indptr),
        shape=(assemble.n_free, assemble.n_free),
    )
    k.has_sorted_indices = True
    _UpperPlan.of(k)  # compiles or loads the pass
    compiled = best(lambda: _UpperPlan.of(k), args.repeats)
    new = best(lambda: _UpperPlan.of_numpy(k), args.repeats)
    old = best(lambda: reference_mirrors(k), args.repeats)
    plan, reference_plan = _UpperPlan.of(k), _UpperPlan.of_numpy(k)
    same = plan is not None and np.array_equal(plan.transposed, reference_mirrors(k))
    print(f"upper plan of {k.nnz} entries: mirrors searched {1e3 * old:.1f} ms (search alone),")
    print(f"  the plan by the transpose {1e3 * new:.1f} ms (whole); the same mirrors: {same}")
    same = reference_plan is not None and all(
        np.array_equal(getattr(plan, name), getattr(reference_plan, name))
        for name in ("transposed", "upper", "indptr", "indices", "columns", "diagonal")
    )
    print(f"  the plan compiled {1e3 * compiled:.1f} ms ({new / compiled:.1f} x); the same: {same}")
    # The band plan of the symmetrised upper triangle (solvers.band.BandPlan: the ordering's
    # pattern, reverse Cuthill-McKee, the band layout) compiled against scipy's and numpy's.
    _, upper = plan.split(k.data)
    BandPlan(upper)  # compiles or loads the passes
    compiled = best(lambda: BandPlan(upper), args.repeats)
    new = best(lambda: BandPlan(upper, compiled=False), args.repeats)
    band, reference_band = BandPlan(upper), BandPlan(upper, compiled=False)
    same = band.bandwidth == reference_band.bandwidth and all(
        np.array_equal(getattr(band, name), getattr(reference_band, name))
        for name in ("perm", "slots", "reaches")
    )
    print(f"band plan of {upper.nnz} entries: numpy {1e3 * new:.1f} ms, compiled")
    print(f"  {1e3 * compiled:.1f} ms ({new / compiled:.1f} x); the same: {same}")
    print(f"load after: {os.getloadavg()[0]:.1f}")


if __name__ == "__main__":
    main()
