"""Stability of the static solver's equilibria (solvers.static.Static, ``seek_stable``;
docs/theory.md §6.5, §6.6).

The number of negative eigenvalues of the tangent K_ff of a converged state is the number of
negative pivots of its LDL^T (Sylvester's law of inertia; solvers.linear counts them, the run
keeps the count of each frame). A non-zero count is an unstable equilibrium: a compressed
plate that stayed flat, the part of a path beyond a limit point. Two ways off it:

- ``downhill``: a Newton step on an indefinite tangent heads for the nearest equilibrium,
  stable or not; its components along the negative modes are turned downhill, and a converged
  saddle is pushed by half an element along its mode (the load path);
- ``buckling_mode``: where the count grows while the load still rises, the lowest negative
  mode, if it is a bifurcation mode (not driven by the load, not along the path), is where the
  next arc-length increment starts.

Both use the lowest modes of the symmetric part of K_ff (``lowest_modes``). A converged saddle
is left only when a push along one of its negative modes is a descent (``push_descends``): the
total potential energy evaluated at the pushed state is lower by more than round-off. A
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

if TYPE_CHECKING:
    from solvers.arc_length import Motion
    from solvers.static import StaticRun

__all__ = ["MODES", "PUSH", "buckling_mode", "downhill", "lowest_modes", "push_descends"]

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
# for the largest translation of the mode.
PUSH = 0.5


def downhill(
    k_ff, rhs, delta, load, translation, size, push, negative=None, modes=None
) -> np.ndarray:
    """The Newton step with its components along the negative modes of K_ff turned downhill.

    A Newton step heads for the nearest equilibrium, stable or not. Along a mode phi with
    eigenvalue lambda < 0 (of the symmetric part), its component (phi . r) / lambda climbs
    the energy towards the saddle; the step is given the component (phi . r) / |lambda|
    instead, at least half an element long when ``push`` (leaving a converged saddle), in the
    direction where the external load does positive work (gravity picks the buckling side).

    k_ff : the tangent of the free DOFs; rhs, delta, load : (n_free,) the right-hand side, the
    Newton step and the external load on the free DOFs; translation : (n_free,) bool, the
    translation slots; size : the element size, mm; negative : the negative pivots of K_ff;
    modes : (eigenvalues, eigenvectors) of ``lowest_modes`` already computed for K_ff.
    """
    values, vectors = lowest_modes(k_ff, negative) if modes is None else modes
    delta = delta.copy()
    for value, phi in zip(values, vectors.T):
        if value >= 0.0:
            continue
        along = phi @ rhs
        wanted = along / abs(value)
        reach = np.abs(phi[translation]).max(initial=0.0)
        if push and reach > 0.0 and abs(wanted) < PUSH * size / reach:
            side = np.sign(phi @ load) or np.sign(along) or 1.0
            wanted = side * PUSH * size / reach
        delta += (wanted - phi @ delta) * phi
    return delta


def push_descends(run: StaticRun, state, frames, load, modes, translation) -> bool:
    """Whether pushing the converged ``state`` along one of its negative modes lowers the total
    potential energy by more than round-off.

    Each mode phi with eigenvalue < 0 is tried on both sides, moved so that its largest
    translation is PUSH elements (the push of ``downhill``); the change of the total potential
    is W(pushed) - W(state) - load . (a phi), the dead loads' work along the straight push
    (prescribed DOFs held). Round-off: 1e-10 of the strain energies, as in the line search.
    A mode with no translation is taken as a descent (nothing to measure it by; ``downhill``
    does not push it).

    run : the StaticRun; state : the converged state; frames : its nodal frames; load :
    (n_free,) the external load on the free DOFs, N and N mm; modes : (eigenvalues (k,),
    unit eigenvectors (n_free, k)) of ``lowest_modes``; translation : (n_free,) bool.
    """
    model = run.model
    dofs = model.dofs
    values, vectors = modes
    before = run.energy(state)
    for value, phi in zip(values, vectors.T):
        if value >= 0.0:
            continue
        reach = np.abs(phi[translation]).max(initial=0.0)
        if reach <= 0.0:
            return True
        amplitude = PUSH * model.element_size / reach
        for side in (1.0, -1.0):
            flat = np.zeros(dofs.n_slots)
            flat[dofs.free_slots] = side * amplitude * phi
            pushed = dofs.advance(state, flat.reshape(-1, N_COLUMNS), frames)
            after = run.energy(pushed)
            change = after - before - side * amplitude * float(phi @ load)
            if change < -1e-10 * (abs(before) + abs(after)):
                return True
    return False


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
    at the last state of ``run``, to the side where the loads do positive work; None if there
    is none, or if phi is the path's own direction: a limit point, which the arc length
    follows by itself. A limit point shows either way: the load pattern P drives the mode
    (|phi . P| > 0.1 |P|), or the mode is the last increment ``previous`` (the cosine of
    their scaled motions above 0.5; at a limit point the path's tangent is the null
    vector of K, while a bifurcation mode is transverse to the path). Under an imposed
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
    values, vectors = lowest_modes(k_ff, run.negative)
    negative = np.flatnonzero(values < 0.0)
    if negative.size == 0:
        return None
    phi = vectors[:, negative[np.argmax(values[negative])]]
    drive, _ = run.load_rate(pattern, frames, k_fp)
    if abs(phi @ drive) > 0.1 * np.linalg.norm(drive):
        return None
    load = run.equilibrium(run.reached).load(frames).ravel()[dofs.free_slots]
    chosen = (values[negative][-1:], phi[:, None])
    if not push_descends(run, state, frames, load, chosen, dofs.free_slots % N_COLUMNS < 3):
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
