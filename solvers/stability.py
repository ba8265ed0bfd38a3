"""Stability of the static solver's equilibria (solvers.static.Static, ``seek_stable``;
docs/theory.md §6.5, §6.6).

The number of negative eigenvalues of the tangent K_ff of a converged state is the number of
negative pivots of its LDL^T (Sylvester's law of inertia; solvers.linear counts them, the run
keeps the count of each frame). A non-zero count is an unstable equilibrium: a compressed
plate that stayed flat, the part of a path beyond a limit point. Only the eigenvalues below
the rounding of their second variation count (solvers.neutral_modes): a zero-energy mode (the
uniform tilt of free fibrous directors, docs/theory.md §1.7) has an eigenvalue of round-off,
either sign, and is neutral, neither counted nor followed. Two ways off it:

- ``downhill``: a Newton step on an indefinite tangent heads for the nearest equilibrium,
  stable or not; its components along the negative modes are turned downhill (the load path;
  a converged saddle is pushed along its mode by ``push_descends``, solvers/saddles.py);
- ``buckling_mode``: where the count grows while the load still rises, the lowest negative
  mode, if it is a bifurcation mode (not driven by the load, not along the path), is where the
  next arc-length increment starts.

Both use the lowest modes of the symmetric part of K_ff (``lowest_modes``). A converged saddle
is left only when a push along one of its negative modes, relaxed with its amplitude held, is a
descent (``push_descends``): the total potential energy evaluated at the pushed state is lower
by more than round-off. A
negative second variation says that the energy falls along the mode for small enough
amplitudes; where the quartic terms take over within a fraction of the push (a flat sheet
whose fibres in tension stiffen any out-of-plane motion within a thousandth of an element), the
push climbs the energy and the Newton iteration from there wanders off the load path instead of
finding a lower branch: the flat specimen of a bias-extension test, a saddle of the discrete
energy only within 1e-3 of an element of the plane, failed its increments that way.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
from scipy.sparse.linalg import ArpackNoConvergence, LinearOperator, eigsh, splu

from femcore.dofs import N_COLUMNS
from solvers.common import IncrementFailed
from solvers.neutral_modes import unstable_modes

if TYPE_CHECKING:
    from solvers.arc_length import Motion
    from solvers.static import StaticRun

__all__ = [
    "MODES",
    "PUSH",
    "PUSH_SHRINK",
    "SHORTEST_PUSH",
    "buckling_mode",
    "downhill",
    "lowest_modes",
    "push_descends",
]

# The most modes a search returns (solvers.inertia shifts tangents with more negative ones).
MODES = 6
# Tangents up to this size are solved densely (all eigenvalues).
DENSE = 200
# The Lanczos vectors of each ARPACK search (at least 2 k + 1), its restarts at most (the
# shift-invert's: solves with the factors; K_ff's own: products with the sparse matrix), and
# the relative residual at which a Ritz pair counts as converged (|K phi - l phi| <= tol |l|).
# Each search applies its operator at most NCV + restarts x NCV times.
NCV = 20
SHIFT_INVERT_RESTARTS = 20
PLAIN_RESTARTS = 50
RITZ_TOL = 1e-8

# The push off a converged saddle along its buckling mode: this fraction of the element size
# for the largest translation of the mode, or PUSH_SHRINK times shorter each time while it is
# no descent (``push_descends``), down to SHORTEST_PUSH. A saddle whose energy falls only
# closer to it is kept: a flat fabric sheet sheared in its plane, whose energy falls along its
# out-of-plane modes only within about 1e-3 of an element (docs/theory.md §6.5).
PUSH = 0.5
PUSH_SHRINK = 4.0
SHORTEST_PUSH = 0.02
# The Newton updates that relax a push with the mode's amplitude held (``push_descends``).
RELAX_STEPS = 3
RELAX_HALVINGS = 6


def downhill(k_ff, rhs, delta, negative=None, modes=None) -> np.ndarray:
    """The Newton step with its components along the negative modes of K_ff turned downhill.

    A Newton step heads for the nearest equilibrium, stable or not. Along a mode phi with
    eigenvalue lambda < 0 (of the symmetric part), its component (phi . r) / lambda climbs
    the energy towards the saddle; the step is given the component (phi . r) / |lambda|
    instead (leaving a converged saddle is ``push_descends``'s push). A neutral mode (lambda
    within the rounding of phi . K phi, solvers.neutral_modes) keeps Newton's component: the
    turn would divide the residual's round-off along it by the eigenvalue's.

    k_ff : the tangent of the free DOFs; rhs, delta : (n_free,) the right-hand side and the
    Newton step on the free DOFs; negative : the negative pivots of K_ff; modes :
    (eigenvalues, eigenvectors) of ``lowest_modes`` already computed for K_ff, its neutral
    modes left out (``solvers.neutral_modes.unstable_modes``).
    """
    if modes is None:
        modes = unstable_modes(k_ff, lowest_modes(k_ff, negative))
    values, vectors = modes
    delta = delta.copy()
    for value, phi in zip(values, vectors.T):
        if value >= 0.0:
            continue
        along = phi @ rhs
        delta += (along / abs(value) - phi @ delta) * phi
    return delta


def push_descends(
    run: StaticRun, state, frames, load, modes, translation, factor=None, equilibrium=None
):
    """The push off the converged ``state`` along one of its negative modes that lowers the
    total potential energy by more than round-off: (its length as a fraction of the element
    size for the mode's largest translation, the pushed state); None where none does.

    Each mode phi with eigenvalue lambda < 0 is tried on both sides, moved so that its largest
    translation is PUSH elements, then PUSH_SHRINK times shorter each time down to
    SHORTEST_PUSH elements. A straight push a phi along a mode that turns cells stretches them
    at second order in a, so the energy change is lambda a^2 / 2 only while that stretch costs
    less: an Euler strip clamped at one end under 1.5 times its buckling load (lambda =
    -0.0065) gains 6.3 N mm at the half-element push (2.5 mm) and loses 1.5e-3 at 0.3 mm, and
    a fibrous one, its fibres 1e4 times stiffer than its bending, gains at every push longer
    than a fiftieth of an element. So with ``factor`` (the LDL^T of K_ff at ``state``) and
    ``equilibrium`` (its Residual), the pushed state is first relaxed with the mode's amplitude
    held: RELAX_STEPS updates K_ff x = r - (phi . r) phi, each x taken orthogonal to phi (the
    second-order field of Koiter's expansion, here by Newton updates on the pushed state's
    residual), which turns the straight push into one along the buckled shape. The change of
    the total potential is W(pushed) - W(state) - load . (the pushed state's generalised
    motion), the dead loads' work along the straight push and the relaxation's updates
    (prescribed DOFs held). Round-off: 1e-10 of the strain energies, as in the line search.
    A mode with no translation (the directors' alone, every translation held) is no descent:
    nothing sizes a push along it, and Newton from the saddle itself, its steps turned
    downhill, does not leave it (its residual is zero there).

    run : the StaticRun; state : the converged state; frames : its nodal frames; load :
    (n_free,) the external load on the free DOFs, N and N mm; modes : (eigenvalues (k,),
    unit eigenvectors (n_free, k)) of ``lowest_modes``; translation : (n_free,) bool;
    factor : solvers.linear.Factorisation of K_ff at ``state`` or None (straight pushes);
    equilibrium : solvers.newton.Residual at the state's load factor, or None.
    """
    model = run.model
    dofs = model.dofs
    values, vectors = modes
    before = run.energy(state)
    for value, phi in zip(values, vectors.T):
        if value >= 0.0:
            continue
        reach = np.abs(phi[translation]).max(initial=0.0)
        if reach <= 0.0:  # nothing to size a push by (module docstring of push_descends)
            continue
        fraction = PUSH
        while fraction >= SHORTEST_PUSH:
            amplitude = fraction * model.element_size / reach
            for side in (1.0, -1.0):
                flat = np.zeros(dofs.n_slots)
                flat[dofs.free_slots] = side * amplitude * phi
                pushed = dofs.advance(state, flat.reshape(-1, N_COLUMNS), frames)
                moved = side * amplitude * phi
                if factor is not None and equilibrium is not None:
                    pushed, relaxed = _relax(run, equilibrium, pushed, phi, factor, load)
                    moved = moved + relaxed
                after = run.energy(pushed)
                change = after - before - float(moved @ load)
                if change < -1e-10 * (abs(before) + abs(after)):
                    return fraction, pushed
            fraction /= PUSH_SHRINK
    return None


def _relax(run: StaticRun, equilibrium, pushed, phi, factor, load):
    """(``pushed`` after at most RELAX_STEPS Newton updates on the DOFs orthogonal to the mode
    phi, (n_free,) the sum of the updates taken). An update is taken only where it lowers the
    total potential (halved up to RELAX_HALVINGS times): on a tangent with other soft modes
    (a fibrous shell's free directors) the full update can overshoot by orders of magnitude."""
    dofs = run.model.dofs
    index = dofs.free_slots
    moved = np.zeros(index.size)
    energy = run.energy(pushed)
    for _ in range(RELAX_STEPS):
        frames = dofs.frames(pushed.directors)
        try:
            r, _, _ = equilibrium.residual(pushed, frames)
        except IncrementFailed:
            break
        rhs = r.ravel()[index]
        rhs = rhs - (phi @ rhs) * phi
        update = factor.solve(rhs)
        if update is None or not np.all(np.isfinite(update)):
            break
        update = update - (phi @ update) * phi
        for _ in range(RELAX_HALVINGS + 1):
            flat = np.zeros(dofs.n_slots)
            flat[index] = update
            trial = dofs.advance(pushed, flat.reshape(-1, N_COLUMNS), frames)
            trial_energy = run.energy(trial)
            if trial_energy - float(update @ load) < energy:
                break
            update = 0.5 * update
        else:
            break
        pushed, energy, moved = trial, trial_energy - float(update @ load), moved + update
    return pushed, moved


def lowest_modes(k_ff, negative: int | None = None, inverse=None) -> tuple[np.ndarray, np.ndarray]:
    """Eigenvalues of the symmetric part of K_ff with their unit eigenvectors (columns),
    ascending: the ``negative`` ones (at most MODES) when the inertia says there are some,
    else the (up to) MODES nearest zero; fewer (or none) when the bounded searches below do
    not find them all.

    Both come from shift-invert about 0, where an eigenvalue l maps to 1 / l: the negative
    eigenvalues nearest zero are the smallest (most negative) 1 / l, and the eigenvalues
    nearest zero those of largest |1 / l|. The largest negative eigenvalue of a buckled plate
    may lie beyond several small positive ones, so asking for the nearest to zero alone can
    miss it.

    Bounded (docs/theory.md §6.5, "The stability search"): the shift-invert Lanczos
    (ARPACK) runs NCV vectors, at most SHIFT_INVERT_RESTARTS restarts and stops at a relative
    residual of RITZ_TOL; the negative modes far from zero, which the shift-invert maps next
    to 0 among the images of the many small positive eigenvalues and hardly separates (the
    16-cell hemisphere drape's tangents: -41 and -12 beside -0.15 ... -0.004, positive ones
    from 5e-4 up; its unbounded search took 5000 to 25 000 solves), are the lowest end of
    K_ff's own spectrum, which a Lanczos of K_ff itself (products only, at most
    PLAIN_RESTARTS restarts) finds. The modes it adds are those not already in the span of
    the shift-invert's (their projection on it below a half). Either search that does not
    converge gives the Ritz pairs it did converge.

    k_ff : (n, n) sparse tangent; negative : the negative pivots of its LDL^T (None or 0:
    the modes nearest zero); inverse : a LinearOperator applying the inverse of the symmetric
    part of K_ff from a factorisation already made (``Factorisation.inverse``), which the
    shift-invert then uses instead of factorising K_ff again (a SuperLU as costly as a Newton
    iteration's own).

    Returns (k,) eigenvalues and (n, k) unit eigenvectors, k <= MODES.
    """
    n = k_ff.shape[0]
    if n <= DENSE:  # small: all of them, densely (ARPACK needs k < n - 1)
        values, vectors = np.linalg.eigh(0.5 * (k_ff + k_ff.T).toarray())
        count = min(max(negative or 0, 1), MODES) if negative else MODES
        return values[:count], vectors[:, :count]
    symmetric = (0.5 * (k_ff + k_ff.T)).tocsc()
    if inverse is None:
        inverse = _inverse(symmetric)
        if inverse is None:
            return np.zeros(0), np.zeros((n, 0))
    wanted = min(negative, MODES, n - 2) if negative else min(MODES, n - 2)
    which = "SA" if negative else "LM"
    values, vectors, complete = _arpack(
        symmetric, wanted, SHIFT_INVERT_RESTARTS, sigma=0.0, which=which, OPinv=inverse
    )
    if negative:
        keep = values < 0.0
        values, vectors = values[keep], vectors[:, keep]
        if not complete or values.size < wanted:
            lowest, modes, _ = _arpack(symmetric, wanted, PLAIN_RESTARTS, which="SA")
            for value, phi in zip(lowest, modes.T):
                if value >= 0.0 or values.size >= wanted:
                    continue
                if np.linalg.norm(vectors.T @ phi) >= 0.5:
                    continue  # a mode the shift-invert found already
                values = np.append(values, value)
                vectors = np.column_stack([vectors, phi])
    order = np.argsort(values)
    return values[order], vectors[:, order]


def _inverse(symmetric) -> LinearOperator | None:
    """The inverse of ``symmetric`` (a sparse csc matrix) as a LinearOperator from its LU, or
    None when it is singular."""
    try:
        lu = splu(symmetric)
    except RuntimeError:
        return None
    return LinearOperator(symmetric.shape, matvec=lu.solve, dtype=float)


def _arpack(symmetric, k: int, restarts: int, **options) -> tuple[np.ndarray, np.ndarray, bool]:
    """ARPACK's ``eigsh`` of ``symmetric`` for ``k`` pairs with NCV vectors, at most
    ``restarts`` restarts and the tolerance RITZ_TOL, from a fixed start vector: (the
    eigenvalues, the eigenvectors, whether all k converged); the converged pairs only when not.

    A fixed start vector: ARPACK's default is a random one drawn from a generator that
    advances with every call in the process, so the modes (and a push decided on an
    eigenvalue near zero) would depend on what ran before in the same process."""
    n = symmetric.shape[0]
    start = np.random.default_rng(0).standard_normal(n)
    ncv = min(max(NCV, 2 * k + 1), n - 1)
    try:
        values, vectors = eigsh(
            symmetric, k=k, v0=start, ncv=ncv, maxiter=restarts, tol=RITZ_TOL, **options
        )
    except ArpackNoConvergence as partial:
        return partial.eigenvalues, partial.eigenvectors, False
    except RuntimeError:
        return np.zeros(0), np.zeros((n, 0)), False
    return values, vectors, True


def buckling_mode(run: StaticRun, pattern, previous: Motion | None = None) -> Motion | None:
    """The unit motion (no load change) along the lowest negative mode phi of the tangent
    at the last state of ``run`` (nearest zero; not a neutral one, solvers.neutral_modes), to
    the side where the loads do positive work; None if there is none, or if phi is the
    path's own direction: a limit point, which the arc length follows by itself. A limit
    point shows either way: the load pattern P drives the mode (|phi . P| > 0.1 |P|), or the
    mode is the last increment ``previous`` (the cosine of their scaled motions above 0.5; at
    a limit point the path's tangent is the null vector of K, while a bifurcation mode is
    transverse to the path). Under an imposed
    displacement P is spread over the whole model and phi may be local, so the first test
    alone took the limit point of bai-6.1.2 (Mindlin) for a bifurcation and sent the path
    back along itself.

    A mode along which a push is no descent (``push_descends``) gives None as well.

    ``pattern``: (forces, moments, imposed displacements) per unit load factor of the phase."""
    if not run.negative:  # no negative pivot in the factorisation: no mode to follow
        return None
    dofs, state = run.model.dofs, run.state
    frames = dofs.frames(state.directors)
    k_ff, k_fp = run.tangent(state, frames)
    factor = run.factorise(k_ff)
    # every negative pivot's mode, then those beyond round-off (solvers.neutral_modes)
    pivots = (factor.negative or 0) + factor.neutral
    values, vectors = unstable_modes(k_ff, lowest_modes(k_ff, pivots))
    if values.size == 0:
        return None
    phi = vectors[:, -1]  # the negative mode nearest zero (ascending)
    drive, _ = run.load_rate(pattern, frames, k_fp)
    if abs(phi @ drive) > 0.1 * np.linalg.norm(drive):
        return None
    equilibrium = run.equilibrium(run.reached)
    load = equilibrium.load(frames).ravel()[dofs.free_slots]
    chosen = (values[-1:], phi[:, None])
    translation = dofs.free_slots % N_COLUMNS < 3
    if not push_descends(run, state, frames, load, chosen, translation, factor, equilibrium):
        return None  # a saddle no push descends from (push_descends): the path goes on
    side = np.sign(phi @ load) or 1.0
    flat = np.zeros(dofs.n_slots)
    flat[dofs.free_slots] = side * phi
    motion = run.as_motion(flat.reshape(-1, N_COLUMNS), frames, 0.0, mode=True)
    if motion.length <= 0.0:
        return None
    if previous is not None and previous.length > 0.0:
        along = motion.vector @ previous.vector / (motion.length * previous.length)
        if abs(along) > 0.5:
            return None
    return motion
