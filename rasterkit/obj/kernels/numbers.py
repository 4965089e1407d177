"""Numba kernels that parse the numbers of OBJ ``v``, ``vt`` and ``vn`` statements.

Every value is the correctly rounded float64 of its text (:func:`rasterkit.runtime.decimal.parse_decimal`):
the tokens it cannot round exactly are flagged for the caller (:mod:`rasterkit.obj.statements`)
to convert again, and so are those that are not a plain decimal number: the caller reads NaN
and infinity (``nan``, ``inf``, MSVC's ``1.#IND``...) and names the token when it is no number
at all. The kernels never raise on bad input: they return status codes.
"""

from __future__ import annotations

import numpy as np

from rasterkit.runtime.jit import kernel
from rasterkit.obj.kernels.scan import next_token
from rasterkit.runtime.decimal import NUMBER_INEXACT, NUMBER_OK, NUMBER_OTHER, parse_decimal


@kernel
def parse_number_rows(buf, starts, ends, width):
    """Parse the numbers of statements (v, vt, vn lines) into rows.

    Parameters
    ----------
    buf : (B,) uint8
    starts, ends : (S,) int64
        Statement ranges from :func:`~rasterkit.obj.kernels.scan.scan_statements`.
    width : int
        Numbers kept per row; further tokens are still checked.

    Returns
    -------
    values : (S, width) float64
        Parsed numbers; NaN where a statement has fewer tokens.
    status : (S,) int8
        Worst NUMBER_* status of the statement's tokens (NUMBER_OTHER: the caller reads
        the statement's tokens itself; its values here are incomplete).
    inexact : (S,) int64
        Bit k set when token k (k < width) is NUMBER_INEXACT.
    """
    rows = len(starts)
    # np.empty and loops: np.full and np.zeros compile an implementation each (~0.2 s)
    values = np.empty((rows, width))
    status = np.empty(rows, np.int8)
    inexact = np.empty(rows, np.int64)
    for r in range(rows):
        for k in range(width):
            values[r, k] = np.nan
        status[r] = NUMBER_OK
        inexact[r] = 0
        i = next_token(buf, starts[r], ends[r])[1]  # after the keyword
        k = 0
        while i < ends[r]:
            a, i = next_token(buf, i, ends[r])
            value, s = parse_decimal(buf, a, i)
            if s == NUMBER_OTHER:
                status[r] = NUMBER_OTHER
                break
            if k < width:
                values[r, k] = value
                if s == NUMBER_INEXACT:
                    inexact[r] |= np.int64(1) << k
                    status[r] = NUMBER_INEXACT
            k += 1
    return values, status, inexact
