"""Where a tension law's force per unit reference width T / lambda stops rising
(materials/tension_peak.py, docs/theory.md §6.4d): d(T / lambda) / d(lambda) = (T' - T) /
lambda^2, eps = ln(lambda), so the force falls past the first strain where T' - T turns
negative with T > 0. Each reference below is that closed form worked by hand."""

import math

import numpy as np
import pytest

from materials import TensionLaw
from materials.laws import Law
from materials.tension_peak import softening_strains


def test_a_linear_law_peaks_at_a_stretch_of_e_and_never_in_compression():
    # T = C eps: T' - T = C (1 - eps), zero at eps = 1 (lambda = e); for eps < 0 it is
    # above C, so the compressive force only grows as the fibre shortens.
    assert softening_strains(TensionLaw.linear(1200.0)) == (-math.inf, pytest.approx(1.0))


def test_a_law_stiffening_as_exp_never_peaks_inside_its_table():
    # T = C (exp(eps) - 1): T' - T = C > 0 everywhere the table holds (to eps = 2); past
    # the last knot the table goes on linearly with the last piece's slope s, where T' - T
    # = s - T(2) - s (eps - 2) vanishes at eps = 3 - T(2) / s.
    eps = np.linspace(-0.5, 2.0, 26)
    c = 10.0
    law = TensionLaw.table(eps, c * (np.exp(eps) - 1.0))
    s = c * (np.exp(2.0) - np.exp(1.9)) / 0.1
    lower, upper = softening_strains(law)
    assert lower == -math.inf
    assert upper == pytest.approx(3.0 - c * (np.exp(2.0) - 1.0) / s, rel=1e-12)
    assert upper > 2.0


def test_a_table_that_flattens_peaks_where_it_flattens():
    # T rises with slope 100 to T = 5 at eps = 0.05, then stays at 5: T' - T = 100 - T on
    # the first piece (positive), -5 from the knot on: the force peaks at the knot.
    law = TensionLaw.table([-1.0, 0.0, 0.05, 1.0], [-100.0, 0.0, 5.0, 5.0])
    assert softening_strains(law)[1] == pytest.approx(0.05, rel=1e-12)
    # a piece of slope 10 past 0.5 from T = 2: T' - T = 10 - 2 - 10 (eps - 0.5) = 0 at 1.3
    law = TensionLaw.table([0.0, 0.5, 2.0], [0.0, 2.0, 17.0])
    assert softening_strains(law)[1] == pytest.approx(1.3, rel=1e-12)


def test_a_cubic_law_peaks_at_the_root_of_its_own_t_prime_minus_t():
    # T = eps + 2 eps^3: T' - T = 1 - eps + 6 eps^2 - 2 eps^3, whose one real root is
    # found here by bisection on [2, 4] (g(2) = 7, g(4) = -35); in compression T' - T > 1
    # for eps < 0: never. (An odd polynomial law, as the fabric presets build them.)
    cubic = Law("TensionLaw", "T = eps + 2 eps^3", odd_coefficients=(1.0, 2.0))
    lower, upper = softening_strains(cubic)
    g = lambda e: 1.0 - e + 6.0 * e**2 - 2.0 * e**3  # noqa: E731
    a, b = 2.0, 4.0
    for _ in range(80):
        a, b = (a, (a + b) / 2) if g((a + b) / 2) < 0 else ((a + b) / 2, b)
    assert lower == -math.inf
    assert upper == pytest.approx(a, rel=1e-10)


def test_a_tension_only_law_carries_nothing_to_soften_in_compression():
    assert softening_strains(TensionLaw.linear(10.0, tension_only=True))[0] == -math.inf
