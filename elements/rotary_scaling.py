"""The Mindlin shell's scaled rotary inertia held to the membrane's step (docs/theory.md §6.2 B2).

B2's closed form j = kappa (1 - nu) L_e^2 / 16 caps the nodal estimate of the rotations'
frequency, kappa G / (2 rho j), at the membrane's 2 c / L_e. The element's own eigenproblem
is what sets the step (B4), and there the two estimates can both miss: on the equivalent
section of a fabric (ElasticShell.equivalent: nu = 0, G12 next to nothing) the MITC3
triangle's largest rotational frequency squared is three times the nodal estimate and its
membrane's largest 3 c^2 / L_e^2, so the rotations set a step about half the membrane's.
``membrane_held_factors`` finds, per cell, the least multiple of the closed-form j whose
element step is within ``STEP_SHARE`` of the step with the rotations held (j without bound).
"""

from __future__ import annotations

import numpy as np

__all__ = ["STEP_SHARE", "membrane_held_factors", "rotary_mode", "scaled_rotary_inertia"]

#: The element's step with the scaled j at least this share of its step with j without bound
#: (the translations alone): a lighter j lets the rotations set the step.
STEP_SHARE = 0.95
# Bisection of log(factor) between 1 and _LARGEST: 2^-_HALVINGS of its range, about 0.4 %.
_LARGEST = 1.0e4
_HALVINGS = 12
_TRANSLATIONS = np.array([0, 1, 2, 6, 7, 8, 12, 13, 14])


def _largest(k: np.ndarray, mass: np.ndarray) -> np.ndarray:
    """Largest eigenvalue (c,) of k phi = omega^2 diag(mass) phi, k (c, n, n) symmetric."""
    scale = 1.0 / np.sqrt(mass)
    return np.linalg.eigvalsh(k * scale[:, :, None] * scale[:, None, :])[:, -1]


def membrane_held_factors(
    tangent: np.ndarray, share: np.ndarray, j: np.ndarray, step_share: float = STEP_SHARE
) -> np.ndarray:
    """Factors s >= 1 (c,) on the rotary inertia j so that each element's critical step with
    s j is at least ``step_share`` of its step with its rotations held (the translations'
    block alone, K_tt phi = omega^2 M_t phi: the limit j -> infinity).

    Parameters
    ----------
    tangent : ndarray, shape (c, 18, 18)
        The elements' symmetric stiffness in (u, psi) of their corners, node by node (three
        translations, then three rotations), N/mm, N, N mm.
    share : ndarray, shape (c,)
        Each corner's lumped mass, t.
    j : ndarray, shape (c,)
        The rotary inertia per unit mass in use, mm^2.
    step_share : float
        In (0, 1].

    Returns
    -------
    ndarray, shape (c,)
        1 where j already gives that step (the bits of j are then kept), else the least
        factor up to 1e4 (within 0.4 %, rounded up) that does.
    """
    if not 0.0 < step_share <= 1.0:
        raise ValueError(f"step_share must lie in (0, 1], got {step_share!r}")
    k = 0.5 * (tangent + np.swapaxes(tangent, 1, 2))
    held = _largest(k[:, _TRANSLATIONS][:, :, _TRANSLATIONS], np.repeat(share[:, None], 9, 1))
    bound = held / step_share**2  # omega^2 of the step asked for

    def omega2(factor: np.ndarray) -> np.ndarray:
        node = np.stack([share] * 3 + [share * j * factor] * 3, axis=1)
        return _largest(k, np.tile(node, 3))

    low = np.zeros(len(j))  # log factors: omega^2 is monotone decreasing in j
    high = np.full(len(j), np.log(_LARGEST))
    needs = omega2(np.ones(len(j))) > bound
    for _ in range(_HALVINGS):
        middle = 0.5 * (low + high)
        fast = omega2(np.exp(middle)) > bound
        low = np.where(fast, middle, low)
        high = np.where(fast, high, middle)
    return np.where(needs, np.exp(high), 1.0)


def hold_to_membrane(block, j: np.ndarray, step_share: float = STEP_SHARE) -> np.ndarray:
    """The rotary inertia j (m,), mm^2, of a bound MindlinShellBlock (or its fabric form)
    times ``membrane_held_factors`` of its cells in the reference configuration (their
    tangent and lumped masses; cells of the same reference shape share one problem)."""
    from elements.mindlin import _TANGENT_SLICE
    from elements.mindlin_tables import _congruent_cells

    x0, v0 = block._reference_cells()
    first, shape_of = _congruent_cells(x0, v0)
    share = block.material.areal_density * block.reference_area[first] / 3.0
    factors = np.empty(len(first))
    for start in range(0, len(first), _TANGENT_SLICE):
        rows = slice(start, start + _TANGENT_SLICE)
        cells = first[rows]
        k = block._cell_tangent(x0[cells], v0[cells], cells).reshape(-1, 18, 18)
        factors[rows] = membrane_held_factors(k, share[rows], j[cells], step_share)
    return j * factors[shape_of]


def rotary_mode(value) -> str | None:
    """The MindlinShell's ``rotary_scaling`` as the block reads it: None (the physical h^2 /
    12), "closed" (B2's closed form) or "element" (the closed form held to the membrane's
    step, ``hold_to_membrane``). True, the default, is "closed": the results as they were."""
    if value is False:
        return None
    if value is True:
        return "closed"
    if value in ("closed", "element"):
        return str(value)
    raise ValueError(f"rotary_scaling must be True, False, 'closed' or 'element', got {value!r}")


def scaled_rotary_inertia(block, mode: str | None, kappa_one_minus_nu: float) -> np.ndarray:
    """j (m,), mm^2, of a bound block (I = m j): h^2 / 12, at least kappa (1 - nu) L_e^2 / 16
    with ``mode`` "closed" (L_e the reference altitude), that held to the membrane's step with
    "element" (docs/theory.md §6.2 B2)."""
    j = np.full(len(block.cell_ids), block.h**2 / 12.0)
    if mode is None:
        return j
    j = np.maximum(j, kappa_one_minus_nu * block._altitude() ** 2 / 16.0)
    return hold_to_membrane(block, j) if mode == "element" else j
