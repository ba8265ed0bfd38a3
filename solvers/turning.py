"""The rotational half of an explicit step in one pass over the nodes (compiled by numba when
it is installed): the out-of-balance moments without their drilling part, the damped update
of the angular velocities, the director constraints (no drilling rate, fixed alpha / beta),
the support moments, the energy terms of the rotations, and the directors turned by the
finite rotations dt omega (Rodrigues) with the positions moved by dt v.

It does in one loop what the damped update of ``solvers.dynamics.damped_velocity``,
``CompiledModel.constrain_angular``, ``EnergyAccount.increments`` and ``DofManager.move`` do
in a dozen numpy passes over (n, 3) arrays (a fifth of a Mindlin step at 100k triangles);
``solvers.step.rotational_update`` is that numpy reference, and the tests hold the two to
1e-12. ``rates`` and ``move`` are the same loops without the energy terms: the
``angular_rates`` and ``advance`` that dynamic relaxation moves with. The loops run over
the nodes on the threads of femcore/jit.py (each node's update is its own, the same on any
thread count); ``_turn`` sums its energy terms a chunk of ``CHUNK`` nodes at a time, in node
order within a chunk, and the chunks' sums in chunk order (``chunk_sums``): the same to the
last bit on any number of threads. Serial, the rotation update of the 100k-triangle forming
blank was a fifth of the step's part that did not run on two threads (1.5 of 7 ms:
benchmarks/threads.py).
"""

from __future__ import annotations

import numpy as np

from femcore import kernel_cache
from femcore.jit import chunk_size, chunk_sums, chunks, jit, prange, unsigned
from femcore.rotation import frame_of, turned

__all__ = ["COMPILED", "move", "rates", "turn"]


def _held(fx, fy, fz, vx, vy, vz, alpha, beta):
    """The angular rate (fx, fy, fz) of a node with rotations under its director
    constraints: without its drilling part along the director (vx, vy, vz), and without its
    part along V2 (``alpha``: alpha held) and along V1 (``beta``) of the nodal frame."""
    along = fx * vx + fy * vy + fz * vz
    wx, wy, wz = fx - along * vx, fy - along * vy, fz - along * vz
    if alpha or beta:
        ax, ay, az, bx, by, bz = frame_of(vx, vy, vz)
        if alpha:
            along = wx * bx + wy * by + wz * bz
            wx, wy, wz = wx - along * bx, wy - along * by, wz - along * bz
        if beta:
            along = wx * ax + wy * ay + wz * az
            wx, wy, wz = wx - along * ax, wy - along * ay, wz - along * az
    return wx, wy, wz


def _turn(
    omega, applied, internal, directors, positions, velocities, inertia, has_rotation,
    fixed_alpha, fixed_beta, dt_bar, dt, dt_prev, damping, full, size,
    new_omega, reaction, new_directors, new_positions, partial,
):  # fmt: skip
    """See ``turn``; the outputs are written into new_omega, reaction, new_directors,
    new_positions (n, 3) and partial (chunks, 8): each chunk's energy terms (``chunks``), a
    chunk ``size`` nodes (femcore/jit.py ``CHUNK``, passed at each call)."""
    scale = 1.0 / (1.0 + 0.5 * damping * dt_bar)
    keep = 1.0 - 0.5 * damping * dt_bar
    n = omega.shape[0]
    for chunk in prange(partial.shape[0]):
        d_ext = d_int = d_damp = kinetic = 0.0
        product = kinetic_mean = ext_before = damp_before = 0.0
        start = chunk * size
        for within in range(min(n - start, size)):
            i = unsigned(start + within)  # an index numba need not test for < 0
            new_positions[i, 0] = positions[i, 0] + dt * velocities[i, 0]
            new_positions[i, 1] = positions[i, 1] + dt * velocities[i, 1]
            new_positions[i, 2] = positions[i, 2] + dt * velocities[i, 2]
            vx, vy, vz = directors[i, 0], directors[i, 1], directors[i, 2]
            mx = applied[i, 0] - internal[i, 0]
            my = applied[i, 1] - internal[i, 1]
            mz = applied[i, 2] - internal[i, 2]
            along = mx * vx + my * vy + mz * vz
            mx, my, mz = mx - along * vx, my - along * vy, mz - along * vz
            j = inertia[i]
            inverse = 1.0 / j if j > 0.0 else 0.0
            fx = (keep * omega[i, 0] + dt_bar * inverse * mx) * scale
            fy = (keep * omega[i, 1] + dt_bar * inverse * my) * scale
            fz = (keep * omega[i, 2] + dt_bar * inverse * mz) * scale
            if has_rotation[i]:
                wx, wy, wz = _held(fx, fy, fz, vx, vy, vz, fixed_alpha[i], fixed_beta[i])
            else:
                wx = wy = wz = 0.0
            new_omega[i, 0], new_omega[i, 1], new_omega[i, 2] = wx, wy, wz
            factor = j * (1.0 + 0.5 * damping * dt_bar) / dt_bar
            rx, ry, rz = factor * (wx - fx), factor * (wy - fy), factor * (wz - fz)
            reaction[i, 0], reaction[i, 1], reaction[i, 2] = rx, ry, rz
            for k in range(3):
                old = omega[i, k]
                new = wx if k == 0 else (wy if k == 1 else wz)
                external = applied[i, k] + (rx if k == 0 else (ry if k == 1 else rz))
                dx = 0.5 * (dt_prev * old + dt * new)
                mean = 0.5 * (old + new)
                d_ext += external * dx
                d_int += internal[i, k] * dx
                d_damp += damping * j * mean * dx
                kinetic += 0.5 * j * new * new
                if full:
                    product += 0.5 * j * old * new
                    kinetic_mean += 0.5 * j * mean * mean
                    ext_before += external * 0.5 * dt_prev * old
                    damp_before += damping * j * old * 0.5 * dt_prev * old
            if not has_rotation[i]:
                new_directors[i, 0], new_directors[i, 1], new_directors[i, 2] = vx, vy, vz
                continue
            # femcore.rotation.rotate_about, the rotation dt omega
            new_directors[i, 0], new_directors[i, 1], new_directors[i, 2] = turned(
                vx, vy, vz, dt * wx, dt * wy, dt * wz
            )
        partial[chunk, 0], partial[chunk, 1] = d_ext, d_int
        partial[chunk, 2], partial[chunk, 3] = d_damp, kinetic
        partial[chunk, 4], partial[chunk, 5] = product, kinetic_mean
        partial[chunk, 6], partial[chunk, 7] = ext_before, damp_before


def _rates(omega, moment, inverse, has_rotation, fixed_alpha, fixed_beta, directors, dt_bar,
           damping, free, held):  # fmt: skip
    """``solvers.step.angular_rates`` in one loop: the damped update of the angular
    velocities into ``free`` and the same with the director constraints into ``held``
    (n, 3) (the formulas of ``_turn``)."""
    scale = 1.0 / (1.0 + 0.5 * damping * dt_bar)
    keep = 1.0 - 0.5 * damping * dt_bar
    for i in prange(omega.shape[0]):
        fx = (keep * omega[i, 0] + dt_bar * inverse[i] * moment[i, 0]) * scale
        fy = (keep * omega[i, 1] + dt_bar * inverse[i] * moment[i, 1]) * scale
        fz = (keep * omega[i, 2] + dt_bar * inverse[i] * moment[i, 2]) * scale
        free[i, 0], free[i, 1], free[i, 2] = fx, fy, fz
        if not has_rotation[i]:
            held[i, 0] = held[i, 1] = held[i, 2] = 0.0
            continue
        vx, vy, vz = directors[i, 0], directors[i, 1], directors[i, 2]
        wx, wy, wz = _held(fx, fy, fz, vx, vy, vz, fixed_alpha[i], fixed_beta[i])
        held[i, 0], held[i, 1], held[i, 2] = wx, wy, wz


def _move(positions, directors, velocities, omega, dt, has_rotation, new_positions,
          new_directors):  # fmt: skip
    """``solvers.step.advance`` in one loop: positions + dt v, the directors turned by
    dt omega where they have rotations (the formulas of ``_turn``)."""
    for i in prange(positions.shape[0]):
        new_positions[i, 0] = positions[i, 0] + dt * velocities[i, 0]
        new_positions[i, 1] = positions[i, 1] + dt * velocities[i, 1]
        new_positions[i, 2] = positions[i, 2] + dt * velocities[i, 2]
        vx, vy, vz = directors[i, 0], directors[i, 1], directors[i, 2]
        if not has_rotation[i]:
            new_directors[i, 0], new_directors[i, 1], new_directors[i, 2] = vx, vy, vz
            continue
        new_directors[i, 0], new_directors[i, 1], new_directors[i, 2] = turned(
            vx, vy, vz, dt * omega[i, 0], dt * omega[i, 1], dt * omega[i, 2]
        )


#: Whether the loops are compiled (numba installed): without, ``solvers.step`` keeps its
#: numpy passes for ``angular_rates`` and ``advance``.
COMPILED = False
if kernel_cache.AVAILABLE:
    _held = kernel_cache.njit(_held)
    _turn = jit(_turn)
    _rates = jit(_rates)
    _move = jit(_move)
    COMPILED = True


def rates(
    omega: np.ndarray,
    moment: np.ndarray,
    inverse_inertia: np.ndarray,
    has_rotation: np.ndarray,
    rotation_fixed: np.ndarray,
    directors: np.ndarray,
    dt_bar: float,
    damping: float,
) -> tuple[np.ndarray, np.ndarray]:
    """(free, held) omega(i+1/2) (n, 3) of ``solvers.step.angular_rates`` in one pass:
    omega (n, 3) rad/s, moment (n, 3) N mm, inverse_inertia (n, 1) or (n,) 1/I, has_rotation
    (n,) bool, rotation_fixed (n, 2) bool, directors (n, 3), dt_bar s, damping 1/s."""
    n = len(omega)
    free, held = np.empty((n, 3)), np.empty((n, 3))
    fixed = np.asarray(rotation_fixed)
    _rates(
        np.ascontiguousarray(omega, dtype=np.float64),
        np.ascontiguousarray(moment, dtype=np.float64),
        np.ascontiguousarray(np.asarray(inverse_inertia, dtype=np.float64).reshape(n)),
        np.ascontiguousarray(has_rotation),
        np.ascontiguousarray(fixed[:, 0]),
        np.ascontiguousarray(fixed[:, 1]),
        np.ascontiguousarray(directors, dtype=np.float64),
        float(dt_bar),
        float(damping),
        free,
        held,
    )
    return free, held


def move(
    positions: np.ndarray,
    directors: np.ndarray,
    velocities: np.ndarray,
    omega: np.ndarray,
    dt: float,
    has_rotation: np.ndarray,
) -> tuple[np.ndarray, np.ndarray]:
    """(positions + dt v, directors turned by dt omega where ``has_rotation``), (n, 3) each,
    in one pass (``solvers.step.advance``)."""
    n = len(positions)
    new_positions, new_directors = np.empty((n, 3)), np.empty((n, 3))
    _move(
        np.ascontiguousarray(positions, dtype=np.float64),
        np.ascontiguousarray(directors, dtype=np.float64),
        np.ascontiguousarray(velocities, dtype=np.float64),
        np.ascontiguousarray(omega, dtype=np.float64),
        float(dt),
        np.ascontiguousarray(has_rotation),
        new_positions,
        new_directors,
    )
    return new_positions, new_directors


def turn(
    omega: np.ndarray,
    moments: tuple[np.ndarray, np.ndarray],
    directors: np.ndarray,
    motion: tuple[np.ndarray, np.ndarray],
    inertia: np.ndarray,
    has_rotation: np.ndarray,
    rotation_fixed: np.ndarray,
    steps: tuple[float, float, float],
    damping: float,
    full: bool,
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, tuple[float, ...]]:
    """The rotational update of one central-difference step, and the positions moved.

    Parameters
    ----------
    omega : (n, 3) angular velocities omega(i-1/2), rad/s.
    moments : (applied, internal), (n, 3) each, the external and internal moment vectors at
        t(i), N mm.
    directors : (n, 3) unit directors at t(i).
    motion : (positions at t(i), velocities v(i+1/2)), (n, 3) each, mm and mm/s.
    inertia : (n,) rotary inertia, t mm^2 (0: no rotation).
    has_rotation : (n,) bool. rotation_fixed : (n, 2) bool, alpha and beta held.
    steps : (dt_bar, dt, dt_prev), s. damping : c, 1/s. full : the energy terms of the checks
        too.

    Returns
    -------
    (omega(i+1/2), support moments, directors at t(i+1), positions at t(i+1)), (n, 3) each,
    and the 8 energy terms of ``EnergyAccount.increments`` for the rotations, N mm.
    """
    positions, velocities = motion
    applied, internal = moments
    n = len(omega)
    new_omega, reaction = np.empty((n, 3)), np.empty((n, 3))
    new_directors, new_positions = np.empty((n, 3)), np.empty((n, 3))
    size = chunk_size()
    partial = np.empty((chunks(n, size), 8))
    dt_bar, dt, dt_prev = steps
    fixed = np.ascontiguousarray(rotation_fixed)
    _turn(
        np.ascontiguousarray(omega, dtype=np.float64),
        np.ascontiguousarray(applied, dtype=np.float64),
        np.ascontiguousarray(internal, dtype=np.float64),
        np.ascontiguousarray(directors, dtype=np.float64),
        np.ascontiguousarray(positions, dtype=np.float64),
        np.ascontiguousarray(velocities, dtype=np.float64),
        np.ascontiguousarray(inertia, dtype=np.float64),
        np.ascontiguousarray(has_rotation),
        np.ascontiguousarray(fixed[:, 0]),
        np.ascontiguousarray(fixed[:, 1]),
        float(dt_bar),
        float(dt),
        float(dt_prev),
        float(damping),
        bool(full),
        size,
        new_omega,
        reaction,
        new_directors,
        new_positions,
        partial,
    )
    terms = chunk_sums(partial)
    return new_omega, reaction, new_directors, new_positions, tuple(float(t) for t in terms)
