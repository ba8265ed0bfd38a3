"""Static against Kratos on the Mindlin cantilever, in the same run.

The strip of benchmarks/static_solver.py (200 x 20 x 1 mm, 80 x 16 cells, 2560 triangles,
aluminium E = 70 GPa, nu = 0, clamped at x = 0) under a tip load P L^2 / EI = 3 in 5 equal
load increments: fibreshell's Static (MindlinShell) and Kratos Multiphysics'
ShellThinElementCorotational3D3N on the same nodes and triangles, the same clamp and the same
nodal tip forces, each with a full Newton-Raphson per increment and a direct sparse solver.

Convergence tests, like for like: Static judges ||r|| / F_ref <= tol with
F_ref = max(||F_ext||, ||F_int||, ||M_ext|| / L_e, ||M_int|| / L_e) (solvers.convergence); Kratos'
ResidualCriteria judges ||r|| / ||r_0||, r_0 the residual at the start of the increment (the
load increment ||dP||; forces and moments in one norm). Static runs with its default
tol = 1e-8; Kratos with the relative tolerance that is the same absolute residual,
1e-8 F_ref / ||dP||, F_ref that of Static's converged states, the smallest over the increments
(the strictest; the clamp's reaction moment over L_e makes F_ref about 80 x ||dP|| on the
first increment). Kratos at a relative 1e-8 never converges: the round-off floor of its
residual is above it. Both print the iterations per increment,
the wall and CPU times of the solve (best of the repeats; model building excluded on both
sides; on a shared machine the CPU time is the fairer figure) and the tip drop against the
elastica.

Kratos is optional: it runs in its own interpreter, given by the environment variable
KRATOS_PYTHON (default: this interpreter), which must import KratosMultiphysics with the
StructuralMechanics and LinearSolvers applications, e.g. a separate venv made with

    python3 -m venv kratos-venv
    kratos-venv/bin/pip install KratosMultiphysics KratosStructuralMechanicsApplication \
        KratosLinearSolversApplication
    KRATOS_PYTHON=kratos-venv/bin/python python benchmarks/kratos_cantilever.py

Without it the Kratos line says so and only Static runs.

Measured on this 2-core machine shared with other work (load 4-6), best of 3, one thread,
Kratos 10.4.4 from PyPI: Static 1.61 s (0.67 s CPU), 9-9-9-8-8 iterations; Kratos 12.81 s
(5.55 s CPU), 7-8-7-7-6 iterations: 7.9 x (CPU 8.3 x). Before the band LDL^T, the compiled
Mindlin tangent and the compiled assembly, the same run gave 4.62 s (2.28 s CPU) against
11.25 s (5.59 s CPU): 2.4 x. The tips agree to 0.003 %.

Later, on a machine about 3 x slower (the numpy reference pass of benchmarks/explicit_step.py,
10k and 100k triangles, one thread: 0.24-0.25 us CPU per element against 0.07-0.08 on the
machine above) and without Kratos, at load 9-12: Static 1.73-2.35 s CPU (best of 3, runs of
the same code differ that much at this load) in 4-5-5-5-5 or 5-5-5-5-4 iterations (curved
steps and one chord correction per step), 0.5-0.8 s on the scale of the machine above against
Kratos's 5.55 s CPU there: 7-11 x. Wall times were 2.5-3 x the CPU times at that load.

Side by side on that slower machine (Kratos 10.4.4 from PyPI in its own venv, one thread,
best of 3, load 8.9-9.1): Static 2.03 s CPU (10.1 s wall) in 4-5-5-5-4 iterations, chords=4
1.79 s CPU in 4-6-5-4-4; Kratos 15.16 s CPU (75.1 s wall) in 7-8-7-7-6 (its relative
tolerance 7.93e-7, the same absolute residual): 7.5 x on CPU time (7.4 x wall); the tips
differ by 0.0027 %, both within 0.004 % of the elastica.

On this machine again (Kratos 10.4.4 from PyPI in its own venv, one thread, best of 3, load
12-17 from other work: wall times mean little), before and after the kept tangent
(solvers/kept_tangent.py: a converged state's stability tangent is the next increment's
first): Static 1.13 s CPU in 4-5-5-5-4 iterations (23 Newton tangents + 5 stability ones)
against Kratos's 6.36 s CPU in 7-8-7-7-6: 5.66 x; after, Static 1.18 s CPU (19 + 5 tangents)
beside its reference pass (every tangent assembled, 23 + 5) at 1.19 s, Kratos 6.40 s: 5.4 x;
the two Static passes alternated 8 times in one process (load 17.3): best 1.001 / 1.054 s,
median 1.050 / 1.101 s (0.95 x), so 6.1-6.4 x on Kratos's 6.40 s. The tips as before
(0.0027 % apart, both within 0.004 % of the elastica). With the curved correction's share
fitted as well (solvers/newton_curvature.py ``LEAST_SCALE = 0.25``, then off by default: the whole
correction compressed the strip at each increment's first update, 8-14 negative pivots and a
mode search there), side by side in one run (best of 3, load ~16): Static 1.08 s CPU in
4-5-5-5-4 iterations (19 + 5 tangents), its reference pass (every tangent assembled) 1.15 s
(23 + 5), with the share fitted 0.67 s in 5-4-4-4-4 (17 + 5), chords=4 1.18 s in 4-6-5-4-4,
Kratos 6.72 s CPU in 7-8-7-7-6: 6.2 x on CPU time by default (5.8 x the reference pass, 10.0
x with the share fitted); wall times 3.36 / 8.27 / 3.67 s against 30.66 at that load. An
earlier run with the share on in the default row: 0.74 s against Kratos's 6.66 (9.0 x).

The share fitted by default since (``Static(correction="fitted")``; the reference pass is
``correction="whole"``, the solver before), side by side in one run (best of 3, one thread,
load 9-11): Static 0.66 s CPU in 5-4-4-4-4 iterations (17 + 5 tangents), its reference pass
1.22 s in 4-5-5-5-4 (19 + 5), the whole correction with every tangent assembled 1.20 s
(23 + 5), chords=4 0.66 s in 4-4-4-4-4 (16 + 5), Kratos 6.46 s CPU in 7-8-7-7-6: 9.8 x on
CPU time (5.3 x for the reference pass); wall 3.31 / 9.79 / 5.34 / 2.30 s against 22.11 s at
that load. The tips the same (0.0027 % from Kratos's, within 0.004 % of the elastica).

Run: python benchmarks/kratos_cantilever.py [--repeats 3]
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # this tree's packages


__all__ = ["kratos_solve", "main", "static_solve"]

LENGTH, WIDTH, THICKNESS, YOUNG = 200.0, 20.0, 1.0, 70e3  # mm, MPa
CELLS, ACROSS, INCREMENTS, LOAD_PARAMETER = 80, 16, 5, 3.0
TOLERANCE = 1e-8


def _strip():
    """(mesh, model, tip nodes, total tip force N, elastica tip drop mm)."""
    from validation import specimens
    from validation.references.elastica import tip_loaded_cantilever

    mesh, model = specimens.mindlin_strip(LENGTH, WIDTH, THICKNESS, YOUNG, CELLS, ACROSS)
    bending = YOUNG * WIDTH * THICKNESS**3 / 12
    load = LOAD_PARAMETER * bending / LENGTH**2
    tip = mesh.nodes("right")
    model.force(tip, (0.0, 0.0, -load / len(tip)), amplitude="linear")
    drop = tip_loaded_cantilever(LENGTH, load, bending)["tip_deflection"]
    return mesh, model, tip, load, drop


def static_solve(
    repeats: int, chords: int | None = None, before: bool = False, correction: str = "fitted"
) -> dict:
    """Static on the strip: best wall time of ``repeats`` solves, iterations, tip drop;
    ``chords``: Static's chord corrections per step (None: its default); ``before``: the
    solver before the kept tangent (every tangent assembled, solvers.kept_tangent
    ``REUSE``); ``correction``: Static's share of the curved correction ("fitted", the
    default, or "whole", the solver before it: the reference pass)."""
    from dataclasses import replace

    from solvers import Static, kept_tangent
    from solvers.convergence import Equilibrium

    _, model, tip, load, drop = _strip()
    compiled = model.compile()
    Static(increments=1, max_iterations=1, progress=False)  # imports settled
    best, cpu, result = np.inf, np.inf, None
    for _ in range(repeats):
        started, cpu_started = time.perf_counter(), time.process_time()
        options = {} if chords is None else {"chords": chords}
        kept_tangent.REUSE = not before
        try:
            result = Static(
                increments=INCREMENTS, correction=correction, progress=False, **options
            ).solve(compiled)
        finally:
            kept_tangent.REUSE = True
        best = min(best, time.perf_counter() - started)
        cpu = min(cpu, time.process_time() - cpu_started)
    assert result is not None
    # The force reference of each converged increment, and the Kratos tolerance it makes.
    relative = []
    for frame in result.frames[1:]:
        state = replace(
            compiled.initial_state(), positions=frame.positions, directors=frame.directors
        )
        f_int, m_int = compiled.internal_force(state)
        f_ext, m_ext = compiled.external_load(1.0, quasi_static=True)
        test = Equilibrium(frame.load_factor * f_ext, m_ext, compiled.element_size, floor=1e-300)
        load_increment = np.linalg.norm(f_ext[tip]) / INCREMENTS
        relative.append(TOLERANCE * test.references(f_int, m_int)[0] / load_increment)
    return {
        "kratos_tolerance": min(relative),
        "wall_s": best,
        "cpu_s": cpu,
        "iterations": result.info["iterations_per_increment"],
        "tip_drop": float(-result.displacements[tip, 2].mean()),
        "elastica": drop,
        "evaluations": result.info["evaluations"],
    }


def kratos_solve(repeats: int, python: str, tolerance: float) -> dict | str:
    """The same strip in Kratos (run by the interpreter ``python``): a dict like
    ``static_solve``'s, or why it did not run; ``tolerance`` relative to the residual at the
    start of each increment."""
    mesh, _, tip, load, drop = _strip()
    left = mesh.nodes("left")
    with tempfile.TemporaryDirectory() as folder:
        data = Path(folder) / "strip.npz"
        np.savez(
            data,
            points=mesh.points,
            triangles=mesh.triangles,
            left=left,
            tip=tip,
            load=load,
            repeats=repeats,
            tolerance=tolerance,
        )
        try:
            done = subprocess.run(
                [python, __file__, "--kratos-side", str(data)],
                capture_output=True,
                text=True,
                # One thread, as Static's solve (Kratos' OpenMP would take every core).
                env=dict(os.environ, OMP_NUM_THREADS=os.environ.get("OMP_NUM_THREADS", "1")),
                timeout=600,
            )
        except (OSError, subprocess.TimeoutExpired) as error:
            return f"not run ({error})"
    if done.returncode != 0:
        last = (done.stderr.strip().splitlines() or ["no output"])[-1]
        return f"not run ({python}: {last})"
    answer = json.loads(done.stdout.strip().splitlines()[-1])
    answer["elastica"] = drop
    return answer


def _kratos_side(path: str) -> None:
    """Runs inside the Kratos interpreter: builds the strip, solves, prints one JSON line."""
    import KratosMultiphysics as KM  # type: ignore[import-not-found]
    import KratosMultiphysics.StructuralMechanicsApplication as SMA  # type: ignore[import-not-found]
    from KratosMultiphysics import python_linear_solver_factory  # type: ignore[import-not-found]

    data = np.load(path)
    points, triangles = data["points"], data["triangles"]
    left, tip, load = data["left"], data["tip"], float(data["load"])
    repeats, tolerance = int(data["repeats"]), float(data["tolerance"])
    KM.Logger.GetDefaultOutput().SetSeverity(KM.Logger.Severity.WARNING)
    best, cpu, iterations, tip_drop = np.inf, np.inf, [], 0.0
    for repeat in range(repeats):
        model = KM.Model()
        part = model.CreateModelPart(f"strip{repeat}")
        part.SetBufferSize(2)
        part.ProcessInfo[KM.DOMAIN_SIZE] = 3
        for variable in (KM.DISPLACEMENT, KM.ROTATION, KM.REACTION, KM.REACTION_MOMENT):
            part.AddNodalSolutionStepVariable(variable)
        part.AddNodalSolutionStepVariable(SMA.POINT_LOAD)
        for i, (x, y, z) in enumerate(points):
            part.CreateNewNode(i + 1, float(x), float(y), float(z))
        props = part.GetProperties()[1]
        props[KM.YOUNG_MODULUS] = YOUNG
        props[KM.POISSON_RATIO] = 0.0
        props[KM.THICKNESS] = THICKNESS
        props[KM.DENSITY] = 2.7e-9
        props[KM.CONSTITUTIVE_LAW] = SMA.LinearElasticPlaneStress2DLaw()
        for e, cell in enumerate(triangles):
            part.CreateNewElement(
                "ShellThinElementCorotational3D3N", e + 1, [int(n) + 1 for n in cell], props
            )
        for c, node in enumerate(tip):
            part.CreateNewCondition("PointLoadCondition3D1N", c + 1, [int(node) + 1], props)
        for name in "XYZ":
            KM.VariableUtils().AddDof(
                getattr(KM, f"DISPLACEMENT_{name}"), getattr(KM, f"REACTION_{name}"), part
            )
            KM.VariableUtils().AddDof(
                getattr(KM, f"ROTATION_{name}"), getattr(KM, f"REACTION_MOMENT_{name}"), part
            )
        for node in left:
            kratos_node = part.GetNode(int(node) + 1)
            for name in "XYZ":
                kratos_node.Fix(getattr(KM, f"DISPLACEMENT_{name}"))
                kratos_node.Fix(getattr(KM, f"ROTATION_{name}"))
        linear = python_linear_solver_factory.ConstructSolver(
            KM.Parameters('{"solver_type": "LinearSolversApplication.sparse_lu"}')
        )
        strategy = KM.ResidualBasedNewtonRaphsonStrategy(
            part,
            KM.ResidualBasedIncrementalUpdateStaticScheme(),
            KM.ResidualCriteria(tolerance, 1e-30),
            KM.ResidualBasedBlockBuilderAndSolver(linear),
            50,
            False,  # compute reactions
            False,  # reform DOFs at each step
            True,  # move mesh
        )
        strategy.SetEchoLevel(0)
        strategy.Initialize()
        started, cpu_started = time.perf_counter(), time.process_time()
        iterations = []
        for step in range(1, INCREMENTS + 1):
            part.CloneTimeStep(float(step))
            part.ProcessInfo[KM.STEP] = step
            force = -load * step / INCREMENTS / len(tip)
            for node in tip:
                part.GetNode(int(node) + 1).SetSolutionStepValue(SMA.POINT_LOAD, [0.0, 0.0, force])
            strategy.Solve()
            iterations.append(int(part.ProcessInfo[KM.NL_ITERATION_NUMBER]))
        best = min(best, time.perf_counter() - started)
        cpu = min(cpu, time.process_time() - cpu_started)
        tip_drop = -float(
            np.mean([part.GetNode(int(n) + 1).GetSolutionStepValue(KM.DISPLACEMENT_Z) for n in tip])
        )
    answer = {"wall_s": best, "cpu_s": cpu, "iterations": iterations, "tip_drop": tip_drop}
    print(json.dumps(answer))


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=3, help="best of this many solves")
    parser.add_argument("--kratos-side", help=argparse.SUPPRESS)
    args = parser.parse_args(argv)
    if args.kratos_side:
        _kratos_side(args.kratos_side)
        return
    print(f"python {platform.python_version()} on {platform.machine()} ({platform.system()})")
    print(
        f"Mindlin cantilever {CELLS} x {ACROSS} x 2 = {2 * CELLS * ACROSS} triangles, "
        f"P L^2 / EI = {LOAD_PARAMETER:g}, {INCREMENTS} increments, best of {args.repeats}:"
    )
    ours = static_solve(args.repeats)
    python = os.environ.get("KRATOS_PYTHON", sys.executable)
    theirs = kratos_solve(args.repeats, python, ours["kratos_tolerance"])
    rows = [
        ("fibreshell Static (MindlinShell)", ours),
        (
            "fibreshell Static (MindlinShell), before (reference pass: the whole curved "
            'correction, correction="whole")',
            static_solve(args.repeats, correction="whole"),
        ),
        (
            "fibreshell Static (MindlinShell), before the kept tangent as well (the whole "
            "correction, every tangent assembled)",
            static_solve(args.repeats, before=True, correction="whole"),
        ),
        ("fibreshell Static (MindlinShell), chords=4", static_solve(args.repeats, chords=4)),
    ]
    if isinstance(theirs, str):
        print(f"  Kratos ShellThinElementCorotational3D3N: {theirs}")
    else:
        rows.append(("Kratos ShellThinElementCorotational3D3N", theirs))
    for name, row in rows:
        tangents = row.get("evaluations", {})
        assembled = (
            f", {tangents['tangent']} + {tangents['stability_tangents']} tangents"
            if tangents
            else ""
        )
        print(
            f"  {name}: {row['wall_s']:.2f} s ({row['cpu_s']:.2f} s CPU), Newton iterations "
            f"per increment "
            f"{row['iterations']}{assembled}, tip drop {row['tip_drop']:.3f} mm "
            f"({row['tip_drop'] / row['elastica'] - 1:+.3%} from the elastica)"
        )
    if not isinstance(theirs, str):
        print(
            f"  Kratos / Static: wall time {theirs['wall_s'] / ours['wall_s']:.2f} x, CPU time "
            f"{theirs['cpu_s'] / ours['cpu_s']:.2f} x; tips differ "
            f"by {abs(theirs['tip_drop'] / ours['tip_drop'] - 1):.4%}; Kratos' relative "
            f"tolerance {ours['kratos_tolerance']:.3g} (module docstring)"
        )


if __name__ == "__main__":
    main()
