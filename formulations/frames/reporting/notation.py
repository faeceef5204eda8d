"""Numbers as engineers read them, for the frames' tables and drawings.

A frame's results mix sizes: a 1e-13 moment where the answer is zero beside a
2 000 kN·m one, "-0.0", 17 digits of float.  Two rules, both on the scale of
what is being shown (a column of a table, the diagram a label sits on):

* **noise is zero**: a value below ``NOISE`` x the largest of its column (or
  diagram) is rounding of a zero and shows as 0 (never "-0");
* **precision by column**: every value of a column is rounded to the same
  number of decimals, the number that gives its largest value ``digits``
  significant digits (so 1234.56 and 0.3 in one column read 1234.6 and 0.3,
  not 0.30000000000000004, and 4.1e-6 beside them reads 0).

Labels on drawings use engineering notation when plain decimals would be
long: exponents in multiples of three (12.5×10³), the unit after the number.
"""

from __future__ import annotations

import math

import numpy as np

#: a value below NOISE x its column's (diagram's) largest is rounding of a zero
NOISE = 1e-9
#: significant digits of a column's largest value
DIGITS = 5


def decimals(ref: float, digits: int = DIGITS) -> int:
    """Decimals that show ``ref`` with ``digits`` significant digits (>= 0)."""
    ref = abs(float(ref))
    if not np.isfinite(ref) or ref == 0.0:
        return 0
    return max(0, digits - 1 - math.floor(math.log10(ref)))


def round_column(values, digits: int = DIGITS, ref: float | None = None) -> list:
    """The values of one column rounded alike (see the module docstring);
    non-finite values pass through.  ``ref``: the column's scale (default its
    largest finite |value|)."""
    arr = np.asarray(values, float)
    finite = arr[np.isfinite(arr)]
    if ref is None:
        ref = float(np.abs(finite).max()) if finite.size else 0.0
    d = decimals(ref, digits)
    out = []
    for v in arr:
        if not np.isfinite(v):
            out.append(float(v))
        elif abs(v) <= NOISE * ref:
            out.append(0.0)
        else:
            r = round(float(v), d)
            out.append(0.0 if r == 0 else r)   # round(-1e-7, 3) is -0.0
    return out


_SUPERSCRIPT = str.maketrans("-0123456789", "⁻⁰¹²³⁴⁵⁶⁷⁸⁹")


def label(value: float, unit: str = "", ref: float | None = None, digits: int = 3) -> str:
    """A value as printed on a drawing: 0 for noise (relative to ``ref``,
    the largest value of what it is drawn with), otherwise ``digits``
    significant digits, in plain decimals when the value lies in [1e-3, 1e5)
    and in engineering notation (×10³, ×10⁻⁶) beyond; the unit follows after
    a thin space."""
    v = float(value)
    ref = abs(v) if ref is None else abs(float(ref))
    tail = f"\u2009{unit}" if unit else ""
    if not np.isfinite(v):
        return f"{v}{tail}"
    if v == 0.0 or abs(v) <= NOISE * ref:
        return f"0{tail}"
    a = abs(v)
    if 1e-3 <= a < 1e5:
        d = decimals(a, digits)
        return f"{v:.{d}f}{tail}"
    exp = 3 * math.floor(math.log10(a) / 3)
    mant = round(v / 10.0 ** exp, decimals(v / 10.0 ** exp, digits))
    if abs(mant) >= 1000:    # 999 999 rounds to 1000×10³: 1.00×10⁶
        exp, mant = exp + 3, mant / 1000.0
    d = decimals(mant, digits)
    return f"{mant:.{d}f}×10{str(exp).translate(_SUPERSCRIPT)}{tail}"
