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

from elements.jit import AVAILABLE, lanes

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
