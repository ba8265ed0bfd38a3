"""An element type written outside the project, in this file, plugs into every solver.

``Membrane`` is what a user would write for a film: the linear (constant-strain) triangle in
plane stress, total Lagrangian, with the St Venant-Kirchhoff law S = D E (E the Green-Lagrange
strain, S the second Piola-Kirchhoff stress), translations only. It imports only the element
protocol (elements.base), is vectorised over its cells, and has its exact tangent (or, with
``exact_tangent=False``, none: the solvers then difference its forces).

Reference (closed form): a W x L rectangle held in x along its left edge (and at one node in
y, everywhere in z), its right edge pulled to the stretch lambda. The deformation is
homogeneous, F = diag(lambda, mu), which the constant-strain triangle represents exactly on
any mesh; free lateral contraction gives S22 = 0, so S11 = E E11 with E11 = (lambda^2 - 1) / 2
and the force on the right edge is the first Piola stress P11 = lambda S11 times the reference
section W t.
"""

import numpy as np
import pytest
import scipy.linalg

from elements.base import CellTangent, ElementBlock, ElementType, Scatter
from femcore import Mesh, Model
from femcore.loads import smooth_step
from solvers import CentralDifference, DynamicRelaxation, Static

E, NU, T, RHO = 1000.0, 0.3, 0.1, 1.0e-9  # N/mm^2, -, mm, t/mm^3
W, L = 20.0, 40.0  # mm
STRETCH = 1.2


class Membrane(ElementType):
    """Constant-strain triangle, plane stress, St Venant-Kirchhoff (E N/mm^2, nu, thickness t
    mm, density rho t/mm^3); ``exact_tangent=False`` leaves the tangent to finite differences."""

    dofs = ("ux", "uy", "uz")
    cell_type = "triangle"

    def __init__(self, E, nu, t, rho, exact_tangent=True):
        self.E, self.nu, self.t, self.rho, self.exact_tangent = E, nu, t, rho, exact_tangent

    def bind(self, mesh, cell_ids, directors):
        return MembraneBlock(self, mesh, np.asarray(cell_ids, dtype=np.int64))


class MembraneBlock(ElementBlock):
    dofs = Membrane.dofs
    cell_type = Membrane.cell_type
    reach = 1

    def __init__(self, film, mesh, cell_ids):
        self.film, self.cell_ids = film, cell_ids
        self.connectivity = mesh.triangles[cell_ids]
        self.scatter = Scatter(self.connectivity, mesh.n_nodes)
        x = mesh.points[self.connectivity]  # (m, 3, 3)
        e1, e2 = x[:, 1] - x[:, 0], x[:, 2] - x[:, 0]
        normal = np.cross(e1, e2)
        self.area = 0.5 * np.linalg.norm(normal, axis=1)
        a1 = e1 / np.linalg.norm(e1, axis=1)[:, None]  # an orthonormal basis of each plane
        a2 = np.cross(normal / (2 * self.area)[:, None], a1)
        edges = np.stack([np.stack([(e * a).sum(1) for a in (a1, a2)], 1) for e in (e1, e2)], 2)
        inverse = np.linalg.inv(edges)  # dX/dxi (2, 2) per cell, inverted
        # Gradients of the shape functions in the plane's basis, (m, 3 nodes, 2).
        self.grad = np.einsum("ak,mkj->maj", [[-1.0, -1.0], [1.0, 0.0], [0.0, 1.0]], inverse)
        longest = np.max([np.linalg.norm(x[:, i] - x[:, i - 1], axis=1) for i in range(3)], 0)
        self.altitude = 2.0 * self.area / longest  # the smallest altitude of each cell
        E, nu = film.E, film.nu
        self.D = E / (1 - nu**2) * np.array([[1, nu, 0], [nu, 1, 0], [0, 0, (1 - nu) / 2]])

    def _strain(self, state):
        """F (m, 3, 2), the strain-displacement matrices B (m, 3 nodes, 3 Voigt, 3) and the
        Voigt stress S (m, 3) from E = (E11, E22, 2 E12)."""
        F = np.einsum("mai,maj->mij", self.scatter.gather(state.positions), self.grad)
        C = np.einsum("mki,mkj->mij", F, F)
        strain = np.stack([C[:, 0, 0] - 1, C[:, 1, 1] - 1, 2 * C[:, 0, 1]], 1) * 0.5
        g = self.grad
        B = np.stack(
            [
                g[:, :, 0, None] * F[:, None, :, 0],
                g[:, :, 1, None] * F[:, None, :, 1],
                g[:, :, 0, None] * F[:, None, :, 1] + g[:, :, 1, None] * F[:, None, :, 0],
            ],
            2,
        )
        return strain, B, strain @ self.D

    def internal_force(self, state, history=None):
        _, B, S = self._strain(state)
        volume = (self.area * self.film.t)[:, None, None]
        return self.scatter.vectors(volume * np.einsum("mavi,mv->mai", B, S)), None

    def strain_energy(self, state, history=None):
        strain, _, S = self._strain(state)
        return float(0.5 * np.sum(self.area * self.film.t * np.sum(strain * S, 1)))

    def tangent(self, state, history=None):
        """Material B_a^T D B_b plus geometric (g_a . S g_b) I, times the volume A t."""
        if not self.film.exact_tangent:
            return None
        _, B, S = self._strain(state)
        stress = np.stack([np.stack([S[:, 0], S[:, 2]], 1), np.stack([S[:, 2], S[:, 1]], 1)], 1)
        geometric = np.einsum("mai,mij,mbj->mab", self.grad, stress, self.grad)
        blocks = np.einsum("mavi,vw,mbwj->maibj", B, self.D, B)
        blocks += geometric[:, :, None, :, None] * np.eye(3)[None, None, :, None, :]
        volume = (self.area * self.film.t)[:, None, None, None, None]
        return [CellTangent(self.connectivity, volume * blocks)]

    def lumped_mass(self, state, density_scale=None):
        third = self.film.rho * self.film.t * self.area / 3.0
        if density_scale is not None:
            third = third * density_scale
        return self.scatter.scalars(np.repeat(third[:, None], 3, axis=1)), None

    def cell_stable_dt(self, state):
        # omega^2 <= 3 / (rho A) * A E / (1 - nu) * lambda_max(sum_a g_a g_a^T) and
        # lambda_max <= 2 / h_min^2 on any triangle: dt = h_min / c sqrt(2 / (3 (1 + nu))),
        # c the plane-stress wave speed (the bound is reached by slivers at nu = 0; it is
        # 0.78 of a right triangle's exact step at nu = 0.3).
        nu = self.film.nu
        wave_speed = np.sqrt(self.film.E / (self.film.rho * (1 - nu**2)))
        return self.altitude / wave_speed * np.sqrt(2.0 / (3.0 * (1.0 + nu)))


def stretched_strip(exact_tangent=True, amplitude="smooth") -> Model:
    """The W x L strip pulled to STRETCH (module docstring), 4 x 2 grid cells."""
    model = Model(Mesh.rectangle(L, W, nx=4, ny=2))
    model.add(Membrane(E, NU, T, RHO, exact_tangent))
    model.fix("left", "ux")
    model.fix([0], "uy")
    model.fix(lambda x, y, z: np.ones_like(x, dtype=bool), "uz")
    model.displace("right", ux=(STRETCH - 1.0) * L, amplitude=amplitude)
    return model


def end_force() -> float:
    """lambda S11 W t, N: the first Piola stress over the reference section."""
    return STRETCH * E * 0.5 * (STRETCH**2 - 1.0) * W * T


def slowest_frequency(compiled, state) -> float:
    """The lowest omega (rad/s) of the free DOFs at ``state`` (lumped mass, dense)."""
    free = compiled.dofs.free_slots
    stiffness = compiled.stiffness(state, "finite_difference").toarray()[np.ix_(free, free)]
    mass = np.repeat(compiled.mass0[:, None], 5, axis=1).ravel()[free]
    omega2 = scipy.linalg.eigh(0.5 * (stiffness + stiffness.T), np.diag(mass), eigvals_only=True)
    return float(np.sqrt(omega2.min()))


# The hold after the ramp (explicit): the prescribed edge reaches its place at half the run.
HELD = 0.5


def ramp_then_hold(tau):
    return smooth_step(np.asarray(tau) / HELD)


def settling_explicit(compiled, increments: int) -> CentralDifference:
    """A damped explicit run that settles on the static state: damping c = omega_min (the
    slowest mode at the state ``Static(increments)`` reaches: every mode underdamped, its
    amplitude decaying as exp(-c t / 2)), held for 30 / c after the ramp, so that the
    oscillation the ramp left (smaller than the static displacement) falls by exp(-15) =
    3e-7."""
    static = Static(increments=increments, progress=False).solve(compiled)
    loaded = compiled.initial_state()
    loaded.positions = static.positions.copy()
    c = slowest_frequency(compiled, loaded)
    return CentralDifference(30.0 / c / (1.0 - HELD), damping=c, progress=False)


def explicit_run(compiled):
    """``settling_explicit`` on the stretched strip: the reaction within 1e-5."""
    return settling_explicit(compiled, increments=2), 1e-5


SOLVERS = {
    # Newton to a residual of 1e-10 of the forces: the reaction within 1e-8.
    "static": lambda compiled: (Static(increments=4, tol=1e-10, progress=False), 1e-8),
    # Kinetic damping to 1e-9 of the forces: the reaction within 1e-7.
    "relaxation": lambda compiled: (DynamicRelaxation(tol=1e-9, progress=False), 1e-7),
    "explicit": explicit_run,
}


@pytest.mark.parametrize("exact_tangent", [True, False], ids=["own tangent", "no tangent"])
@pytest.mark.parametrize("name", SOLVERS)
def test_a_user_membrane_carries_the_closed_form_end_force_with_every_solver(name, exact_tangent):
    amplitude = ramp_then_hold if name == "explicit" else "smooth"
    model = stretched_strip(exact_tangent, amplitude)
    compiled = model.compile()
    solver, tolerance = SOLVERS[name](compiled)
    result = solver.solve(compiled)
    assert result.converged
    right, left = model.mesh.nodes("right"), model.mesh.nodes("left")
    assert result.reactions[right, 0].sum() == pytest.approx(end_force(), rel=tolerance)
    assert result.reactions[left, 0].sum() == pytest.approx(-end_force(), rel=tolerance)
    # The lateral contraction of free SVK: S22 = 0, so E22 = -nu E11.
    contraction = np.sqrt(1.0 - NU * (STRETCH**2 - 1.0))
    top = model.mesh.nodes("top")
    assert result.positions[top, 1] == pytest.approx(contraction * W, rel=10 * tolerance)


def test_the_user_membrane_tangent_is_the_derivative_of_its_force():
    """At a jittered state (stretched, sheared, lifted out of its plane): the exact tangent
    against coloured central differences of the forces, within 1e-6 of the largest entry
    (truncation O(step^2), rounding O(eps F / step) with the step 1e-6 of an edge)."""
    compiled = stretched_strip().compile()
    state = compiled.initial_state()
    rng = np.random.default_rng(1)
    state.positions = state.positions * [1.1, 0.95, 1.0] + rng.normal(scale=0.5, size=(15, 3))
    own = compiled.stiffness(state, "element").toarray()
    numerical = compiled.stiffness(state, "finite_difference").toarray()
    assert np.abs(own - numerical).max() <= 1e-6 * np.abs(numerical).max()


def test_the_user_membrane_passes_the_element_conformance_kit():
    testing = pytest.importorskip("femcore.testing")

    def mesh(refine):
        return Mesh.rectangle(L, W, nx=2 * refine, ny=refine)

    report = testing.check_element(Membrane(E, NU, T, RHO), mesh, total_mass=RHO * T * W * L)
    assert report.passed, report


def test_an_object_that_is_not_an_element_type_is_refused():
    model = Model(Mesh.rectangle(1.0, 1.0, nx=1, ny=1))
    with pytest.raises(ValueError, match="not an element type"):
        model.add(object())


def test_a_user_element_over_no_cells_is_refused():
    class Floor(Membrane):
        cell_type = None  # what acts on nodes without cells is an interaction

    model = Model(Mesh.rectangle(1.0, 1.0, nx=1, ny=1))
    with pytest.raises(ValueError, match="is an interaction|model.interact"):
        model.add(Floor(E, NU, T, RHO))


def test_a_block_whose_methods_do_not_take_the_history_is_named():
    class OldBlock(MembraneBlock):
        def internal_force(self, state):  # the protocol passes (state, history)
            return super().internal_force(state)

    class OldMembrane(Membrane):
        def bind(self, mesh, cell_ids, directors):
            return OldBlock(self, mesh, np.asarray(cell_ids, dtype=np.int64))

    model = Model(Mesh.rectangle(L, W, nx=4, ny=2))
    model.add(OldMembrane(E, NU, T, RHO))
    with pytest.raises(ValueError, match=r"OldBlock.internal_force must take \(state, history"):
        model.compile()
