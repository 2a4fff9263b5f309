# SPDX-License-Identifier: Apache-2.0
"""Independent checks of a compensated tool path (the safety net).

* ``gouges``: every element of the tool centre's path against every
  programmed element it can reach (a spatial hash finds the pairs whose boxes
  are within the radius; the exact minimum distance decides): any pair
  closer than ``r - tol`` is a gouge.
* ``self_crossings``: pairs of path elements that touch or cross anywhere
  other than where consecutive elements join.

Both work on ``geom.Line`` / ``geom.Arc`` objects and know nothing about how
the path was made; ``comp.compensate`` runs them on every result, and the
tests use them (next to a sampling oracle of their own) on random contours.
"""

from __future__ import annotations

import numpy as np

from .spatial import box_pairs, boxes, element_distance, pack

TOL = 1e-6
_CHUNK = 1 << 20


def _bound(bx):
    """Centre and half diagonal of each box: a circle around the element."""
    cx = (bx[:, 0] + bx[:, 2]) / 2
    cy = (bx[:, 1] + bx[:, 3]) / 2
    return cx, cy, np.hypot(bx[:, 2] - bx[:, 0], bx[:, 3] - bx[:, 1]) / 2


def gouges(path, programmed, r: float, tol: float = TOL, arrays=None):
    """(path index, programmed index, distance) for every pair of a path
    element and a programmed element closer than ``r - tol``.

    ``arrays``: the two lists already packed (``spatial.pack``), to save the
    work."""
    if not len(path) or not len(programmed):
        return []
    p, q = arrays if arrays is not None else (pack(path), pack(programmed))
    bp, bq = boxes(p), boxes(q)
    i, j = box_pairs(bp, bq, r)
    # circles around the two elements farther apart than r - tol: no gouge
    pcx, pcy, ph = _bound(bp)
    qcx, qcy, qh = _bound(bq)
    near = np.hypot(pcx[i] - qcx[j], pcy[i] - qcy[j]) - ph[i] - qh[j] < r - tol
    i, j = i[near], j[near]
    out = []
    for k in range(0, len(i), _CHUNK):
        ii, jj = i[k:k + _CHUNK], j[k:k + _CHUNK]
        d = element_distance(p[ii], q[jj])
        bad = np.nonzero(d < r - tol)[0]
        out += [(int(ii[b]), int(jj[b]), float(d[b])) for b in bad]
    return out


def self_crossings(path, tol: float = 1e-9, joint: float = 1e-6, arr=None):
    """(i, j) pairs of path elements, i < j, that come within ``tol`` of each
    other although more than ``joint`` of path lies between them (so the
    ordinary joints of neighbours, and hair-thin elements, are not counted).
    A path that ends where it starts is a loop: its last and first elements
    are neighbours."""
    if len(path) < 3:
        return []
    p = pack(path) if arr is None else arr
    arc = p[:, 0] == 1
    lengths = np.where(arc, np.abs(p[:, 9]) * p[:, 7],
                       np.hypot(p[:, 3] - p[:, 1], p[:, 4] - p[:, 2]))
    cum = np.concatenate([[0.0], np.cumsum(lengths)])
    b = boxes(p)
    i, j = box_pairs(b, b, tol)
    keep = i < j
    i, j = i[keep], j[keep]
    between = cum[j] - cum[i + 1]
    s, e = path[0].start, path[-1].end
    if abs(s[0] - e[0]) <= joint and abs(s[1] - e[1]) <= joint:
        between = np.minimum(between, cum[-1] - cum[j + 1] + cum[i])
    keep = between > joint
    i, j = i[keep], j[keep]
    out = []
    for k in range(0, len(i), _CHUNK):
        ii, jj = i[k:k + _CHUNK], j[k:k + _CHUNK]
        d = element_distance(p[ii], p[jj])
        bad = np.nonzero(d <= tol)[0]
        out += [(int(ii[x]), int(jj[x])) for x in bad]
    return out
