"""Pieces of the pseudo-dynamic and dynamic solvers: the damped central-difference velocity
update that CentralDifference and DynamicRelaxation share, the energy account and its
divergence check, and the output schedule of frames.

The configuration update itself (move the nodes, turn the directors by finite rotations) is
``femcore.dofs.DofManager.move``, the one the static solver uses too.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from femcore.jit import chunk_size, chunk_sums, chunks, jit, prange, unsigned
from solvers.common import inverse_diagonal

__all__ = [
    "EnergyAccount",
    "FrameSchedule",
    "damped_velocity",
    "rotational_kinetic",
    "update_rates",
]


def damped_velocity(
    rate: np.ndarray, force: np.ndarray, inverse_mass: np.ndarray, dt_bar: float, damping: float
) -> np.ndarray:
    """Central-difference update of a nodal rate with mass-proportional damping C = c M
    (Bai Eq. 23 with damping, docs/theory.md §6.1):

        v(i+1/2) = [(1 - c dt_bar/2) v(i-1/2) + dt_bar M^-1 F(i)] / (1 + c dt_bar/2)

    Parameters
    ----------
    rate : (n, 3) float
        v(i-1/2): velocities (mm/s) or angular velocities (rad/s).
    force : (n, 3) float
        Out-of-balance forces (N) or moments (N mm) at t(i).
    inverse_mass : (n, 1) float
        1/m or 1/I per node, 0 where the node has no such DOF.
    dt_bar : float
        s, (dt_prev + dt) / 2.
    damping : float
        c, 1/s.
    """
    return ((1.0 - 0.5 * damping * dt_bar) * rate + dt_bar * inverse_mass * force) / (
        1.0 + 0.5 * damping * dt_bar
    )


def _update_rates(
    old, applied, internal, inverse_mass, mass, free, constrained, target, dt_bar, dt, dt_prev,
    damping, full, size, new, reactions, partial,
):  # fmt: skip
    """The central-difference update of one kind of nodal rate (velocities or angular
    velocities, (n, 3)) fused with its support reactions and energy terms, in one pass over
    the nodes (compiled by numba when it is installed, on the threads of femcore/jit.py);
    ``update_rates`` documents it. Each chunk of ``size`` nodes (femcore/jit.py ``CHUNK``,
    passed at each call) writes its energy terms to its row of ``partial`` (chunks, 8),
    summed in node order."""
    scale = 1.0 / (1.0 + 0.5 * damping * dt_bar)
    keep = 1.0 - 0.5 * damping * dt_bar
    n = old.shape[0]
    for chunk in prange(partial.shape[0]):
        d_ext = d_int = d_damp = kinetic = 0.0
        product = kinetic_mean = ext_before = damp_before = 0.0
        start = chunk * size
        for within in range(min(n - start, size)):
            i = unsigned(start + within)  # an index numba need not test for < 0
            m = mass[i]
            for j in range(3):
                v0 = old[i, j]
                v_free = (
                    keep * v0 + dt_bar * inverse_mass[i, 0] * (applied[i, j] - internal[i, j])
                ) * scale
                if free[i, j]:
                    v1 = v_free
                elif target.shape[0] > 0 and not np.isnan(target[i, j]):
                    v1 = target[i, j]
                else:
                    v1 = 0.0
                reaction = 0.0
                if constrained[i, j]:
                    reaction = m * (v1 - v_free) / (scale * dt_bar)
                new[i, j] = v1
                reactions[i, j] = reaction
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
        partial[chunk, 0], partial[chunk, 1] = d_ext, d_int
        partial[chunk, 2], partial[chunk, 3] = d_damp, kinetic
        partial[chunk, 4], partial[chunk, 5] = product, kinetic_mean
        partial[chunk, 6], partial[chunk, 7] = ext_before, damp_before


_update_rates = jit(_update_rates)


def update_rates(
    old: np.ndarray,
    applied: np.ndarray,
    internal: np.ndarray,
    mass: np.ndarray,
    free: np.ndarray,
    constrained: np.ndarray,
    target: np.ndarray | None,
    steps: tuple[float, float, float],
    damping: float,
    full: bool,
    inverse_mass: np.ndarray | None = None,
) -> tuple[np.ndarray, np.ndarray, tuple[float, ...]]:
    """One kind of nodal rate through a step: v(i+1/2) of ``damped_velocity`` where the DOF
    is free, the ``target`` rate (NaN: none) where it is prescribed, 0 where it is fixed; the
    support reactions (what the constraint adds to the momentum balance); and the energy
    terms of ``EnergyAccount.increments`` (the same sums in one pass).

    old, applied, internal : (n, 3) rates v(i-1/2) and external and internal loads at t(i).
    mass : (n,) lumped mass or inertia. free, constrained : (n, 3) bool. steps : (dt_bar, dt,
    dt_prev), s. inverse_mass : (n, 1) 1/m, 0 where m is not positive (default: made from
    ``mass``). Returns (new rates, reactions, energy terms)."""
    new = np.empty_like(old)
    reactions = np.empty_like(old)
    size = chunk_size()
    partial = np.empty((chunks(len(old), size), 8))
    dt_bar, dt, dt_prev = steps
    _update_rates(
        np.ascontiguousarray(old),
        np.ascontiguousarray(applied),
        np.ascontiguousarray(internal),
        inverse_diagonal(mass) if inverse_mass is None else inverse_mass,
        np.ascontiguousarray(mass, dtype=np.float64),
        np.ascontiguousarray(free),
        np.ascontiguousarray(constrained),
        np.zeros((0, 3)) if target is None else np.ascontiguousarray(target),
        dt_bar,
        dt,
        dt_prev,
        damping,
        full,
        size,
        new,
        reactions,
        partial,
    )
    terms = chunk_sums(partial)
    return new, reactions, tuple(float(t) for t in terms)


def rotational_kinetic(inertia: np.ndarray, omega: np.ndarray) -> float:
    """The directors' kinetic energy 1/2 sum_i I_i |omega_i|^2, N mm: the rotational part of
    the kinetic energy the explicit step counts (solvers/turning.py), over the rotary inertia
    in use (the Mindlin shell's scaled one, docs/theory.md §6.2 B2).

    Parameters
    ----------
    inertia : (n,) float
        Rotary inertia per node, t mm^2 (0 at nodes without rotations).
    omega : (n, 3) float
        Angular velocities, rad/s.
    """
    return 0.5 * float(np.sum(inertia * np.einsum("ij,ij->i", omega, omega)))


class EnergyAccount:
    """Kinetic energy, internal and external work and damping dissipation of an explicit run,
    with the records kept for the result (about ``records`` of them, thinned every ``thin``
    steps) and the blow-up check.

    Work over [t(i-1/2), t(i+1/2)] is taken with the forces at t(i) (midpoint rule).

    The records (``KEYS``, N mm; docs/theory.md §6.1, "The energy records"), each at
    t(i+1/2): "kinetic" 1/2 v.M v; "external_work" the work of the loads, the supports'
    reactions and the moving tools; "damping" the mass-proportional damping's dissipation;
    "friction" the interactions' dissipation D_f (Coulomb friction, contact damping: the
    mean of its values at t(i) and t(i+1)); "internal" the stored part of the internal
    forces' work, W_int - D_f (the strain energy, the contact and stick springs' energy),
    so that kinetic + internal + damping + friction = external_work.
    """

    KEYS = ("time", "kinetic", "internal", "external_work", "damping", "friction")
    #: Kept beside ``KEYS`` (not in the history's columns): the rotational part of "kinetic",
    #: 1/2 sum I |omega|^2 over the rotary inertia in use (docs/theory.md §6.3).
    ROTATIONAL = "kinetic_rotational"

    def __init__(self, thin: int):
        self.thin = thin
        self.kinetic = self.internal = self.external = self.dissipated = 0.0
        #: Energy the interactions dissipated (friction, contact damping) up to t(i+1/2) and
        #: up to the last committed state t(i+1) (``dissipate``), N mm.
        self.friction = 0.0
        self.friction_end = 0.0
        #: Sum of |external work increments|: the yardstick for a blow-up.
        self.work_scale = 0.0
        #: The largest energy of the run so far: the yardstick of the energy balance.
        self.largest = 0.0
        #: The kinetic energy after the first step (see ``check``).
        self.start: float | None = None
        self.records: dict[str, list[float]] = {k: [0.0] for k in self.KEYS}

    @staticmethod
    def increments(
        forces: tuple[np.ndarray, np.ndarray],
        rates: tuple[np.ndarray, np.ndarray],
        mass: np.ndarray,
        damping: float,
        dt_prev: float,
        dt: float,
        full: bool = True,
    ) -> tuple[float, ...]:
        """Energy terms of one kind of DOF over a step, ``forces`` = (external + reaction,
        internal) at t(i), ``rates`` = (old, new) at t(i -+ 1/2): the external, internal and
        damping work over [t(i - 1/2), t(i + 1/2)], the new kinetic energy, and for the checks
        at t(i): the kinetic energy 1/2 v(i-1/2) . M v(i+1/2) (the one the scheme conserves
        with the strain energy, docs/theory.md §6.1), that of the mean rate, and the external
        and damping work done before t(i), computed only when ``full`` (the steps that are
        checked; zeros otherwise)."""
        external, internal = forces
        old, new = rates
        dx = 0.5 * (dt_prev * old + dt * new)
        d_ext = float(np.sum(external * dx))
        d_int = float(np.sum(internal * dx))
        mean = 0.5 * (old + new)
        d_damp = float(np.sum(damping * mass[:, None] * mean * dx))
        kinetic = 0.5 * float(np.sum(mass[:, None] * new * new))
        if not full:
            return d_ext, d_int, d_damp, kinetic, 0.0, 0.0, 0.0, 0.0
        product = 0.5 * float(np.sum(mass[:, None] * old * new))
        kinetic_mean = 0.5 * float(np.sum(mass[:, None] * mean * mean))
        ext_before = float(np.sum(external * 0.5 * dt_prev * old))
        damp_before = float(np.sum(damping * mass[:, None] * old * 0.5 * dt_prev * old))
        return d_ext, d_int, d_damp, kinetic, product, kinetic_mean, ext_before, damp_before

    def blows_up(self, d_ext: float, d_int: float, d_damp: float, kinetic_new: float, *_) -> bool:
        """Count the step's external work into ``work_scale``, then judge it: energy
        conservation bounds the kinetic energy by the work done on the model; ten times that
        work means the integration is unstable. A fast blow-up shows here within the step; a
        slow one is ``check``'s."""
        self.work_scale += abs(d_ext)
        return (not np.isfinite(kinetic_new)) or kinetic_new > 10.0 * (
            self.work_scale + abs(self.internal)
        ) + 1e-300

    def accept(self, d_ext: float, d_int: float, d_damp: float, kinetic: float, *_) -> None:
        if self.start is None:
            self.start = kinetic
        self.kinetic = kinetic
        self.external += d_ext
        self.internal += d_int
        self.dissipated += d_damp

    def dissipate(self, total: float) -> None:
        """Take the interactions' dissipation ``total`` (N mm) at the state just committed,
        t(i+1): the records' friction is its value at t(i+1/2), the mean of those at t(i) and
        t(i+1), the midpoint rule of the works it is set beside (the internal work, which holds
        it, runs to t(i+1/2))."""
        self.friction = 0.5 * (self.friction_end + total)
        self.friction_end = total

    @property
    def stored(self) -> float:
        """The internal forces' work less what the interactions dissipated, W_int - D_f, N mm:
        the energy the model holds (the records' "internal")."""
        return self.internal - self.friction

    def check(
        self, work: tuple, strain_energy: float, friction: float = 0.0, onset: float = 0.0
    ) -> tuple[float, float]:
        """The two energy measures at t(i) of the step whose ``work`` terms were just
        accepted, U the strain energy of the configuration at t(i) (change from the start),
        D_f the energy friction dissipated up to t(i), ``onset`` (N mm, >= 0) the moving
        tools' work over [t(i-1/2), t(i)] with the contact forces at t(i):

        * the balance |KE* + U + D + D_f - W_ext| over the largest of these energies so far in the
          run, KE* = 1/2 v(i-1/2) . M v(i+1/2). For a linear model the central difference
          conserves KE* + U exactly, stable or not; what it measures is the integration error
          of a nonlinear one (a director driven through the surface, a contact, a law's
          knee). A deficit up to ``onset`` is not counted: a contact that began within the
          step has had its tool's work counted over the whole half step before t(i), (1 -
          sigma) of it before the spring engaged (sigma the share of the step it touched),
          a deficit that stays in the balance and is of the order of the energy itself at a
          first touch, whatever the step (docs/theory.md §6.1, "First touch");
        * the growth (KE + U) / (the work supplied, the sum of |dW_ext|), KE that of the mean
          velocity at t(i): what shows an instability, whose energy grows without the work
          that would feed it. A stable linear run keeps it below 1 / (1 - (omega dt / 2)^2)
          (docs/theory.md §6.1), 5.3 at omega dt = 1.8, the default safety of an exact
          step.

        Both inf for non-finite energies."""
        d_ext, _, d_damp, _, product, kinetic_mean, ext_before, damp_before = work
        external = self.external - d_ext + ext_before
        dissipated = self.dissipated - d_damp + damp_before
        dissipated += friction
        terms = (product, kinetic_mean, strain_energy, dissipated, external)
        if not all(np.isfinite(terms)):
            return float("inf"), float("inf")
        self.largest = max(self.largest, abs(product), kinetic_mean, abs(strain_energy))
        self.largest = max(self.largest, abs(dissipated), abs(external))
        balance = 0.0
        if self.largest > 0.0:
            # From rest the first half step starts at v(-1/2) = 0 where the conserved form
            # has -v(1/2): KE*(0) = -1/2 v(1/2) . M v(1/2), the first step's kinetic energy.
            total = product + strain_energy + dissipated - external + (self.start or 0.0)
            if total < 0.0:  # the first touch's over-counted tool work is a deficit only
                total = min(total + onset, 0.0)
            balance = abs(total) / self.largest
        growth = 0.0
        if self.work_scale > 0.0:
            growth = (kinetic_mean + strain_energy) / self.work_scale
        return balance, growth

    def record(self, step: int, time: float, rotational: Callable[[], float] | None = None) -> bool:
        """Keep the energies at ``time`` if the step is one of the thinned records: True;
        ``rotational`` gives the rotational part of the kinetic energy (N mm; called only for
        a kept record; None: 0)."""
        if step % self.thin:
            return False
        values = (time, self.kinetic, self.stored, self.external, self.dissipated, self.friction)
        for key, value in zip(self.KEYS, values):
            self.records[key].append(value)
        kept = self.records.get(self.ROTATIONAL)
        if kept is None:  # (a record made before it was kept: zeros for the earlier ones)
            kept = self.records[self.ROTATIONAL] = [0.0] * (len(self.records["time"]) - 1)
        kept.append(0.0 if rotational is None else rotational())
        return True

    def latest(self) -> tuple[float, ...]:
        """The last record: (time, kinetic, internal, external work, damping, friction)."""
        return tuple(self.records[key][-1] for key in self.KEYS)

    def arrays(self) -> dict[str, np.ndarray]:
        return {k: np.asarray(v) for k, v in self.records.items()}

    def drop_after(self, time: float) -> None:
        """Forget the records after ``time`` (s): a diverged run's records end with its last
        good state, as its frames do (the failed steps' energies are the blow-up's, not the
        model's)."""
        kept = sum(t <= time * (1.0 + 1e-12) for t in self.records["time"])
        for values in self.records.values():
            del values[kept:]


class FrameSchedule:
    """When to write a frame: every ``interval`` of time and at the end of ``duration``."""

    def __init__(self, interval: float, duration: float):
        self.interval = interval
        self.duration = duration
        self.next = interval

    def due(self, time: float) -> bool:
        """True (and the next output time moved past ``time``) when a frame is due."""
        if time >= self.next * (1.0 - 1e-9) or time >= self.duration * (1.0 - 1e-12):
            while self.next <= time * (1.0 + 1e-9):
                self.next += self.interval
            return True
        return False
