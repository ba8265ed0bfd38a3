"""The core's rotational DOF machinery (docs/theory.md §1.2-1.3, §6.1, §6.4), checked before any
shell
element exists with a test-only element, ``DirectorSpring``: a rotational spring at each node
that pulls the director back to its reference direction.

Everything here has a closed-form answer because the spring moment k theta acts about the axis
V0 x V: under a moment perpendicular to V0 the director turns in one plane, about a fixed axis,
and the nodal problem is the 1-DOF oscillator I theta'' + k theta = M.
"""

from __future__ import annotations

import numpy as np
import pytest

from elements.base import ElementBlock, ElementType
from femcore import Mesh, Model
from femcore.rotation import rotate_about
from femcore.state import State
from solvers import CentralDifference, DynamicRelaxation

E1, E2, E3 = np.eye(3)


# ------------------------------------------------------------------------------ test element
class DirectorSpring(ElementType):
    """Rotational spring W = 1/2 k theta^2 per node, theta = angle(V0, V) (test only).

    stiffness : k, N mm / rad (0 allowed: a free director).
    mass : translational mass of each node, t.
    inertia : rotary inertia of each node, t mm^2.

    Mass, inertia and spring belong to the *nodes* of the block's triangles, not to its cells:
    a node shared by several triangles still gets exactly one mass, one inertia and one spring,
    so the closed-form answers do not depend on how many triangles meet at a node.
    """

    cell_type = "triangle"
    dofs = ("ux", "uy", "uz", "alpha", "beta")
    defines_directors = True

    def __init__(self, stiffness: float, mass: float, inertia: float):
        if not (np.isfinite(stiffness) and stiffness >= 0):
            raise ValueError(f"stiffness must be >= 0 (N mm/rad), got {stiffness!r}")
        if not (np.isfinite(mass) and mass > 0 and np.isfinite(inertia) and inertia > 0):
            raise ValueError(f"mass and inertia must be > 0, got {mass!r}, {inertia!r}")
        self.stiffness = float(stiffness)
        self.mass = float(mass)
        self.inertia = float(inertia)

    def bind(self, mesh: Mesh, cell_ids: np.ndarray, directors: np.ndarray) -> DirectorSpringBlock:
        return DirectorSpringBlock(self, mesh, cell_ids, directors)


class DirectorSpringBlock(ElementBlock):
    """Node-level block: every array below is over ``nodes``, the unique nodes of the cells."""

    dofs = DirectorSpring.dofs
    cell_type = DirectorSpring.cell_type
    reach = 1

    def __init__(self, spring: DirectorSpring, mesh: Mesh, cell_ids, directors):
        self.material = spring
        self.n_nodes = mesh.n_nodes
        self.cell_ids = np.asarray(cell_ids, dtype=np.int64)
        self.connectivity = mesh.triangles[self.cell_ids]
        self.nodes = np.unique(self.connectivity)
        self.reference_directors = np.array(directors[self.nodes], dtype=float)  # V0, (p, 3)

    def _angles(self, state: State):
        """theta (p,) in [0, pi] and the unit axis (V0 x V)/|V0 x V| (p, 3), zero at theta = 0."""
        v0 = self.reference_directors
        cross = np.cross(v0, state.directors[self.nodes])
        sine = np.linalg.norm(cross, axis=1)
        cosine = np.sum(v0 * state.directors[self.nodes], axis=1)
        theta = np.arctan2(sine, cosine)  # accurate at small and large angles alike
        axis = np.where(sine[:, None] > 0, cross / np.where(sine > 0, sine, 1.0)[:, None], 0.0)
        return theta, axis

    def lumped_mass(self, state: State, density_scale=None):
        scale = np.ones(self.n_nodes)
        if density_scale is not None:  # a node takes the largest factor of its cells
            np.maximum.at(scale, self.connectivity.ravel(), np.repeat(density_scale, 3))
        mass = np.zeros(self.n_nodes)
        inertia = np.zeros(self.n_nodes)
        mass[self.nodes] = self.material.mass * scale[self.nodes]
        inertia[self.nodes] = self.material.inertia * scale[self.nodes]
        return mass, inertia

    def internal_force(self, state: State, history=None):
        # dW/dpsi: a small rotation psi changes theta by psi . (V0 x V)/|V0 x V|.
        theta, axis = self._angles(state)
        moment = np.zeros((self.n_nodes, 3))
        moment[self.nodes] = (self.material.stiffness * theta)[:, None] * axis
        return np.zeros((self.n_nodes, 3)), moment

    def cell_stable_dt(self, state: State) -> np.ndarray:
        # Each node is an oscillator omega = sqrt(k / I); the translations carry no stiffness.
        # k = 0 has no stability limit (inf): solvers must then be given a fixed dt.
        k, inertia = self.material.stiffness, self.material.inertia
        node_dt = np.full(self.n_nodes, np.inf)
        if k > 0:
            node_dt[self.nodes] = 2.0 / np.sqrt(k / inertia)
        return node_dt[self.connectivity].min(axis=1)

    def strain_energy(self, state: State, history=None) -> float:
        theta, _ = self._angles(state)
        return float(0.5 * self.material.stiffness * np.sum(theta**2))


# ------------------------------------------------------------------------------ helpers
def two_triangles() -> Mesh:
    """Unit square in z = 0 split into two counter-clockwise triangles: directors V0 = +e3."""
    points = [[0.0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]]
    return Mesh(points, triangles=[[0, 1, 2], [0, 2, 3]])


def spring_model(k: float, mass: float = 1.0, inertia: float = 1.0) -> Model:
    """Two triangles of DirectorSpring with every translation fixed."""
    model = Model(two_triangles())
    model.add(DirectorSpring(k, mass, inertia))
    model.fix(np.arange(4), ("ux", "uy", "uz"))
    return model


def angle_from_e3(directors: np.ndarray) -> np.ndarray:
    """Angle (rad) between each director (n, 3) and the reference director e3."""
    return np.arctan2(np.linalg.norm(np.cross(E3, directors), axis=1), directors @ E3)


# ------------------------------------------------------------------------------ the element
def test_the_reference_directors_are_plus_e3_and_the_mass_is_per_node():
    # Counter-clockwise triangles in z = 0 have normal +e3; nodes 0 and 2 belong to both
    # triangles and still get one mass and one inertia (the element is node-level).
    compiled = spring_model(2.0, mass=3.0, inertia=5.0).compile()
    assert np.allclose(compiled.reference_directors, E3)
    assert np.allclose(compiled.mass0, 3.0)
    assert np.allclose(compiled.inertia0, 5.0)
    state = compiled.initial_state()
    force, moment = compiled.internal_force(state)
    assert np.all(force == 0) and np.all(moment == 0)  # theta = 0: no moment
    assert compiled.stable_dt(state) == pytest.approx(2.0 / np.sqrt(2.0 / 5.0))


def test_the_moment_is_the_gradient_of_the_strain_energy():
    # Reference: m = dW/dpsi, the derivative of W along small rotations psi of the director
    # (V -> rotate_about(V, psi)); central differences, step h = 1e-6 (error O(h^2)).
    compiled = spring_model(7.0).compile()
    state = compiled.initial_state()
    rng = np.random.default_rng(1)
    tilts = rng.normal(size=(4, 3))
    tilts -= (tilts @ E3)[:, None] * E3
    tilts *= (np.array([0.05, 0.4, 1.2, 2.5]) / np.linalg.norm(tilts, axis=1))[:, None]
    state.directors = rotate_about(state.directors, tilts)  # theta = 0.05 .. 2.5 rad
    _, moment = compiled.internal_force(state)

    h = 1e-6
    gradient = np.zeros((4, 3))
    for node in range(4):
        for j in range(3):
            energies = []
            for sign in (1.0, -1.0):
                psi = np.zeros((4, 3))
                psi[node, j] = sign * h
                trial = state.copy()
                trial.directors = rotate_about(state.directors, psi)
                energies.append(compiled.strain_energy(trial))
            gradient[node, j] = (energies[0] - energies[1]) / (2 * h)
    scale = np.linalg.norm(moment, axis=1)
    assert np.all(np.linalg.norm(gradient - moment, axis=1) <= 1e-6 * scale)
    # The moment has no drilling part: it is perpendicular to the director.
    assert np.allclose(np.sum(moment * state.directors, axis=1), 0.0, atol=1e-12 * scale.max())


# ------------------------------------------------------------------------------ explicit dynamics
def test_free_rotation_under_a_dead_moment_is_uniformly_accelerated():
    # Reference: k = 0, I theta'' = M (the moment stays perpendicular to the director, which
    # turns about the moment axis): theta(t) = M t^2 / (2 I). Central difference is exact for a
    # constant acceleration (the half first step gives omega(i+1/2) = (i+1/2) dt M/I).
    moment, inertia, duration, steps = 2.0, 4.0, 1.5, 300  # theta(T) = 0.5625 rad
    model = spring_model(0.0, inertia=inertia)
    model.moment(np.arange(4), (moment, 0.0, 0.0))
    result = CentralDifference(duration=duration, dt=duration / steps).solve(model)
    directors = result.directors
    theta = angle_from_e3(directors)
    assert theta == pytest.approx(np.full(4, moment * duration**2 / (2 * inertia)), rel=1e-3)
    # A right-handed turn about +e1 takes e3 towards -e2; the director stays a unit vector.
    assert np.allclose(directors[:, 0], 0.0, atol=1e-12) and np.all(directors[:, 1] < 0)
    for frame in result.frames:
        assert np.abs(np.linalg.norm(frame.directors, axis=1) - 1.0).max() < 1e-12


def test_a_step_moment_makes_the_director_oscillate_about_M_over_k():
    # Reference: I theta'' + k theta = M from rest: theta(t) = (M/k)(1 - cos(omega t)),
    # omega = sqrt(k/I); maximum 2M/k, period 2 pi/omega. M/k = 0.01 rad. With omega dt = 0.1
    # the central-difference period error (omega dt)^2/24 is 0.04 %; tolerance 2 %.
    k, inertia, moment = 50.0, 2.0, 0.5
    omega = np.sqrt(k / inertia)
    period = 2 * np.pi / omega
    dt = 0.1 / omega
    model = spring_model(k, inertia=inertia)
    model.moment(np.arange(4), (0.0, moment, 0.0))
    result = CentralDifference(duration=3 * period, dt=dt, output_interval=dt).solve(model)
    times = result.times
    theta = np.array([angle_from_e3(f.directors)[0] for f in result.frames])
    assert theta.max() == pytest.approx(2 * moment / k, rel=0.02)
    # Upward crossings of the mean M/k, linearly interpolated, are one period apart.
    offset = theta - moment / k
    up = np.flatnonzero((offset[:-1] < 0) & (offset[1:] >= 0))
    crossings = times[up] - offset[up] * (times[up + 1] - times[up]) / (offset[up + 1] - offset[up])
    assert len(crossings) >= 2
    assert np.diff(crossings) == pytest.approx(np.full(len(crossings) - 1, period), rel=0.02)
    # Every node turns alike (same spring, same load).
    assert np.allclose(angle_from_e3(result.directors), angle_from_e3(result.directors)[0])


def test_a_drilling_moment_does_not_turn_the_director():
    # Reference: there is no drilling DOF (docs/theory.md §1.3): a moment along the director e3 is
    # dropped, so the director stays e3 and no reaction moment arises.
    model = spring_model(10.0)
    model.moment(np.arange(4), (0.0, 0.0, 3.0))
    result = CentralDifference(duration=1.0, dt=0.01).solve(model)
    assert np.allclose(result.directors, E3, atol=1e-15)
    relaxed = DynamicRelaxation().solve(model)
    assert np.allclose(relaxed.directors, E3, atol=1e-15)
    assert np.allclose(relaxed.reaction_moments, 0.0, atol=1e-15)


# ------------------------------------------------------------------------------ dynamic relaxation
@pytest.mark.parametrize("damping", ["kinetic", "viscous"])
def test_dynamic_relaxation_finds_theta_equal_M_over_k(damping):
    # Reference: equilibrium k theta = M for a dead moment M about e1 (perpendicular to V0):
    # the spring moment k theta stays along e1 as the director turns about e1, so theta = M/k
    # exactly at any angle. M/k = 0.5 rad; 1e-4 relative.
    k, moment = 4.0, 2.0
    model = spring_model(k)
    model.moment(np.arange(4), (moment, 0.0, 0.0))
    result = DynamicRelaxation(tol=1e-7, max_iterations=2000, damping=damping).solve(model)
    assert result.converged
    assert angle_from_e3(result.directors) == pytest.approx(np.full(4, moment / k), rel=1e-4)


def test_a_fixed_alpha_holds_the_director_and_reacts_the_moment():
    # Reference: alpha is the rotation about V2 = e2 (V0 = e3: V1 = e1, V2 = e2); with alpha
    # fixed a moment along e2 cannot turn the director, and the support moment balances the
    # applied one: reaction_moments = -M (1e-6 of |M|).
    applied = np.array([0.0, 1.5, 0.0])
    model = spring_model(4.0)
    held = np.array([0, 2])
    model.fix(held, "alpha")
    model.moment(held, applied)
    result = DynamicRelaxation(tol=1e-7).solve(model)
    assert result.converged
    assert np.allclose(result.directors, E3, atol=1e-12)
    assert np.abs(result.reaction_moments[held] + applied).max() <= 1e-6 * np.linalg.norm(applied)


def test_a_fixed_alpha_leaves_beta_free():
    # Reference: a moment along e1 = V1 acts on beta (rotation about V1), which is free: the
    # director turns about e1 to theta = M/k (M/k = 0.5 rad) and stays in the y-z plane
    # (the frame follows: V1 stays e1 as V turns about it). 1e-4 relative.
    k, moment = 4.0, 2.0
    model = spring_model(k)
    held = np.arange(4)
    model.fix(held, "alpha")
    model.moment(held, (moment, 0.0, 0.0))
    result = DynamicRelaxation(tol=1e-7, max_iterations=2000).solve(model)
    assert result.converged
    directors = result.directors
    assert angle_from_e3(directors) == pytest.approx(np.full(4, moment / k), rel=1e-4)
    assert np.allclose(directors[:, 0], 0.0, atol=1e-12)
    assert np.abs(result.reaction_moments).max() <= 1e-5 * moment


@pytest.mark.parametrize("damping", [0.0, 50.0])
def test_central_difference_reports_the_support_moment_of_a_fixed_alpha(damping):
    # Reference: alpha fixed, moment M along e2 = V2: the director never moves, so at every
    # step the support moment balances the applied one, reaction_moments = -M, with or without
    # mass-proportional damping (omega along V2 stays 0, so the damping force there is 0).
    applied = np.array([0.0, 1.5, 0.0])
    model = spring_model(4.0)
    held = np.array([0, 2])
    model.fix(held, "alpha")
    model.moment(held, applied)
    result = CentralDifference(duration=1.0, dt=0.01, damping=damping).solve(model)
    assert np.allclose(result.directors, E3, atol=1e-12)
    assert np.abs(result.reaction_moments[held] + applied).max() <= 1e-9 * np.linalg.norm(applied)
