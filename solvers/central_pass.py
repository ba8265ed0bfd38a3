"""The whole nodal update of a central-difference step in one pass over the nodes (compiled by
numba when it is installed), docs/theory.md §6.1: for each node the damped update of its
velocities with the prescribed and fixed components and their support reactions
(``solvers.dynamics.update_rates``), its position moved by dt v(i+1/2), and the rotational
half of ``solvers.turning.turn`` (the moments without their drilling part, the damped
angular velocities under the director constraints, the support moments, the director turned
by dt omega), with the energy terms of both kinds of rate summed on the way.

Why: ``explicit_step`` makes these two passes one after the other (the velocities, then the
rotations reading them back), each with its own entry into compiled code and its own
temporaries; one pass reads each node's arrays once. It is the same arithmetic in the same
order, node by node: the translational and the rotational terms are summed apart, in node
order, as the two passes summed them, so that a step gives the same numbers to the last bit
as the two passes (tests/test_step.py).

Measured, it is not faster: on the arguments of a step of the 20k forming blank (10201 nodes,
one thread, best of 60 calls, CPU), 0.64-1.02 ms against 0.56-0.74 for the two passes with
the subnormals flushed (load 6.8), 2.53-3.28 against 2.46-2.97 without (load 8): the work is
arithmetic (a sine and a cosine a node for the directors' turn), not memory traffic, and the
one loop's larger body may keep LLVM from the simpler code it makes of the velocities' loop
alone. ``solvers.step.FUSED`` turns it on (off by default).
"""

from __future__ import annotations

import numpy as np

from solvers.turning import COMPILED, _held, turned

__all__ = ["COMPILED", "update_and_turn"]


def _update_and_turn(
    velocity, applied, internal, inverse_mass, mass, free, constrained, target, omega,
    applied_moment, internal_moment, directors, positions, inertia, has_rotation, fixed_alpha,
    fixed_beta, dt_bar, dt, dt_prev, damping, full, new_velocity, reactions, new_omega,
    reaction_moments, new_directors, new_positions, terms, turning,
):  # fmt: skip
    """See ``update_and_turn``; the outputs are written into the (n, 3) arrays new_velocity,
    reactions, new_omega, reaction_moments, new_directors, new_positions and the (8,) arrays
    terms (translations) and turning (rotations)."""
    scale = 1.0 / (1.0 + 0.5 * damping * dt_bar)
    keep = 1.0 - 0.5 * damping * dt_bar
    prescribed = target.shape[0] > 0
    # the translations' sums (solvers/dynamics.py ``_update_rates``)
    d_ext = d_int = d_damp = kinetic = 0.0
    product = kinetic_mean = ext_before = damp_before = 0.0
    # the rotations' sums (solvers/turning.py ``_turn``)
    r_ext = r_int = r_damp = r_kinetic = 0.0
    r_product = r_kinetic_mean = r_ext_before = r_damp_before = 0.0
    for i in range(velocity.shape[0]):
        m = mass[i]
        for j in range(3):
            v0 = velocity[i, j]
            v_free = (
                keep * v0 + dt_bar * inverse_mass[i, 0] * (applied[i, j] - internal[i, j])
            ) * scale
            if free[i, j]:
                v1 = v_free
            elif prescribed and not np.isnan(target[i, j]):
                v1 = target[i, j]
            else:
                v1 = 0.0
            reaction = 0.0
            if constrained[i, j]:
                reaction = m * (v1 - v_free) / (scale * dt_bar)
            new_velocity[i, j] = v1
            reactions[i, j] = reaction
            new_positions[i, j] = positions[i, j] + dt * v1
            external = applied[i, j] + reaction
            dx = 0.5 * (dt_prev * v0 + dt * v1)
            d_ext += external * dx
            d_int += internal[i, j] * dx
            d_damp += damping * m * 0.5 * (v0 + v1) * dx
            kinetic += 0.5 * m * v1 * v1
            if full:
                mean = 0.5 * (v0 + v1)
                product += 0.5 * m * v0 * v1
                kinetic_mean += 0.5 * m * mean * mean
                ext_before += external * 0.5 * dt_prev * v0
                damp_before += damping * m * v0 * 0.5 * dt_prev * v0
        # the rotations: solvers/turning.py ``_turn``'s formulas
        vx, vy, vz = directors[i, 0], directors[i, 1], directors[i, 2]
        mx = applied_moment[i, 0] - internal_moment[i, 0]
        my = applied_moment[i, 1] - internal_moment[i, 1]
        mz = applied_moment[i, 2] - internal_moment[i, 2]
        along = mx * vx + my * vy + mz * vz
        mx, my, mz = mx - along * vx, my - along * vy, mz - along * vz
        jj = inertia[i]
        inverse = 1.0 / jj if jj > 0.0 else 0.0
        fx = (keep * omega[i, 0] + dt_bar * inverse * mx) * scale
        fy = (keep * omega[i, 1] + dt_bar * inverse * my) * scale
        fz = (keep * omega[i, 2] + dt_bar * inverse * mz) * scale
        if has_rotation[i]:
            wx, wy, wz = _held(fx, fy, fz, vx, vy, vz, fixed_alpha[i], fixed_beta[i])
        else:
            wx = wy = wz = 0.0
        new_omega[i, 0], new_omega[i, 1], new_omega[i, 2] = wx, wy, wz
        factor = jj * (1.0 + 0.5 * damping * dt_bar) / dt_bar
        rx, ry, rz = factor * (wx - fx), factor * (wy - fy), factor * (wz - fz)
        reaction_moments[i, 0], reaction_moments[i, 1], reaction_moments[i, 2] = rx, ry, rz
        for k in range(3):
            old = omega[i, k]
            new = wx if k == 0 else (wy if k == 1 else wz)
            external = applied_moment[i, k] + (rx if k == 0 else (ry if k == 1 else rz))
            dx = 0.5 * (dt_prev * old + dt * new)
            mean = 0.5 * (old + new)
            r_ext += external * dx
            r_int += internal_moment[i, k] * dx
            r_damp += damping * jj * mean * dx
            r_kinetic += 0.5 * jj * new * new
            if full:
                r_product += 0.5 * jj * old * new
                r_kinetic_mean += 0.5 * jj * mean * mean
                r_ext_before += external * 0.5 * dt_prev * old
                r_damp_before += damping * jj * old * 0.5 * dt_prev * old
        if not has_rotation[i]:
            new_directors[i, 0], new_directors[i, 1], new_directors[i, 2] = vx, vy, vz
            continue
        new_directors[i, 0], new_directors[i, 1], new_directors[i, 2] = turned(
            vx, vy, vz, dt * wx, dt * wy, dt * wz
        )
    terms[0], terms[1], terms[2], terms[3] = d_ext, d_int, d_damp, kinetic
    terms[4], terms[5], terms[6], terms[7] = product, kinetic_mean, ext_before, damp_before
    turning[0], turning[1], turning[2], turning[3] = r_ext, r_int, r_damp, r_kinetic
    turning[4], turning[5] = r_product, r_kinetic_mean
    turning[6], turning[7] = r_ext_before, r_damp_before


if COMPILED:
    import numba

    _update_and_turn = numba.njit(cache=True)(_update_and_turn)


def _loop(array: np.ndarray) -> np.ndarray:
    """``array`` as the loop reads it: C-contiguous float64 (no copy when it is already)."""
    return np.ascontiguousarray(array, dtype=np.float64)


def update_and_turn(
    rates: tuple[np.ndarray, np.ndarray],
    forces: tuple[np.ndarray, np.ndarray],
    moments: tuple[np.ndarray, np.ndarray],
    motion: tuple[np.ndarray, np.ndarray],
    masses: tuple[np.ndarray, np.ndarray, np.ndarray],
    translation: tuple[np.ndarray, np.ndarray, np.ndarray | None],
    rotation: tuple[np.ndarray, np.ndarray],
    steps: tuple[float, float, float],
    damping: float,
    full: bool,
) -> tuple[
    np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray, tuple[float, ...],
    tuple[float, ...],
]:  # fmt: skip
    """The nodal update of one central-difference step in one pass: what
    ``solvers.dynamics.update_rates`` then ``solvers.turning.turn`` give, to the last bit.

    Parameters
    ----------
    rates : (v(i-1/2), omega(i-1/2)), (n, 3) each, mm/s and rad/s.
    forces : (external, internal) nodal forces at t(i), (n, 3) each, N.
    moments : (external, internal) moment vectors at t(i), (n, 3) each, N mm.
    motion : (positions, directors) at t(i), (n, 3) each, mm and unit vectors.
    masses : (mass (n,) t, inverse mass (n, 1) 1/t (0 where m is not positive), rotary
        inertia (n,) t mm^2, 0 at nodes without rotations).
    translation : (free, constrained) (n, 3) bool, and the prescribed rates (n, 3) mm/s (NaN:
        none) or None.
    rotation : has_rotation (n,) bool, rotation_fixed (n, 2) bool (alpha, beta held).
    steps : (dt_bar, dt, dt_prev), s. damping : c, 1/s. full : the energy terms of the checks
        too.

    Returns
    -------
    (v(i+1/2), reactions, omega(i+1/2), support moments, directors at t(i+1), positions at
    t(i+1)), (n, 3) each; the 8 energy terms of the translations and those of the rotations
    (``EnergyAccount.increments``), N mm, as two tuples.
    """
    velocity, omega = rates
    applied, internal = forces
    applied_moment, internal_moment = moments
    positions, directors = motion
    mass, inverse_mass, inertia = masses
    free, constrained, target = translation
    has_rotation, rotation_fixed = rotation
    dt_bar, dt, dt_prev = steps
    n = len(velocity)
    velocity_new, reactions, omega_new = np.empty((n, 3)), np.empty((n, 3)), np.empty((n, 3))
    moments_new, directors_new, positions_new = np.empty((n, 3)), np.empty((n, 3)), np.empty((n, 3))
    terms, turning = np.zeros(8), np.zeros(8)
    fixed = np.ascontiguousarray(rotation_fixed)
    _update_and_turn(
        _loop(velocity), _loop(applied), _loop(internal), _loop(inverse_mass).reshape(n, 1),
        _loop(mass), np.ascontiguousarray(free), np.ascontiguousarray(constrained),
        np.zeros((0, 3)) if target is None else _loop(target), _loop(omega),
        _loop(applied_moment), _loop(internal_moment), _loop(directors), _loop(positions),
        _loop(inertia), np.ascontiguousarray(has_rotation), np.ascontiguousarray(fixed[:, 0]),
        np.ascontiguousarray(fixed[:, 1]), float(dt_bar), float(dt), float(dt_prev),
        float(damping), bool(full), velocity_new, reactions, omega_new, moments_new,
        directors_new, positions_new, terms, turning,
    )  # fmt: skip
    return (
        velocity_new, reactions, omega_new, moments_new, directors_new, positions_new,
        tuple(float(t) for t in terms), tuple(float(t) for t in turning),
    )  # fmt: skip
