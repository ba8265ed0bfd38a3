"""Static (Newton) against DynamicRelaxation on quasi-static problems: wall time, iterations.

1. Bai §6.2.1: the G1151 laminate (200 x 150 x 15 mm, Table 2) with the free triangle
   beyond the clamped diagonal, its corner lowered by 40 mm, under gravity; fibrous shell.
2. A Mindlin cantilever strip of 2560 triangles (200 x 20 x 1 mm, 80 x 16 cells, aluminium,
   nu = 0) under a tip load P L^2 / EI = 3: the tip drops by 0.603 L (elastica).
3. The same strip rolled up into a quarter circle by an end moment: Static with the element's
   own tangent against the coloured finite-difference tangent.

4. The bias-extension test (200 x 100 mm, fibres at +/-45 deg, cells diamonds along, pulled
   30 mm) along its flat branch: the central zone's shear angle against the pin-jointed net,
   for the G986 stack, one G986 ply and a ply with 100 times stiffer fibres. The net is the
   limit of inextensible fibres; with 1200 N/mm the fibres stretch near the clamp corners,
   more so as the mesh resolves the corners and as the shear stiffness grows.
5. A von Mises truss pushed through a soft spring, along the arc length (path with two limit
   points).
6. Peirce's cantilever (validation case heavy-cantilever-nonlinear): the G986 strip whose
   chord dips 41.5 deg under its own weight, 20 x 1 cells, 3 increments, fibrous shell and
   MindlinShell(fabric).

Every Static line gives the wall time, the Newton iterations, the evaluations of the internal
forces, strain energy and tangent, the CPU time of the process (on a shared machine the
fairer figure) and the wall time in units of one internal-force evaluation of the same model
timed in the same run (what a solve costs, whatever the machine's load).

Before and after, side by side: each Static line of 1, 2, 3 and 6 runs with the default
(curved steps and one chord correction per whole step, solvers.newton_curvature) and with
straight steps, no chord and no fibre projection (``curved=False, chords=0,
fibre_projection=False``, the solver before them); line 6 also without the fibre projection
alone. The
straight steps of a turning strip stretch it (a chord is longer than its arc by theta^2 / 2):
the residual is then the membrane force of that stretch (ratio ~1 for two or three
iterations) before the quadratic phase; the Mindlin tangent matches central differences of
the residual to 1e-8, and the watchdog takes every step whole there. Measured on this 2-core
machine (load 6-8, CPU time, one thread), iterations per increment straight -> default:
cantilever 9-9-9-8-8 -> 4-5-5-5-5, roll-up 8-8-8-8 -> 4-5-5-4 (20 cells; 2560 triangles here),
Peirce fibrous 37-21-18 -> 7-14-11, Peirce MindlinShell(fabric) 33-30-22 (one cut) -> 8-12-12;
CPU time, best of 3 (load 7-9): cantilever 1.83 -> 1.79 s, Peirce fibrous 0.88 -> 0.44 s,
Peirce Mindlin 1.35 -> 0.50 s. On the Mindlin cantilever the tangents saved (24 against 43)
are spent on eigen-solves: the step after a curved first step meets an indefinite tangent
(the remainder compresses a part of the strip), whose downhill turn (seek_stable) computes its
lowest modes, 5 shift-invert solves against 2, 2.6 s of 8.2 s profiled; with
seek_stable=False 2.08 -> 1.46 s. The figures of the last run are printed. Measured and not
taken: extrapolating the last increment (``predictor=True``: 9-10-10-8-8 with straight
steps), a residual line search, chord corrections accepted on the residual, smaller rotation
caps, more increments. ``chords=4`` with straight steps (line 2): 5-6-5-5-5 tangents, more
solves.

Where the fibrous increments above 6 come from (heavy cantilever of validation/cases, 20
cells, 30-11-8; Peirce fibrous 7-14-11, MindlinShell(fabric) 8-12-12), measured on this machine
(one thread, load 9-11): not the tangent (the coloured finite-difference tangent gives 26-11-9,
7-20-10 and 8-12-12) and not line-search cuts (every step but a few of the first increment
taken whole). The first Newton step of an increment, curved, leaves a state with residual
ratio ~1 whose tangents then have up to 61-76 negative eigenvalues (Mindlin cantilever: 1-14):
a step of 12 elements from the flat strip (heavy cantilever) or of 1.7 elements turning 0.02
rad (Peirce), whose third-order remainder stretches fibres whose tension stiffness per element,
T L_e^2 / B, is 7800 times the bending's (heavy cantilever, L_e = 7 mm), where the aluminium
strip's membrane is 75 times (12 (L_e / t)^2). Shortening steps did worse: curved steps cut to
a correction of at most 0.1 / 0.2 / 0.3 of the step, heavy 80-44-43 / 49-21-21 / 33-18-8,
Peirce fibrous 9-67-23 / 8-24-53 / 7-17-27, cantilever 5-18-15-8-7 at 0.1; the first step of
each increment cut to the lowest total potential of t = 1, 1/2, 1/4, 1/8 along its curved path:
heavy 40-26-23, Peirce 7-50-30, cantilever 11-11-14-8-7. Without the downhill turns
(seek_stable=False): heavy 38-18-8, Peirce 7-17-14, cantilever 5-6-4-5-4 (5 mode searches
fewer); taking Newton's own step on the first indefinite tangent after a definite one of the
same increment (and turning only a second one in a row): cantilever 5-6-4-5-4, elastica 4-4-4-5-5,
heavy 38-18-8: not kept. Each line prints the mode searches (eigen-solves) of the run.

The fibre-length projection (``fibre_projection=True``, the default; solvers.newton_fibres):
each step's end moved back onto the fibre lengths its first order asks for, by Gauss-Newton
sweeps on the warp and weft edges of MindlinShell(fabric). Line 6, MindlinShell(fabric),
without -> with (same run, one thread, CPU time best of 3, load 6.9-7.0): 8-12-12 -> 4-5-5
iterations, 32 -> 14 tangents, 80 -> 39 force evaluations, 0.21 -> 0.11 s; the same tip. In
the validation case heavy-cantilever-nonlinear (default), MindlinShell(fabric) strips of 10,
20 and 40 cells 9-20-11 -> 5-9-5, 34-21-6 -> 6-7-5, 16-31-35 -> 5-6-5 and its Peirce strip
8-12-12 -> 4-5-5, every check's value the same to 1e-8 (the case's CPU time 8.7 -> 5.7 s,
load 8-9; its fibrous strips 20-19-11, 12-12-9, 39-39-48 and 7-14-11 unchanged); bai-6.1.2
(coarse: 7 solves of 9-20 increments under a prescribed push) 646 -> 645 iterations, 7.7 ->
8.2 s CPU at load 8.5 (the same within the load's noise). The
fibrous shell gives no fibre edges: its fibres are levels through the thickness whose lengths
follow the directors, and projecting the mid-surface edges made it worse (one thread, load
7-9): heavy cantilever 30-11-8 -> 29-18-11, Peirce 7-14-11 -> 6-21-25; with the directors
turned by the change of the nodal normals as well, 28-36-12 and 8-23-29; with the projection
followed by one or two relaxations of the directors alone (K_rr^-1 of the iteration's rotation
block against the rotational residual at the projected end), Peirce 10-16-12 / 6-10-12, heavy
26-15-8 / 25-14-12, and the relaxation alone Peirce 7-12-35, heavy 42-28-19; with the outer
levels' lengths projected too by Gauss-Newton sweeps on the director rotations (the
top-bottom difference of each fibre edge: Peirce 6-11-16, heavy 19-15-6; each level: 7-23-13,
29-15-7): not kept. What the projection leaves on Peirce's strip (its first step of the second
increment): the mid-surface edges at 4e-7, both outer levels stretched alike by 1.27 %, the
second-order term of a director tilt across the fibres that a tangent of an unstretched state
does not resist (the step turns the directors by up to 0.06 rad). The
cantilever, the elastica and the roll-up have no fibre edges: their counts are those above.

The compiled cell Hessians of the fibrous tangent (elements/fibrous/hessian_kernels.py),
line 1's Static (default variant) before and after, CPU time on one thread, best of 3 (the
spread in brackets), load 9-10 on 2 cores: 20 x 20 cells (400 triangles) 0.87 -> 0.76 s (one
run each), 40 x 40 cells (1600 triangles) 6.35 (6.35-8.18) -> 4.91 (4.91-6.18) s; the same
Newton iterations 4-4-4-4, 16 tangents and 43 / 48 residuals. Peirce fibrous (line 6, 40
triangles) 0.29 -> 0.32 s, one run each (its 32 tangents of 40 cells are not what it spends).

The fibrous figures above were measured before the compression-free tangent of the iterates
far from equilibrium (``Static(compression_free=None)``, by default 1e-2 on a fibrous model
without interactions; docs/theory.md §6.5), i.e. as ``compression_free=0`` gives them; with it
line 6's fibrous strip takes 10-9-10 iterations (29 tangents) and the heavy cantilever 25-9-8,
the same tips (benchmarks/fibrous_newton.py, both side by side); line 1 (20 x 20 cells) 4-4-4-4
iterations, 16 tangents either way (43 -> 42 forces; one thread, load 7.1, run apart).

Run: python benchmarks/static_solver.py [--cells 20] [--dr-limit 400000] [--skip-dr]
Prints one line per run; one core (set OMP_NUM_THREADS=1 to be sure).
"""

from __future__ import annotations

import argparse
import dataclasses
import math
import platform
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from elements import Cable, FibrousShell  # noqa: E402
from femcore import Mesh, Model  # noqa: E402
from materials import presets  # noqa: E402
from materials.presets import g1151_laminate  # noqa: E402
from solvers import ConvergenceError, DynamicRelaxation, Static  # noqa: E402
from validation import specimens  # noqa: E402
from validation.references.elastica import peirce_overhang, tip_loaded_cantilever  # noqa: E402

# Each Static line of 1, 2, 3 and 6 twice: the default, then the solver before the curved
# steps (straight Newton steps, no chord correction, no fibre projection).
VARIANTS = (
    ("", {}),
    (", straight steps", {"curved": False, "chords": 0, "fibre_projection": False}),
)

__all__ = [
    "bias_extension",
    "central_shear",
    "corner_model",
    "describe",
    "force_time",
    "main",
    "strip",
    "timed",
    "von_mises_truss",
]


def corner_model(cells: int) -> tuple[Model, specimens.Specimen]:
    """The bai-6.2.1 specimen (validation.specimens), its corner lowered by 40 mm."""
    specimen = specimens.corner(*specimens.G1151_SIZE, cells)
    model = specimens.build(specimen, "fibrous", g1151_laminate(), (None, None, -40.0))
    return model, specimen


def strip(load_kind: str) -> tuple[Model, np.ndarray, float]:
    length, width, thickness, young = 200.0, 20.0, 1.0, 70e3  # aluminium, nu = 0
    mesh, model = specimens.mindlin_strip(length, width, thickness, young, cells=80, across=16)
    bending = young * width * thickness**3 / 12
    tip = mesh.nodes("right")
    if load_kind == "force":
        load = 3.0 * bending / length**2
        model.force(tip, (0.0, 0.0, -load / len(tip)), amplitude="linear")
        reference = tip_loaded_cantilever(length, load, bending)["tip_deflection"]
    else:
        moment = 0.25 * 2 * math.pi * bending / length
        model.moment(tip, (0.0, -moment / len(tip), 0.0), amplitude="linear")
        reference = bending / moment  # radius of the quarter circle
    return model, tip, reference


def bias_extension(cells: int, fabric):
    """The bias-extension specimen: left end clamped, right end pulled 30 mm along x."""
    mesh = specimens.bias_extension_mesh(200.0, 100.0, cells)
    c = math.cos(math.pi / 4)
    model = Model(mesh)
    model.add(FibrousShell(fabric, warp=(c, c, 0.0)))
    model.fix("left")
    model.fix("right", dofs=("uy", "uz", "alpha", "beta"))
    model.displace("right", ux=30.0)
    return model, mesh


def central_shear(result, mesh) -> float:
    """Mean |shear angle| (deg) of the cells within 10 mm of the specimen's centre."""
    centres = mesh.points[mesh.triangles].mean(axis=1)
    central = np.linalg.norm(centres[:, :2] - [100.0, 50.0], axis=1) < 10.0
    gamma = result.frames[-1].fields["triangle"]["shear_angle_deg"]
    return float(np.abs(gamma[central]).mean())


def von_mises_truss():
    """Half-span 10 mm, rise 1 mm, EA 1e4 N, pushed through a 1 N/mm spring lowered 6 mm."""
    points = np.array([[-10.0, 0, 0], [10.0, 0, 0], [0, 0, 1.0], [0, 0, 11.0]])
    model = Model(Mesh(points, lines=np.array([[0, 2], [1, 2], [2, 3]])))
    model.add(Cable(axial_stiffness=1e4, mass_per_length=1e-6), cells=[0, 1])
    model.add(Cable(axial_stiffness=10.0, mass_per_length=1e-6), cells=[2])
    model.fix([0, 1])
    model.fix([2, 3], ("ux", "uy"))
    model.displace(3, uz=-6.0)
    return model


def timed(solver, model):
    started, cpu = time.perf_counter(), time.process_time()
    try:
        result = solver.solve(model)
        converged = True
    except ConvergenceError as error:
        result, converged = error.result, False
    result.cpu_time = time.process_time() - cpu
    return result, time.perf_counter() - started, converged


def force_time(model) -> float:
    """Seconds of one internal-force evaluation of the model (best of 5)."""
    compiled = model.compile()
    state = compiled.initial_state()
    best = np.inf
    for _ in range(5):
        started = time.perf_counter()
        compiled.internal_force(state)
        best = min(best, time.perf_counter() - started)
    return best


def describe(name, result, wall, converged, extra="", model=None):
    if name.startswith("Static"):
        info = result.info
        counts = info["evaluations"]
        its = (
            f"Newton iterations per increment {info['iterations_per_increment']}, "
            f"{counts['residual']} force + {counts['energy']} energy + {counts['tangent']} "
            f"tangent evaluations, {info['mode_searches']} mode searches"
        )
        if model is not None:
            its += f", = {wall / force_time(model):.0f} force evaluations' worth of time"
    else:
        its = f"{result.steps} iterations"
    status = "" if converged else " (NOT converged)"
    cpu = getattr(result, "cpu_time", None)
    cpu_text = "" if cpu is None else f" ({cpu:.2f} s CPU)"
    print(f"  {name}: {wall:.2f} s{cpu_text}, {its}{status}{extra}")


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cells", type=int, default=20, help="corner specimen: n x n cells")
    parser.add_argument("--dr-limit", type=int, default=400_000, help="DR iteration limit")
    parser.add_argument("--skip-dr", action="store_true")
    parser.add_argument("--bias-cells", type=int, default=40, help="bias extension: diamonds along")
    args = parser.parse_args(argv)
    print(f"python {platform.python_version()} on {platform.machine()} ({platform.system()})")

    model, specimen = corner_model(args.cells)
    n_tri = len(specimen.mesh.triangles)
    print(f"1. Bai 6.2.1 G1151 corner bending, fibrous shell, {n_tri} triangles:")
    for name, options in VARIANTS:
        static, wall, ok = timed(Static(increments=4, **options), model)
        describe(f"Static{name}", static, wall, ok, model=model)
    if not args.skip_dr:
        relaxed, wall, ok = timed(DynamicRelaxation(tol=1e-5, max_iterations=args.dr_limit), model)
        gap = np.abs(relaxed.positions - static.positions).max()
        travel = np.abs(static.displacements).max()
        describe(
            "DynamicRelaxation",
            relaxed,
            wall,
            ok,
            f"; largest position difference to Static {gap:.3g} mm = {gap / travel:.2e} of the "
            f"largest displacement",
        )

    model, tip, reference = strip("force")
    print(f"2. Mindlin cantilever, 2560 triangles, tip load (elastica: drop {reference:.2f} mm):")
    chorded = (", straight steps, chords=4", {"curved": False, "chords": 4})
    for name, options in (*VARIANTS, chorded):
        static, wall, ok = timed(Static(increments=5, **options), model)
        drop = -static.displacements[tip, 2].mean()
        describe(
            f"Static{name}",
            static,
            wall,
            ok,
            f"; tip drop {drop:.2f} mm ({drop / reference - 1:+.2%})",
            model=model,
        )
    if not args.skip_dr:
        relaxed, wall, ok = timed(
            DynamicRelaxation(increments=5, tol=1e-5, max_iterations=args.dr_limit), model
        )
        drop = -relaxed.displacements[tip, 2].mean()
        describe(
            "DynamicRelaxation",
            relaxed,
            wall,
            ok,
            f"; tip drop {drop:.2f} mm ({drop / reference - 1:+.2%})",
        )

    model, tip, radius = strip("moment")
    print(f"3. Mindlin roll-up to a quarter circle, 2560 triangles (radius {radius:.2f} mm):")
    runs = [(f"{name}, element tangent", options) for name, options in VARIANTS]
    runs.append((", finite_difference tangent", {"tangent": "finite_difference"}))
    for name, options in runs:
        result, wall, ok = timed(Static(increments=4, **options), model)
        x, _, z = result.positions[tip].mean(axis=0)
        describe(
            f"Static{name}",
            result,
            wall,
            ok,
            f"; tip at x = {x:.2f} ({x / radius - 1:+.2%}), z = {z:.2f} ({z / radius - 1:+.2%})",
            model=model,
        )

    expected = np.degrees(specimens.pin_jointed_shear(200.0, 100.0, 30.0))
    triangles = len(specimens.bias_extension_mesh(200.0, 100.0, args.bias_cells).triangles)
    print(
        f"4. Bias extension, {triangles} triangles, pulled 30 mm (pin-jointed net: "
        f"{expected:.2f} deg in the central zone):"
    )
    ply = presets.g986_ply()
    fabrics = {
        "G986 stack (1200 N/mm fibres, shear 4 N/mm)": presets.g986_stack(),
        "G986 ply (1200 N/mm fibres, shear 0.2 N/mm)": ply,
        "ply with 1.2e5 N/mm fibres (the net's limit)": dataclasses.replace(
            ply, tension=1.2e5, tension_weft=1.2e5
        ),
    }
    for name, fabric in fabrics.items():
        model, mesh = bias_extension(args.bias_cells, fabric)
        # The flat state becomes unstable (out-of-plane wrinkling modes: negative eigenvalues
        # of the tangent) as the shear grows; the pin-jointed net describes the flat branch.
        result, wall, ok = timed(Static(path="arc_length", seek_stable=False), model)
        shear = central_shear(result, mesh)
        describe(
            f"Static, {name}",
            result,
            wall,
            ok,
            f"; central shear {shear:.2f} deg ({shear / expected - 1:+.2%}), reached "
            f"{30.0 * result.frames[-1].load_factor:.1f} mm, negative eigenvalues at the end: "
            f"{result.info['negative_eigenvalues'][-1]}",
            model=model,
        )

    model = von_mises_truss()
    print("5. Von Mises truss through a soft spring, arc length (two limit points):")
    result, wall, ok = timed(Static(increments=12, path="arc_length"), model)
    describe(
        "Static, arc length",
        result,
        wall,
        ok,
        f"; {len(result.frames) - 1} increments, limit points at load factors "
        + ", ".join(f"{value:.4f}" for value in result.info["limit_points"]),
        model=model,
    )

    fabric = presets.g986_stack()
    overhang = peirce_overhang(fabric.areal_density * specimens.GRAVITY, fabric.bending)["overhang"]
    print(f"6. Peirce's cantilever, G986 stack, overhang {overhang:.2f} mm, 20 x 1 cells:")
    for name, build in (
        ("fibrous", specimens.fibrous_strip),
        ("MindlinShell(fabric)", specimens.mindlin_fabric_strip),
    ):
        mesh, model = build(overhang, 10.0, fabric, 20)
        unprojected = (", no fibre projection", {"fibre_projection": False})
        for variant, options in (*VARIANTS, unprojected):
            result, wall, ok = timed(Static(increments=3, **options), model)
            x, _, z = result.positions[mesh.nodes("right")].mean(axis=0)
            describe(
                f"Static{variant}, {name}",
                result,
                wall,
                ok,
                f"; chord {math.degrees(math.atan2(-z, x)):.2f} deg (Peirce: 41.5)",
                model=model,
            )


if __name__ == "__main__":
    main()
