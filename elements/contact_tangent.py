"""The return mapping's friction tangent of a tool contact (elements/contact.py, module
docstring "Friction"; docs/theory.md §9.2): d(friction force)/dx per touching node, k_t ds/dx in
stick and -mu k s^ n^T + mu k p / |s| (I - s^ s^T) ds/dx in slip, with ds/dx = I - n n^T -
(n . r) N - n (N r)^T, r = x - a (a the node's anchor, N = dn/dx the tool's normal gradient)."""

from __future__ import annotations

from typing import Any

import numpy as np

from elements.contact_history import FrictionHistory, landing_terms, start_anchors

__all__ = ["friction_tangent"]


def friction_tangent(
    contact: Any,
    history: FrictionHistory,
    x: np.ndarray,
    p: np.ndarray,
    n: np.ndarray,
    touching: np.ndarray,
    curvature: np.ndarray,
    s: np.ndarray,
    stuck: np.ndarray,
    sliding: np.ndarray,
) -> np.ndarray:
    """The friction's (s, 3, 3) tangent blocks, to add to the normal ones.

    Parameters
    ----------
    contact : the ContactBlock (its stiffness (s,) N/mm, friction, stick_ratio).
    history : the block's friction history (anchors, a frozen set's slip directions).
    x : (s, 3) mm, the contact nodes' positions in the tool's frame (the tool's offset taken off).
    p : (s,) mm, penetrations (< 0 for a frozen node pulled off); n : (s, 3) the tool's normals.
    touching, stuck, sliding : (s,) bool; curvature : (s, 3, 3) 1/mm, dn/dx; s : (s, 3) mm, the
        tangential offsets from the anchors.
    """
    k = contact.stiffness[:, None, None]
    eye = np.eye(3)
    nn = n[:, :, None] * n[:, None, :]
    anchors = start_anchors(history, x, p, touching, contact)
    anchor = np.where(np.isfinite(anchors), anchors, 0.0)
    r = x - anchor
    normal_part = np.sum(n * r, axis=1)[:, None, None]
    curved_r = np.einsum("sij,sj->si", curvature, r)
    ds_dx = eye - nn - normal_part * curvature - n[:, :, None] * curved_r[:, None, :]
    ds_dx = ds_dx + landing_terms(contact, history, x, p, touching, n)
    length = np.linalg.norm(s, axis=1)
    unit = s / np.where(length > 0, length, 1.0)[:, None]
    # A frozen node pulled off the tool (p < 0) has the limit mu k max(p, 0) = 0.
    mu = contact.friction * (p > 0.0)[:, None, None]
    pressed = np.maximum(p, 0.0)
    slip_part = -mu * k * unit[:, :, None] * n[:, None, :] + (
        mu * k * (pressed / np.where(length > 0, length, 1.0))[:, None, None]
    ) * np.einsum("sij,sjk->sik", eye - unit[:, :, None] * unit[:, None, :], ds_dx)
    if history.sliding is not None:  # a frozen direction d, projected: v = P d
        fixed = history.direction
        assert fixed is not None  # (a frozen set keeps its directions beside its sliding nodes)
        v = fixed - np.sum(fixed * n, axis=1)[:, None] * n
        size = np.linalg.norm(v, axis=1)
        along = v / np.where(size > 0, size, 1.0)[:, None]
        curved_d = np.einsum("sij,sj->si", curvature, fixed)
        dv_dx = (
            -np.sum(n * fixed, axis=1)[:, None, None] * curvature
            - n[:, :, None] * curved_d[:, None, :]
        )
        turn = (eye - along[:, :, None] * along[:, None, :]) / np.where(size > 0, size, 1.0)[
            :, None, None
        ]
        slip_part = -mu * k * along[:, :, None] * n[:, None, :] + mu * k * pressed[
            :, None, None
        ] * np.einsum("sij,sjk->sik", turn, dv_dx)
    return np.where(
        stuck[:, None, None],
        contact.stick_ratio * k * ds_dx,
        np.where(sliding[:, None, None], slip_part, 0.0),
    )
