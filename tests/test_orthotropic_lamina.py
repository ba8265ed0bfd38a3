"""An orthotropic lamina (ElasticShell.orthotropic) is accepted whenever its plane-stress
stiffness is positive definite: nu12^2 E2 / E1 < 1 (e.g. Jones, Mechanics of Composite
Materials, 2nd ed., §2.4: |nu12| < sqrt(E1 / E2)), not the isotropic bound (-1, 0.5)."""

from __future__ import annotations

import numpy as np
import pytest

from materials import ElasticShell

E1, E2, G = 10000.0, 1000.0, 500.0  # MPa


def test_a_lamina_with_a_major_poisson_ratio_past_one_half_is_accepted():
    """nu12 = 0.6, nu21 = 0.06: Q = [[E1, nu12 E2], [nu12 E2, E2]] / (1 - nu12 nu21) and
    G12, the closed form to round-off, positive definite."""
    nu12 = 0.6
    section = ElasticShell.orthotropic(E1, E2, nu12, G, G, G, thickness=1.0, density=1.5e-9)
    d = 1.0 - nu12**2 * E2 / E1
    expected = np.array([[E1 / d, nu12 * E2 / d, 0.0], [nu12 * E2 / d, E2 / d, 0.0], [0, 0, G]])
    assert np.allclose(section.plane_stress, expected, rtol=1e-15, atol=0.0)
    assert np.linalg.eigvalsh(section.plane_stress).min() > 0.0


@pytest.mark.parametrize("nu12", [3.17, -3.17], ids=["positive", "negative"])
def test_a_lamina_past_positive_definiteness_is_refused(nu12):
    """|nu12| > sqrt(E1 / E2) = 3.162: Q has a negative eigenvalue."""
    with pytest.raises(ValueError, match=r"nu12\^2 E2 / E1 < 1.*3\.162"):
        ElasticShell.orthotropic(E1, E2, nu12, G, G, G, thickness=1.0, density=1.5e-9)


def test_a_mindlin_shell_of_such_a_lamina_has_a_stable_step():
    """B2's rotary inertia factor kappa (1 - nu) (docs/theory.md §6.2) takes nu at most 0.5:
    with nu12 = 3 (valid: nu12^2 E2 / E1 = 0.9) it stays positive, and the explicit step
    is a positive finite number."""
    from elements import MindlinShell
    from femcore import Mesh, Model

    section = ElasticShell.orthotropic(E1, E2, 3.0, G, G, G, thickness=1.0, density=1.5e-9)
    model = Model(Mesh.rectangle(20.0, 10.0, nx=4, ny=2))
    model.add(MindlinShell(section))
    compiled = model.compile()
    step = compiled.stable_dt(compiled.initial_state())
    assert np.isfinite(step) and step > 0.0
