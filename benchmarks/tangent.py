"""Speed of the fibrous shell's tangent and of its assembly, against one internal force.

Two models, each at a randomly deformed state (nodes moved, directors tilted):

1. the default model of validation case bai-6.1.2 (91 nodes, 144 triangles);
2. a 200 x 100 mm ``Mesh.rectangle`` of 40 x 25 cells (2000 triangles) of ``FibrousShell``
   (G986 stack of Bai Table 1), clamped along x = 0.

For each: the time of one internal force, of the element tangent (``tangent_parts``) by the
reference implementation below (one central difference of the cells' gradient per unknown,
sparse products by scipy, cell-local second derivatives by ``local_tangent``) and by the
block's own, and of the assembly into K_ff, K_fp with the SparseTangent transformed by scipy
(T^T K T, then sliced) and by ``FreeTangentAssembler``. Best of ``--repeats`` runs,
interleaved. Agreement: max |K_new - K_reference| / max |K_reference| of the generalised
tangents, next to the reference's own scatter (the same differences with a 4 x larger step).

``--compiled``: the compiled cell Hessians (elements/fibrous/hessian_kernels.py) against the
numpy ones they replaced, on the sheet of benchmarks/fibrous_shell.py sagged into a bowl
(``bowl``) at ``--sizes`` triangles: CPU time of the block's tangent before
(``numpy_hessian_tangent``: numpy cell Hessians, normal-share Jacobians and bincounts; the
other pieces compiled, as the block formed it) and now, and of the explicit solver's
assembled Gershgorin bound (``assembled_stable_dt``) before (the sparse part through scipy's
T^T K T) and now; the internal force is the reference pass, timed in the same rounds.
Measured on this 2-core machine (one thread, NUMBA_NUM_THREADS=1, CPU time, best of 3,
interleaved, 1-minute load 9.5), the Hessians formed and summed 8192 cells at a time:

    968 triangles:   tangent  50.8 -> 20.0 ms (x2.5),  bound  108.6 -> 28.0 ms (x3.9),
                     internal force 0.7 ms
    20000 triangles: tangent 1210 -> 417 ms (x2.9),    bound 2694 -> 651 ms (x4.1),
                     internal force 10.7 ms
    max |K_now - K_before| / max |K_before| 3.7e-16 and 3.3e-16; the stable steps equal.

(An earlier run, all cells' Hessians held at once, load 9.3-9.5: 53.0 -> 20.9 and
1498 -> 477 ms, bounds 112 -> 29 and 3115 -> 747 ms.)

Where the 477 ms of the 20k tangent went in that run (CPU, one thread, load 9.5, parts
timed apart): the cell Hessians 182 ms (9 us a cell), J^T H J 122 ms, the bending (its
material part numpy) 87 ms, the node-pair sums of the Hessians 28 ms, the normal-pull
stiffness 24 ms, the normal-share Jacobians and their sums 9 ms.

Run from the project root:

    python benchmarks/tangent.py
    python benchmarks/tangent.py --repeats 7
    python benchmarks/tangent.py --compiled --sizes 1000,20000 --repeats 3
"""

from __future__ import annotations

import argparse
import platform
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # run from anywhere, no install

import numpy as np  # noqa: E402
import scipy.sparse as sp  # noqa: E402

from elements import FibrousShell  # noqa: E402
from elements.base import local_tangent  # noqa: E402
from elements.fibrous import FibrousShellBlock, bending, geometry, tangent  # noqa: E402
from elements.fibrous.bending import side_geometry  # noqa: E402
from elements.fibrous.geometry import corner_normal_pull, corner_normals  # noqa: E402
from femcore import Mesh, Model  # noqa: E402
from femcore.assembly import (  # noqa: E402
    CellTangent,
    FreeTangentAssembler,
    SparseTangent,
    generalised_sparse,
    tangent_matrix,
)
from femcore.rotation import rotate_about  # noqa: E402
from materials import presets  # noqa: E402

__all__ = ["main", "reference_tangent"]


# ---------------------------------------------------------------------- reference
def _reference_membrane(block: FibrousShellBlock, state, step: float, scale: float = 1.0):
    """Tension + shear stiffness with nodal normals from central differences of
    ``tangent.cell_gradient``, one unknown at a time (steps times ``scale``), as a scipy matrix."""
    n, conn = block.n_nodes, block.connectivity
    x, v = state.positions[conn], state.directors[conn]
    sums = geometry.normal_sums(block, state.positions)[conn]
    sum_step = scale * 1e-6 * np.linalg.norm(sums, axis=-1)
    m = len(conn)
    hessian = np.empty((m, 3, 9, 3, 9))
    for node in range(3):
        for comp in range(9):
            plus_x, minus_x, plus_v, minus_v, plus_s, minus_s = x, x, v, v, sums, sums
            if comp < 3:
                h: float | np.ndarray = scale * step
                plus_x, minus_x = x.copy(), x.copy()
                plus_x[:, node, comp] += h
                minus_x[:, node, comp] -= h
            elif comp < 6:
                h = scale * 1e-6
                psi = np.zeros((m, 3))
                psi[:, comp - 3] = h
                plus_v, minus_v = v.copy(), v.copy()
                plus_v[:, node] = rotate_about(v[:, node], psi)
                minus_v[:, node] = rotate_about(v[:, node], -psi)
            else:
                h = sum_step[:, node, None, None]
                plus_s, minus_s = sums.copy(), sums.copy()
                plus_s[:, node, comp - 6] += sum_step[:, node]
                minus_s[:, node, comp - 6] -= sum_step[:, node]
            difference = tangent.cell_gradient(
                block, plus_x, plus_v, plus_s
            ) - tangent.cell_gradient(block, minus_x, minus_v, minus_s)
            hessian[:, :, :, node, comp] = difference / (2.0 * h)
    index = (9 * conn)[:, :, None] + np.arange(9)
    shape = (m, 3, 9, 3, 9)
    h_ext = sp.csr_matrix(
        (
            hessian.ravel(),
            (
                np.broadcast_to(index[:, :, :, None, None], shape).ravel(),
                np.broadcast_to(index[:, None, None], shape).ravel(),
            ),
        ),
        shape=(9 * n, 9 * n),
    )
    _, ds_dx = corner_normals(x, jacobian=True)
    ident_rows = (9 * np.arange(n))[:, None] + np.arange(6)
    ident_cols = (6 * np.arange(n))[:, None] + np.arange(6)
    shape_j = (m, 3, 3, 3, 3)
    s_rows = np.broadcast_to(
        ((9 * conn)[:, :, None] + 6 + np.arange(3))[:, :, :, None, None], shape_j
    )
    s_cols = np.broadcast_to(((6 * conn)[:, :, None] + np.arange(3))[:, None, None], shape_j)
    values = (ds_dx * ~block.wall_nodes[conn][:, :, None, None, None]).ravel()
    jac = sp.csr_matrix(
        (
            np.concatenate([np.ones(ident_rows.size), values]),
            (
                np.concatenate([ident_rows.ravel(), s_rows.ravel()]),
                np.concatenate([ident_cols.ravel(), s_cols.ravel()]),
            ),
        ),
        shape=(9 * n, 6 * n),
    )
    gradient = tangent.cell_gradient(block, x, v, sums)
    pull = geometry.free_sums(block, block.scatter.vectors(gradient[..., 6:]))[conn]
    blocks = local_tangent(
        lambda xx, _: (corner_normal_pull(xx, pull), None), x, None, scale * step
    )
    node_index = (6 * conn)[:, :, None] + np.arange(3)
    second = sp.csr_matrix(
        (
            blocks.ravel(),
            (
                np.broadcast_to(node_index[:, :, :, None, None], shape_j).ravel(),
                np.broadcast_to(node_index[:, None, None], shape_j).ravel(),
            ),
        ),
        shape=(6 * n, 6 * n),
    )
    return SparseTangent((jac.T @ h_ext @ jac + second).tocsr())


def reference_tangent(block: FibrousShellBlock, state, scale: float = 1.0) -> list:
    """The tangent parts of a FibrousShell block with nodal normals by the reference
    implementation: central differences one unknown at a time (steps times ``scale``)."""
    step = 1e-6 * float(np.sqrt(np.median(block.reference_area)))
    bend = bending.geometry(block, state.positions)
    chi, coefficients = bending.curvatures(block, bend)
    slopes = bending.moments(block, chi, slope=True)
    share = bend["gradient"][..., None] * bend["normal"][:, None, None, :]
    across_share = np.where(
        block.interior_side[..., None, None], share[block.across_cell, block.across_side], 0.0
    )
    m = len(block.cell_ids)
    own = -np.einsum("mas,mskj->makj", coefficients, share)
    across = -coefficients[..., None, None] * across_share[:, None]
    g = np.concatenate([own, across.reshape(m, 2, 9, 3)], axis=2)
    nodes = np.concatenate(
        [block.connectivity, block.connectivity[block.across_cell].reshape(m, 9)], axis=1
    )
    weight = block.reference_area[:, None] * slopes
    material = np.einsum("ma,maki,malj->mkilj", weight, g, g)
    side_moment = _side_moments(block, state)

    def share_forces(x, _):
        sides = side_geometry(x)
        w = np.matmul(side_moment[:, None, :], sides["gradient"])[:, 0]
        return w[..., None] * sides["normal"][:, None, :], None

    x = state.positions[block.connectivity]
    geometric = local_tangent(share_forces, x, None, scale * step)
    return [
        _reference_membrane(block, state, step, scale),
        CellTangent(nodes, material),
        CellTangent(block.connectivity, geometric),
    ]


def _side_moments(block: FibrousShellBlock, state) -> np.ndarray:
    """mu_s (m, 3) of the bending forces, as bending.py ``tangent`` holds them."""
    bend = bending.geometry(block, state.positions)
    chi, coefficients = bending.curvatures(block, bend)
    moments = bending.moments(block, chi)
    own = -block.reference_area[:, None] * np.matmul(moments[:, None, :], coefficients)[:, 0]
    across = np.where(block.interior_side, own[block.across_cell, block.across_side], 0.0)
    return own + across


def scipy_assembly(assembler: FreeTangentAssembler, parts: list, frames):
    """(K_ff, K_fp) with the cell parts through ``assembler`` and each SparseTangent
    transformed as T^T K T by scipy products, then sliced and added."""
    cells = [p for p in parts if isinstance(p, CellTangent)]
    k_ff, k_fp = assembler(cells, frames)
    dofs = assembler.dofs
    maps = dofs.node_maps(frames)
    for part in parts:
        if isinstance(part, SparseTangent):
            k = generalised_sparse(part, maps)[dofs.free_slots]
            k_ff = (k_ff + k[:, dofs.free_slots]).tocsc()
            k_fp = (k_fp + k[:, dofs.prescribed_slots]).tocsr()
    return k_ff, k_fp


# ---------------------------------------------------------------------- models
def bai_model():
    from validation import specimens
    from validation.cases import bai_6_1_2

    spec = bai_6_1_2.SPEC
    specimen = spec.make_specimen(spec.cells["default"])
    return specimens.build(specimen, "fibrous", spec.fabric, spec.displacement)


def sheet_model():
    mesh = Mesh.rectangle(200.0, 100.0, nx=40, ny=25)
    model = Model(mesh)
    model.add(FibrousShell(presets.g986_stack(), clamped="left"))
    model.fix(mesh.nodes("left"))
    return model


def deformed(compiled, seed: int = 0):
    """The initial state with every node moved by ~0.3 mm and every director tilted by
    ~0.05 rad at random."""
    state = compiled.initial_state()
    rng = np.random.default_rng(seed)
    state.positions = state.positions + 0.3 * rng.standard_normal(state.positions.shape)
    state.directors = rotate_about(
        state.directors, 0.05 * rng.standard_normal(state.directors.shape)
    )
    return state


def measure(name: str, model, repeats: int) -> dict:
    compiled = model.compile()
    state = deformed(compiled)
    block = compiled.blocks[0]
    frames = compiled.dofs.frames(state.directors)
    new_assembler = FreeTangentAssembler(compiled.dofs)
    old_assembler = FreeTangentAssembler(compiled.dofs)
    new_parts = compiled.tangent_parts(state, [0])
    old_parts = reference_tangent(block, state)
    best = dict.fromkeys(
        ("force", "old tangent", "new tangent", "old assembly", "new assembly"), 1e9
    )

    def timed(key, call):
        started = time.perf_counter()
        out = call()
        best[key] = min(best[key], time.perf_counter() - started)
        return out

    for _ in range(repeats):
        timed("force", lambda: compiled.internal_force(state))
        timed("old tangent", lambda: reference_tangent(block, state))
        timed("new tangent", lambda: compiled.tangent_parts(state, [0]))
        old_k = timed("old assembly", lambda: scipy_assembly(old_assembler, old_parts, frames))
        new_k = timed("new assembly", lambda: new_assembler(new_parts, frames))
    k_new = tangent_matrix(compiled.dofs, new_parts, frames)
    k_old = tangent_matrix(compiled.dofs, old_parts, frames)
    k_coarse = tangent_matrix(compiled.dofs, reference_tangent(block, state, 4.0), frames)
    largest = abs(k_old).max()
    free_largest = max(abs(old_k[0]).max(), 1e-300)
    return {
        "name": name,
        "nodes": compiled.n_nodes,
        "cells": len(block.connectivity),
        **{key: 1e3 * value for key, value in best.items()},
        "agreement": abs(k_new - k_old).max() / largest,
        "reference scatter": abs(k_coarse - k_old).max() / largest,
        "assembly agreement": abs(new_k[0] - old_k[0]).max() / free_largest,
    }


# ---------------------------------------------------------------------- compiled Hessians
def bowl(triangles: int):
    """The sheet of benchmarks/fibrous_shell.py (5 mm cells, edges pinned, G986 stack) sagged
    into a bowl (z = 1e-3 r^2 mm, r from its centre), its directors left vertical: the
    compiled model and the state."""
    from fibrous_shell import _sheet

    compiled = _sheet(triangles)
    state = compiled.initial_state()
    x = state.positions
    sag = 1e-3 * np.sum((x[:, :2] - x[:, :2].mean(axis=0)) ** 2, axis=1)
    state.positions = x + np.column_stack([np.zeros_like(sag), np.zeros_like(sag), sag])
    return compiled, state


def numpy_hessian_tangent(block: FibrousShellBlock, state) -> list:
    """The tangent as the compiled block formed it before the compiled Hessians: the numpy
    cell Hessians (``tangent.membrane_hessian``), normal-share Jacobians and bincounts, with
    the compiled normal-pull and share stiffnesses and J^T H J."""
    from elements.fibrous import tangent_kernels

    conn = block.connectivity
    x, v = state.positions[conn], state.directors[conn]
    sums = geometry.normal_sums(block, state.positions)[conn]
    pairs = block.corner_pairs()
    hessian, d_sums = tangent.membrane_hessian(block, x, v, sums)
    h_ext = pairs.hessian(hessian)
    _, ds_dx = corner_normals(x, jacobian=True)
    jac = pairs.jacobian(ds_dx * ~block.wall_nodes[conn][:, :, None, None, None])
    pull = geometry.free_sums(block, block.scatter.vectors(d_sums))[conn]
    second = tangent_kernels.normal_pull_stiffness(x, pull)
    if pairs.product is None:
        pairs.product = tangent_kernels.MembraneProduct(pairs.indptr, pairs.indices, block.n_nodes)
    sparse = SparseTangent(pairs.product(h_ext.data, jac.data[:, 6:, :3]))
    bend = bending.tangent(block, state.positions)
    bend.blocks[:, :3, :, :3] += second
    return [sparse, bend]


def compiled_hessians(triangles: int, repeats: int) -> dict:
    """CPU seconds (best of ``repeats``, interleaved) on the bowl of ``triangles``: the block's
    tangent before (``numpy_hessian_tangent``) and now, the assembled Gershgorin bound of
    ``assembled_stable_dt`` before (the sparse part through scipy's T^T K T: handed over as
    CSR) and now, and the internal force (the reference pass); the largest difference of the
    two tangents over the largest entry, and of the two bounds."""
    compiled, state = bowl(triangles)
    block = compiled.blocks[0]
    mass, inertia = compiled.lumped_mass(state)
    own_pieces = block.tangent_pieces

    def as_csr(state, history=None):
        return [
            SparseTangent(p.matrix.tocsr()) if isinstance(p, SparseTangent) else p
            for p in numpy_hessian_tangent(block, state)
        ]

    def bound(pieces):
        block.tangent_pieces = pieces  # type: ignore[method-assign]
        try:
            return compiled.assembled_stable_dt(state, mass, inertia)
        finally:
            block.tangent_pieces = own_pieces  # type: ignore[method-assign]

    calls = {
        "internal force": lambda: compiled.internal_force(state),
        "tangent before": lambda: numpy_hessian_tangent(block, state),
        "tangent now": lambda: block.tangent(state),
        "bound before": lambda: bound(as_csr),
        "bound now": lambda: bound(own_pieces),
    }
    best = dict.fromkeys(calls, np.inf)
    out = {}
    for _ in range(repeats + 1):  # the first round compiles or loads the loops
        for key, call in calls.items():
            started = time.process_time()
            out[key] = call()
            best[key] = min(best[key], time.process_time() - started)
    frames = compiled.dofs.frames(state.directors)
    k_old = tangent_matrix(compiled.dofs, out["tangent before"], frames)
    k_new = tangent_matrix(compiled.dofs, out["tangent now"], frames)
    return {
        "cells": len(block.connectivity),
        **best,
        "agreement": abs(k_new - k_old).max() / abs(k_old).max(),
        "bound agreement": abs(out["bound now"] / out["bound before"] - 1.0),
    }


def print_compiled_hessians(sizes: list[int], repeats: int) -> None:
    import os

    print(f"load {os.getloadavg()[0]:.1f}; CPU time, best of {repeats}, interleaved")
    for triangles in sizes:
        r = compiled_hessians(triangles, repeats)
        force = r["internal force"]
        print(f"\nbowl of {r['cells']} triangles: internal force {1e3 * force:.1f} ms")
        for what in ("tangent", "bound"):
            old, new = r[f"{what} before"], r[f"{what} now"]
            print(
                f"  {what:8s} before {1e3 * old:8.1f} ms ({old / force:5.1f} forces)   "
                f"now {1e3 * new:8.1f} ms ({new / force:5.1f} forces)   x{old / new:.1f}"
            )
        print(
            f"  max |K_now - K_before| / max |K_before| = {r['agreement']:.1e}; "
            f"stable step now / before - 1 = {r['bound agreement']:.1e}"
        )


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=5, help="best of this many runs")
    parser.add_argument(
        "--compiled",
        action="store_true",
        help="the compiled cell Hessians and the Gershgorin bound against their numpy forms",
    )
    parser.add_argument("--sizes", default="1000,20000", help="--compiled: triangles, comma list")
    args = parser.parse_args(argv)
    print(f"python {platform.python_version()}, numpy {np.__version__}, {platform.machine()}")
    if args.compiled:
        print_compiled_hessians([int(size) for size in args.sizes.split(",")], args.repeats)
        return
    for name, model in (("bai-6.1.2 default", bai_model()), ("40 x 25 sheet", sheet_model())):
        r = measure(name, model, args.repeats)
        force = r["force"]
        print(f"\n{r['name']}: {r['nodes']} nodes, {r['cells']} triangles")
        print(f"  internal force        {force:8.1f} ms")
        for what in ("tangent", "assembly"):
            old, new = r[f"old {what}"], r[f"new {what}"]
            print(
                f"  {what:9s} old {old:8.1f} ms ({old / force:5.1f} forces)   "
                f"new {new:8.1f} ms ({new / force:5.1f} forces)   x{old / new:.1f}"
            )
        both_old = r["old tangent"] + r["old assembly"]
        both_new = r["new tangent"] + r["new assembly"]
        print(
            f"  tangent + assembly: old {both_old / force:.1f}, new {both_new / force:.1f} "
            "internal forces"
        )
        print(
            f"  max |K_new - K_ref| / max |K_ref| = {r['agreement']:.1e} (the reference against "
            f"itself with 4 x its steps: {r['reference scatter']:.1e}); assembled K_ff "
            f"{r['assembly agreement']:.1e}"
        )


if __name__ == "__main__":
    main()
