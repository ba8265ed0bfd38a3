"""The compiled fabric section response (elements/fabric_section_kernels.py) against its numpy
reference (elements.fabric_section.numpy_response) to 1e-12, and the laws' compiled slope
against materials.Law.slope: polynomial and tabulated laws, tension-only ones, strains past a
table's ends and on its knots, warp and weft laws that differ."""

from __future__ import annotations

import numpy as np
import pytest

from elements import fabric_section_kernels
from elements.fabric_section import FabricSection, numpy_response, response
from elements.fibrous.packed_laws import pack_laws
from materials import BendingLaw, Fabric, ShearLaw, TensionLaw

pytestmark = pytest.mark.skipif(not fabric_section_kernels.COMPILED, reason="numba missing")

FABRICS = {
    "linear": Fabric(thickness=1.0, areal_density=1e-9, tension=1e4, shear=1.0, bending=1.0),
    # Bai Table 1's G986 bilinear bending, a polynomial shear, tension-only tabulated tension
    # with a different weft
    "non-linear": Fabric(
        thickness=0.3,
        areal_density=1e-9,
        tension=TensionLaw.table([0.0, 0.01, 0.05], [0.0, 5.0, 300.0], tension_only=True),
        tension_weft=TensionLaw.linear(800.0, tension_only=True),
        shear=ShearLaw.polynomial(0.3, 2.0, 5.0),
        bending=BendingLaw.bilinear(7.5, 0.5, knee=1e-3),
        bending_weft=BendingLaw.table(
            [-0.03, -0.002, 0.0, 0.002, 0.03], [-0.2, -0.004, 0.0, 0.004, 0.2]
        ),
    ),
}


def _section(fabric: Fabric, m: int, rng: np.random.Generator) -> FabricSection:
    rows = rng.uniform(-1.0, 1.0, (3, m, 3))
    q = rng.uniform(-1.0, 1.0, (m, 4, 4))
    return FabricSection(
        fabric=fabric,
        area=rng.uniform(0.5, 2.0, m),
        warp_rows=rows[0],
        weft_rows=rows[1],
        shear_rows=0.3 * rows[2],
        half_thickness=0.5 * fabric.thickness,
        twisting=0.7,
        transverse=q @ np.swapaxes(q, 1, 2),
        reference_bending=rng.uniform(-0.01, 0.01, (m, 2)),  # a curved reference
    )


def _measures(m: int, rng: np.random.Generator) -> np.ndarray:
    """Membrane strains of a few percent (both signs: compressed fibres meet the tension-only
    laws' zero branch), curvatures across the tables' knots and past their ends."""
    y = np.empty((m, 10))
    y[:, 0:3] = rng.uniform(-0.03, 0.06, (m, 3))
    y[:, 3:6] = rng.uniform(-0.02, 0.02, (m, 3))
    y[:, 6:10] = rng.uniform(-0.1, 0.1, (m, 4))
    return y


@pytest.mark.parametrize("name", FABRICS)
@pytest.mark.parametrize("hessian", [True, False])
def test_the_compiled_response_is_the_numpy_one_to_1e_12(name, hessian):
    rng = np.random.default_rng(7)
    section = _section(FABRICS[name], 400, rng)
    y = _measures(400, rng)
    compiled, reference = response(section, y, hessian), numpy_response(section, y, hessian)
    for key in ("energy", "gradient", "hessian", "tension", "shear_moment", "moments",
                "strains", "shear_angle", "curvatures"):  # fmt: skip
        got, expected = getattr(compiled, key), getattr(reference, key)
        if expected is None:
            assert got is None, key
            continue
        assert got.shape == expected.shape, key
        scale = max(1.0, float(np.abs(expected).max()))
        assert np.abs(got - expected).max() <= 1e-12 * scale, key
    # the samples reach both branches of every law
    strains = reference.strains
    assert (strains < 0).any() and (strains > 0.01).any()
    assert (np.abs(reference.curvatures[:, 0]) > 1e-3).any()


def test_a_section_whose_fibres_lock_flat_is_refused_as_by_numpy():
    rng = np.random.default_rng(1)
    section = _section(FABRICS["linear"], 5, rng)
    # cell 2 in its fibre frame (E_aa = E11, E_bb = E22, E_ab = E12), sheared to
    # sin(gamma) = 2 E_ab / sqrt(p_a p_b) = 1.1 with unstretched fibres
    section.warp_rows[2], section.weft_rows[2] = (1.0, 0.0, 0.0), (0.0, 1.0, 0.0)
    section.shear_rows[2] = (0.0, 0.0, 0.5)
    y = _measures(5, rng)
    y[2, 0:3] = (0.0, 0.0, 1.1)
    for evaluate in (response, numpy_response):
        with pytest.raises(ValueError, match="locked flat"):
            evaluate(section, y)


def test_the_compiled_slope_is_the_laws_slope_on_and_between_the_knots():
    laws = [
        FABRICS["non-linear"].tension,
        FABRICS["non-linear"].tension_weft,
        FABRICS["non-linear"].shear,
        FABRICS["non-linear"].bending,
        FABRICS["non-linear"].bending_weft,
    ]
    integers, reals = pack_laws(laws)
    knots = np.concatenate([law.knots[0] for law in laws if law.knots is not None])
    x = np.concatenate([np.linspace(-0.1, 0.1, 401), knots])
    for i, law in enumerate(laws):
        compiled = [fabric_section_kernels.law_slope(integers, reals, i, v) for v in x]
        assert np.allclose(compiled, law.slope(x), rtol=1e-13, atol=0.0), law


def test_the_sections_gradient_and_hessian_are_the_central_differences_of_its_energy():
    """The linear fabric on a curved reference (k0 != 0: the fibre curvature's change
    (K + k0) / ((h/2) p) - k0 / (h/2), docs/theory.md §5.7), at random measures: dW/dy and
    d2W/dy2 against central differences of W and of dW/dy, step 1e-6 (truncation ~ 1e-12 of
    W's third derivative, round-off ~ 1e-16 W / 1e-6): 1e-6 of the largest entry."""
    rng = np.random.default_rng(11)
    section = _section(FABRICS["linear"], 20, rng)
    y = _measures(20, rng)
    exact = numpy_response(section, y)
    step = 1e-6
    for j in range(10):
        up, down = y.copy(), y.copy()
        up[:, j] += step
        down[:, j] -= step
        plus, minus = numpy_response(section, up), numpy_response(section, down)
        gradient = (plus.energy - minus.energy) / (2 * step)
        hessian = (plus.gradient - minus.gradient) / (2 * step)
        scale = np.abs(exact.gradient).max()
        assert np.abs(gradient - exact.gradient[:, j]).max() <= 1e-6 * scale, j
        scale = np.abs(exact.hessian).max()
        assert np.abs(hessian - exact.hessian[:, :, j]).max() <= 1e-6 * scale, j
