"""The natural logarithm and the arcsine as branch-free arithmetic that LLVM can vectorise across
the lanes of a compiled loop (``lane_log``, ``lane_arcsin``), for the fibrous cells' pass
(elements/fibrous/kernels.py), whose fibre levels take two logs and an arcsine each.

numba compiles ``np.log`` and ``np.arcsin`` to calls of the C library, one value a call: in a
loop that LLVM vectorises it still calls the library lane by lane (llvmlite's LLVM has no
vector maths library, benchmarks/vector_maths.py). The functions here are fdlibm's algorithms
(Sun Microsystems' freely distributable libm, ``e_log.c`` and ``e_asin.c``, whose polynomial
coefficients they use) written with selects instead of branches: every lane runs the same
operations, with no call, so that a loop of them runs 4 lanes at a time with AVX2.

* ``lane_log``: x = 2^k m with m in [sqrt(2)/2, sqrt(2)) by the bits of x (``float_bits``,
  ``bits_float``: the float's 64 bits as an integer and back, an LLVM bitcast), then
  log(m) = f - (f^2 / 2 - s (f^2 / 2 + R(s^2))), f = m - 1, s = f / (2 + f), R fdlibm's
  minimax polynomial of degree 14 (error below 2^-58.45), and k ln 2 in two parts. A
  subnormal x is scaled by 2^54 first; x <= 0, inf and nan are selected at the end (log 0 =
  -inf, log of a negative nan, as numpy).
* ``lane_arcsin``: for |x| < 0.5 x + x P(x^2) / Q(x^2), fdlibm's rational approximation; for
  0.5 <= |x| <= 1 the identity asin |x| = pi/2 - 2 asin(sqrt((1 - |x|) / 2)) with the same
  rational approximation of its argument (fdlibm uses this form from 0.975; below it its
  extra care for the last bit is dropped here: a unit in the last place more at most); nan
  beyond |x| > 1, as numpy.

Accuracy, against numpy (tests/test_lane_maths.py, over the whole domain): the log within 1
unit in the last place, the arcsine within 2.
"""

from __future__ import annotations

import struct
from typing import Any

import numpy as np

from femcore.jit import AVAILABLE, inline, lanes

__all__ = ["bits_float", "float_bits", "lane_arcsin", "lane_log"]


def _float_bits_python(x):
    """The 64 bits of the float64 ``x`` as an int64 (without numba)."""
    return struct.unpack("<q", struct.pack("<d", float(x)))[0]


def _bits_float_python(bits):
    """The float64 whose 64 bits are the int64 ``bits`` (without numba)."""
    return struct.unpack("<d", struct.pack("<q", int(bits)))[0]


float_bits: Any = _float_bits_python
bits_float: Any = _bits_float_python
if AVAILABLE:
    from llvmlite import ir  # type: ignore[import-untyped]
    from numba.core import types
    from numba.extending import intrinsic

    @intrinsic
    def _float_bits(typingctx, x):
        """The 64 bits of the float64 ``x`` as an int64 (a bitcast: no instruction)."""
        if x != types.float64:
            return None

        def codegen(context, builder, signature, args):
            return builder.bitcast(args[0], ir.IntType(64))

        return types.int64(types.float64), codegen

    @intrinsic
    def _bits_float(typingctx, bits):
        """The float64 whose 64 bits are the int64 ``bits`` (``float_bits`` undone)."""
        if bits != types.int64:
            return None

        def codegen(context, builder, signature, args):
            return builder.bitcast(args[0], ir.DoubleType())

        return types.float64(types.int64), codegen

    # With numba's JIT switched off (NUMBA_DISABLE_JIT=1, to debug a kernel in Python) an
    # intrinsic cannot run: the kernels then call the struct-based versions above.
    from numba.core import config as _numba_config

    if not getattr(_numba_config, "DISABLE_JIT", False):
        float_bits, bits_float = _float_bits, _bits_float


# fdlibm e_log.c: ln 2 in two parts (the high one with 32 trailing zero bits, so that k ln2_hi
# is exact for |k| < 2^11) and the coefficients Lg1..Lg7 of R(z), z = s^2.
_LN2_HI = 6.93147180369123816490e-01
_LN2_LO = 1.90821492927058770002e-10
_LG1 = 6.666666666666735130e-01
_LG2 = 3.999999999940941908e-01
_LG3 = 2.857142874366239149e-01
_LG4 = 2.222219843214978396e-01
_LG5 = 1.818357216161805012e-01
_LG6 = 1.531383769920937332e-01
_LG7 = 1.479819860511658591e-01
_TWO54 = 1.80143985094819840000e16
_SMALLEST_NORMAL = 2.2250738585072014e-308

# fdlibm e_asin.c: pi/2 in two parts and the coefficients of P(t) and Q(t), t = x^2.
_PIO2_HI = 1.57079632679489655800e00
_PIO2_LO = 6.12323399573676603587e-17
_PS0 = 1.66666666666666657415e-01
_PS1 = -3.25565818622400915405e-01
_PS2 = 2.01212532134862925881e-01
_PS3 = -4.00555345006794114027e-02
_PS4 = 7.91534994289814532176e-04
_PS5 = 3.47933107596021167570e-05
_QS1 = -2.40339491173441421878e00
_QS2 = 2.02094576023350569471e00
_QS3 = -6.88283971605453293030e-01
_QS4 = 7.70381505559019352791e-02


@lanes
def lane_log(x):
    """log(x) of a float64 (0 < x < inf; -inf at 0, nan below, inf at inf, nan at nan), within
    1 unit in the last place of numpy's, by selects only (module docstring)."""
    tiny = x < _SMALLEST_NORMAL
    y = x * _TWO54 if tiny else x
    bits = float_bits(y)
    high = bits >> 32  # sign, exponent and the mantissa's 20 leading bits
    k = (high >> 20) - 1023 - (54 if tiny else 0)
    high = high & 0x000FFFFF
    # m = the mantissa as 1.xxx or, above sqrt(2) (the 20 bits past 0x6a09e), halved
    i = (high + 0x95F64) & 0x100000
    k += i >> 20
    m = bits_float(((high | (i ^ 0x3FF00000)) << 32) | (bits & 0xFFFFFFFF))
    f = m - 1.0
    s = f / (2.0 + f)
    dk = float(k)
    z = s * s
    w = z * z
    t1 = w * (_LG2 + w * (_LG4 + w * _LG6))
    t2 = z * (_LG1 + w * (_LG3 + w * (_LG5 + w * _LG7)))
    r = t2 + t1
    half_square = 0.5 * f * f
    value = dk * _LN2_HI - ((half_square - (s * (half_square + r) + dk * _LN2_LO)) - f)
    if x > 0.0 and x < np.inf:
        return value
    if x == 0.0:
        return -np.inf
    return x if x == np.inf else np.nan


@lanes
def lane_arcsin(x):
    """arcsin(x) of a float64 in [-1, 1] (nan beyond, and at nan), within 2 units in the last
    place of numpy's, by selects only (module docstring)."""
    magnitude = abs(x)
    big = magnitude >= 0.5
    # t = x^2, or (1 - |x|) / 2 (exact for 0.5 <= |x| <= 1) whose root's arcsine is sought
    t = 0.5 * (1.0 - magnitude) if big else x * x
    p = t * (_PS0 + t * (_PS1 + t * (_PS2 + t * (_PS3 + t * (_PS4 + t * _PS5)))))
    q = 1.0 + t * (_QS1 + t * (_QS2 + t * (_QS3 + t * _QS4)))
    w = p / q
    root = np.sqrt(t)
    near_one = _PIO2_HI - (2.0 * (root + root * w) - _PIO2_LO)
    if big:
        return -near_one if x < 0.0 else near_one
    return x + x * w


# fdlibm s_atan.c: atan(0.5), atan(1), atan(1.5), atan(inf) in two parts, and the coefficients
# aT[0..10] of the odd polynomial.
_ATAN_HI0, _ATAN_HI1 = 4.63647609000806093515e-01, 7.85398163397448278999e-01
_ATAN_HI2, _ATAN_HI3 = 9.82793723247329054082e-01, 1.57079632679489655800e00
_ATAN_LO0, _ATAN_LO1 = 2.26987774529616870924e-17, 3.06161699786838301793e-17
_ATAN_LO2, _ATAN_LO3 = 1.39033110312309984516e-17, 6.12323399573676603587e-17
_AT0 = 3.33333333333329318027e-01
_AT1 = -1.99999999998764832476e-01
_AT2 = 1.42857142725034663711e-01
_AT3 = -1.11111104054623557880e-01
_AT4 = 9.09088713343650656196e-02
_AT5 = -7.69187620504482999495e-02
_AT6 = 6.66107313738753120669e-02
_AT7 = -5.83357013379057348645e-02
_AT8 = 4.97687799461593236017e-02
_AT9 = -3.65315727442169155270e-02
_AT10 = 1.62858201153657823623e-02
_PI = 3.1415926535897931160e00
_PI_LO = 1.2246467991473531772e-16


@inline
def _arctan_ratio(q):
    """atan(q) for q in [0, inf] (fdlibm's s_atan.c by selects): its five ranges of q, each
    but the first reduced by one division to an argument below 7/16 for the polynomial."""
    # [0, 7/16) as it is; [7/16, 11/16), [11/16, 19/16), [19/16, 39/16) about 0.5, 1, 1.5 by
    # (2q - 1) / (2 + q), (q - 1) / (q + 1), (q - 1.5) / (1 + 1.5 q); above, -1 / q about inf
    # (-1 / inf = -0 at q = inf: pi/2)
    small, first, second, third = q < 0.4375, q < 0.6875, q < 1.1875, q < 2.4375
    numerator = q if small else (2.0 * q - 1.0 if first else (q - 1.0 if second else (
        q - 1.5 if third else -1.0)))  # fmt: skip
    denominator = 1.0 if small else (2.0 + q if first else (q + 1.0 if second else (
        1.0 + 1.5 * q if third else q)))  # fmt: skip
    hi = 0.0 if small else (_ATAN_HI0 if first else (_ATAN_HI1 if second else (
        _ATAN_HI2 if third else _ATAN_HI3)))  # fmt: skip
    lo = 0.0 if small else (_ATAN_LO0 if first else (_ATAN_LO1 if second else (
        _ATAN_LO2 if third else _ATAN_LO3)))  # fmt: skip
    r = numerator / denominator
    z = r * r
    w = z * z
    s1 = z * (_AT0 + w * (_AT2 + w * (_AT4 + w * (_AT6 + w * (_AT8 + w * _AT10)))))
    s2 = w * (_AT1 + w * (_AT3 + w * (_AT5 + w * (_AT7 + w * _AT9))))
    return hi - ((r * (s1 + s2) - lo) - r)


@inline
def lane_arctan2(y, x):
    """arctan2(y, x) of two float64 (numpy's at the signed zeros, infinities and nan), within 2
    units in the last place of numpy's, by selects only: fdlibm's atan of q = |y| / |x|
    (``_arctan_ratio``), then the quadrant by the signs' bits (e_atan2.c)."""
    q = abs(y) / abs(x)  # inf where x = 0; nan where both are 0 or both inf
    angle = _arctan_ratio(q)  # in [0, pi/2]
    negative_x = float_bits(x) < 0  # the sign bits: -0 counts as negative
    negative_y = float_bits(y) < 0
    # x < 0 (but for q = inf, x = 0 or y infinite: pi/2 on either side)
    left = _PI - (angle - _PI_LO)
    angle = left if negative_x & (q < np.inf) else angle
    # q = nan: both 0 (0 or pi), both infinite (pi/4 or 3 pi/4), or a nan
    zero = abs(x) == 0.0
    both = (_PI if zero else 0.75 * _PI) if negative_x else (0.0 if zero else 0.25 * _PI)
    angle = angle if q == q else (both if (x == x) & (y == y) else np.nan)
    return -angle if negative_y else angle
