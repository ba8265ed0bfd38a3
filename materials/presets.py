"""Fabrics of Bai et al., Composites Part A 139 (2020) 106135, with every assumption stated.

The paper gives tension and bending per unit width (Tables 1 and 2) and the G1151 specimen size
(§6.2: 200 x 150 x 15 mm, 11 plies). It gives no areal density, no in-plane shear law, no ply
thickness for G986 and no material data at all for the paper stack of §6.1. The values assumed
here are listed in each docstring; the validation report varies those that matter.

Units: mm, N, t (1 kg/m^2 = 1e-9 t/mm^2).
"""

from __future__ import annotations

from typing import Any

from materials.fabric import Fabric
from materials.laws import BendingLaw, Law, ShearLaw

__all__ = [
    "G1151_SPECIMEN",
    "g986_ply",
    "g986_stack",
    "g1151_laminate",
    "paper_stack",
]

KG_PER_M2 = 1e-9  # t/mm^2

# Hexcel G0986: 285 g/m^2 carbon 2x2 twill (manufacturer's nominal areal weight; assumed, the
# paper gives none). Ply thickness 0.3 mm: assumed, a lightly compacted ply of that weight.
G986_AREAL_WEIGHT = 285e-3 * KG_PER_M2
G986_PLY_THICKNESS = 0.3

# Hexcel G1151: 630 g/m^2 carbon interlock (nominal areal weight; assumed). 11 plies make the
# 15 mm laminate of Bai §6.2, i.e. 1.36 mm per ply.
G1151_AREAL_WEIGHT = 630e-3 * KG_PER_M2
G1151_SPECIMEN = {"length": 200.0, "width": 150.0, "thickness": 15.0, "plies": 11}

# In-plane shear of a dry carbon ply: no coefficients are published for these fabrics
# (docs/theory.md §3). Picture-frame forces of order 10-100 N at 40 deg on a 150 mm frame give, by
# M_s = F L sin(pi/4 - gamma/2) / L^2, about 0.2 N/mm per rad; assumed per ply, linear.
SHEAR_PER_PLY = 0.2


def _table1_bending() -> Law:
    # Bai Table 1 in the continuous reading of docs/theory.md §4.6 (knee moment 0.0075 N).
    return BendingLaw.bilinear(7.5, 0.5, knee=1e-3)


def g986_stack(plies: int = 20) -> Fabric:
    """Stack of G986 plies of Bai §5.1, simulated as one shell: Bai Table 1.

    From the paper: tension 1200 N/mm per unit width; bending B = 7.5 N mm up to |chi| =
    1e-3 1/mm, 0.5 N mm beyond (continuous reading). Assumed: Table 1 is the 20-ply stack's,
    modelled with one element through the thickness (its caption reads "single layer in
    multilayer reinforcement", the text says only that G986's properties "are given in Table
    1", and §4.1.3 that the bending used is the overall stack's), and this preset applies it
    whatever ``plies`` is. Assumed: 0.3 mm and 285 g/m^2 per ply (6 mm, 5.7 kg/m^2 for 20 plies);
    linear shear 0.2 N/mm per ply.

    Parameters
    ----------
    plies : int, optional
        Number of plies (20 in Bai §5.1); scales thickness, areal density and shear only.

    Returns
    -------
    Fabric
        The stack.

    Raises
    ------
    ValueError
        ``plies`` is not a positive integer.
    """
    plies = _plies(plies)
    return Fabric(
        thickness=plies * G986_PLY_THICKNESS,
        areal_density=plies * G986_AREAL_WEIGHT,
        tension=1200.0,
        shear=ShearLaw.linear(plies * SHEAR_PER_PLY),
        bending=_table1_bending(),
        ply_count=plies,
    )


def g986_ply() -> Fabric:
    """One G986 ply with the laws of Bai Table 1 ("single layer in multilayer reinforcement").

    The paper gives a single table, read here as the whole stack's (see ``g986_stack``); this
    preset keeps those laws with one ply's assumed thickness (0.3 mm), areal weight
    (285 g/m^2) and shear (0.2 N/mm). Use it for single-ply studies knowing that the bending
    law was measured on the stack.

    Returns
    -------
    Fabric
        One ply: 0.3 mm, 2.85e-10 t/mm^2.
    """
    return g986_stack(plies=1)


def g1151_laminate() -> Fabric:
    """The 11-ply G1151 laminate of Bai §6.2 (200 x 150 x 15 mm): Bai Table 2.

    From the paper: tension 2300 N/mm per unit width (one value, used for warp and weft);
    bending B = 72 N mm (warp) and 68 N mm (weft), linear, measured on the stack (friction
    included). Assumed: 630 g/m^2 per ply (6.93 kg/m^2 in all); linear shear 0.2 N/mm per ply
    (2.2 N/mm).

    Returns
    -------
    Fabric
        The laminate: 15 mm, 6.93e-9 t/mm^2, warp and weft bending laws.
    """
    plies = G1151_SPECIMEN["plies"]
    return Fabric(
        thickness=G1151_SPECIMEN["thickness"],
        areal_density=plies * G1151_AREAL_WEIGHT,
        tension=2300.0,
        shear=ShearLaw.linear(plies * SHEAR_PER_PLY),
        bending=BendingLaw.linear(72.0),
        bending_weft=BendingLaw.linear(68.0),
        ply_count=int(plies),
    )


def paper_stack(sheets: int = 130) -> Fabric:
    """The stack of 130 paper sheets of Bai §6.1.

    The paper gives no material data; only that the sheets slide on each other and that the
    in-plane shear stiffness is large.

    Assumed: office paper, 80 g/m^2 and 0.1 mm per sheet (13 mm, 10.4 kg/m^2 in all);
    bending 50 N mm per unit width (130 sheets of E t^3/12 = 4000 x 0.1^3/12 = 0.33 N mm each
    sliding freely give 43 N mm, friction adds a little); tension 2300 N/mm, used as an
    inextensibility penalty as in Table 2 (the real sheets are stiffer still, about
    5e4 N/mm, which only makes them more inextensible); in-plane shear K = 1000 N/mm, the
    ratio K/C ~ 0.4 of an isotropic sheet (G h / E h), "large" as the paper says.

    Parameters
    ----------
    sheets : int, optional
        Number of sheets (130 in Bai §6.1); scales thickness, areal density and bending.

    Returns
    -------
    Fabric
        The stack.

    Raises
    ------
    ValueError
        ``sheets`` is not a positive integer.
    """
    sheets = _plies(sheets)
    return Fabric(
        thickness=0.1 * sheets,
        areal_density=sheets * 80e-3 * KG_PER_M2,
        tension=2300.0,
        shear=ShearLaw.linear(1000.0),
        bending=BendingLaw.linear(50.0 * sheets / 130),
        ply_count=sheets,
    )


def _plies(count: Any) -> int:
    if isinstance(count, bool) or not isinstance(count, int) or count < 1:
        raise ValueError(f"the number of plies or sheets must be a positive integer, got {count!r}")
    return count
