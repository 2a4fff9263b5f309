# SPDX-License-Identifier: Apache-2.0
"""Vectorised plane geometry for many elements at once (numpy).

Elements (lines and arcs) are packed into one float array of ``NCOL``
columns: kind (0 line, 1 arc), the line's end points x0 y0 x1 y1 (for an arc:
its start and end points), and for an arc its centre cx cy, radius R, start
angle a0 and signed sweep sw.  On top of that:

* ``box_pairs``: every pair of boxes closer than a gap, found through a
  uniform grid (a spatial hash) instead of comparing all pairs; an element
  whose box covers many cells is compared with every box directly.
* ``point_distance``: distance from points to elements, pair by pair.
* ``element_distance``: the exact minimum distance between two elements,
  pair by pair (line-line and line-arc vectorised; arc-arc pairs, which are
  rare, one by one in Python).

Used by the compensation (``comp``) and by its independent check
(``check``); nothing here knows about G-code.
"""

from __future__ import annotations

import math

import numpy as np

from .geom import Line

NCOL = 10
K, X0, Y0, X1, Y1, CX, CY, R, A0, SW = range(NCOL)
TAU = 2 * math.pi
_BIG_CELLS = 64


def pack(elements) -> np.ndarray:
    """Array of geom.Line / geom.Arc objects (lines in one pass, arcs apart)."""
    n = len(elements)
    if not n:
        return np.zeros((0, NCOL))
    out = np.zeros((n, NCOL))
    arcs = [k for k, e in enumerate(elements) if type(e) is not Line]
    if len(arcs) < n:
        lines = [e for e in elements if type(e) is Line] if arcs else elements
        rows = np.array([(*e.p0, *e.p1) for e in lines], dtype=float)
        if arcs:
            mask = np.ones(n, dtype=bool)
            mask[arcs] = False
            out[mask, 1:5] = rows
        else:
            out[:, 1:5] = rows
    if arcs:
        out[arcs] = np.array([(1.0, *e.start, *e.end, e.c[0], e.c[1], e.r, e.a0, e.sweep)
                              for e in (elements[k] for k in arcs)], dtype=float)
    return out


def boxes(el: np.ndarray) -> np.ndarray:
    """Bounding boxes (x0, y0, x1, y1) of packed elements."""
    bx = np.empty((len(el), 4))
    bx[:, 0] = np.minimum(el[:, X0], el[:, X1])
    bx[:, 1] = np.minimum(el[:, Y0], el[:, Y1])
    bx[:, 2] = np.maximum(el[:, X0], el[:, X1])
    bx[:, 3] = np.maximum(el[:, Y0], el[:, Y1])
    arcs = np.nonzero(el[:, K] == 1)[0]
    if len(arcs):
        a = el[arcs]
        lo = np.minimum(a[:, A0], a[:, A0] + a[:, SW])
        hi = np.maximum(a[:, A0], a[:, A0] + a[:, SW])
        for q in range(4):       # the circle's extreme points the arc passes
            ang = q * math.pi / 2
            k = np.ceil((lo - ang) / TAU)
            inside = ang + k * TAU <= hi
            px = a[:, CX] + a[:, R] * math.cos(ang)
            py = a[:, CY] + a[:, R] * math.sin(ang)
            sub = bx[arcs]
            sub[:, 0] = np.where(inside, np.minimum(sub[:, 0], px), sub[:, 0])
            sub[:, 1] = np.where(inside, np.minimum(sub[:, 1], py), sub[:, 1])
            sub[:, 2] = np.where(inside, np.maximum(sub[:, 2], px), sub[:, 2])
            sub[:, 3] = np.where(inside, np.maximum(sub[:, 3], py), sub[:, 3])
            bx[arcs] = sub
    return bx


def _cells(bx, cell):
    c = np.floor(bx / cell).astype(np.int64)
    return c[:, 0], c[:, 1], c[:, 2], c[:, 3]


def _expand(idx, x0, y0, x1, y1):
    """(element index, cell key) for every cell each element's box covers."""
    nx = x1 - x0 + 1
    ny = y1 - y0 + 1
    cnt = nx * ny
    total = int(cnt.sum())
    rep = np.repeat(np.arange(len(idx)), cnt)
    start = np.repeat(np.cumsum(cnt) - cnt, cnt)
    off = np.arange(total) - start
    ix = x0[rep] + off // ny[rep]
    iy = y0[rep] + off % ny[rep]
    return idx[rep], ix * 4_000_000_007 + iy


def _join(ka, ea, kb, eb):
    """All (ea, eb) pairs whose cell keys are equal."""
    order = np.argsort(kb, kind="stable")
    kb, eb = kb[order], eb[order]
    lo = np.searchsorted(kb, ka, "left")
    hi = np.searchsorted(kb, ka, "right")
    n = hi - lo
    rep = np.repeat(np.arange(len(ka)), n)
    start = np.repeat(np.cumsum(n) - n, n)
    pos = lo[rep] + (np.arange(int(n.sum())) - start)
    return ea[rep], eb[pos]


def box_pairs(a: np.ndarray, b: np.ndarray, gap: float = 0.0, cell: float | None = None):
    """Index arrays (i, j): box a[i] and box b[j] are at most ``gap`` apart in
    x and in y (a superset of the pairs whose elements are within ``gap``).

    A uniform grid: every b box, grown by the gap and by half the largest
    small a box, is entered in the cells it covers; a small a box is looked
    up in the one cell of its centre, so each pair is found once.  Larger a
    boxes are entered in all their cells (pairs made unique), and boxes that
    cover very many cells are compared with every box directly."""
    e = np.zeros(0, np.int64)
    if len(a) == 0 or len(b) == 0:
        return e, e
    ext_a = np.maximum(a[:, 2] - a[:, 0], a[:, 3] - a[:, 1])
    ext_b = np.maximum(b[:, 2] - b[:, 0], b[:, 3] - b[:, 1])
    if cell is None:
        cell = max(gap, 2.0 * float(np.median(np.concatenate([ext_a, ext_b]))), 1e-6)
    small = ext_a <= cell
    half = float(ext_a[small].max()) / 2 if small.any() else 0.0
    grow = gap + half
    bx0, by0, bx1, by1 = _cells(np.stack([b[:, 0] - grow, b[:, 1] - grow,
                                          b[:, 2] + grow, b[:, 3] + grow], axis=1), cell)
    b_big = (bx1 - bx0 + 1) * (by1 - by0 + 1) > _BIG_CELLS
    ib = np.nonzero(~b_big)[0]
    eb, kb = _expand(ib, bx0[ib], by0[ib], bx1[ib], by1[ib])
    out_i, out_j = [], []
    ia = np.nonzero(small)[0]
    if len(ia) and len(eb):
        cx = np.floor((a[ia, 0] + a[ia, 2]) / 2 / cell).astype(np.int64)
        cy = np.floor((a[ia, 1] + a[ia, 3]) / 2 / cell).astype(np.int64)
        pi, pj = _join(cx * 4_000_000_007 + cy, ia, kb, eb)
        out_i.append(pi)
        out_j.append(pj)
    large = np.nonzero(~small)[0]
    if len(large):
        ax0, ay0, ax1, ay1 = _cells(a[large], cell)
        big = (ax1 - ax0 + 1) * (ay1 - ay0 + 1) > _BIG_CELLS
        mid = large[~big]
        if len(mid) and len(eb):
            ea, ka = _expand(mid, ax0[~big], ay0[~big], ax1[~big], ay1[~big])
            pi, pj = _join(ka, ea, kb, eb)
            code = np.unique(pi * len(b) + pj)
            out_i.append(code // len(b))
            out_j.append(code % len(b))
        for k in large[big]:
            out_i.append(np.full(len(b), k))
            out_j.append(np.arange(len(b)))
    for k in np.nonzero(b_big)[0]:
        sel = np.arange(len(a))
        if len(large):
            ax0, ay0, ax1, ay1 = _cells(a[large], cell)
            big = (ax1 - ax0 + 1) * (ay1 - ay0 + 1) > _BIG_CELLS
            sel = np.setdiff1d(sel, large[big])
        out_i.append(sel)
        out_j.append(np.full(len(sel), k))
    if not out_i:
        return e, e
    i = np.concatenate(out_i).astype(np.int64)
    j = np.concatenate(out_j).astype(np.int64)
    keep = ((a[i, 0] <= b[j, 2] + gap) & (b[j, 0] <= a[i, 2] + gap) &
            (a[i, 1] <= b[j, 3] + gap) & (b[j, 1] <= a[i, 3] + gap))
    return i[keep], j[keep]


def _point_line(px, py, x0, y0, x1, y1):
    dx, dy = x1 - x0, y1 - y0
    n2 = dx * dx + dy * dy
    with np.errstate(invalid="ignore", divide="ignore"):
        t = np.where(n2 > 0, ((px - x0) * dx + (py - y0) * dy) / np.where(n2 > 0, n2, 1.0), 0.0)
    t = np.clip(t, 0.0, 1.0)
    return np.hypot(px - (x0 + t * dx), py - (y0 + t * dy))


def _on_arc(px, py, cx, cy, a0, sw):
    ang = np.arctan2(py - cy, px - cx)
    rel = np.mod((ang - a0) * np.sign(sw), TAU)
    return (rel <= np.abs(sw) + 1e-12) | (rel >= TAU - 1e-12)


def _point_arc(px, py, e):
    d = np.hypot(px - e[:, CX], py - e[:, CY])
    on = _on_arc(px, py, e[:, CX], e[:, CY], e[:, A0], e[:, SW])
    ends = np.minimum(np.hypot(px - e[:, X0], py - e[:, Y0]),
                      np.hypot(px - e[:, X1], py - e[:, Y1]))
    return np.where(on, np.abs(d - e[:, R]), ends)


def point_distance(px, py, e: np.ndarray) -> np.ndarray:
    """Distance from point k to packed element e[k], for every k."""
    out = _point_line(px, py, e[:, X0], e[:, Y0], e[:, X1], e[:, Y1])
    arcs = e[:, K] == 1
    if arcs.any():
        out[arcs] = _point_arc(px[arcs], py[arcs], e[arcs])
    return out


def _seg_seg(a, b):
    sa = (a[:, X0], a[:, Y0], a[:, X1], a[:, Y1])
    sb = (b[:, X0], b[:, Y0], b[:, X1], b[:, Y1])
    d = np.minimum(np.minimum(_point_line(a[:, X0], a[:, Y0], *sb),
                              _point_line(a[:, X1], a[:, Y1], *sb)),
                   np.minimum(_point_line(b[:, X0], b[:, Y0], *sa),
                              _point_line(b[:, X1], b[:, Y1], *sa)))

    def orient(px, py, qx, qy, rx, ry):
        return (qx - px) * (ry - py) - (qy - py) * (rx - px)

    o1 = orient(a[:, X0], a[:, Y0], a[:, X1], a[:, Y1], b[:, X0], b[:, Y0])
    o2 = orient(a[:, X0], a[:, Y0], a[:, X1], a[:, Y1], b[:, X1], b[:, Y1])
    o3 = orient(b[:, X0], b[:, Y0], b[:, X1], b[:, Y1], a[:, X0], a[:, Y0])
    o4 = orient(b[:, X0], b[:, Y0], b[:, X1], b[:, Y1], a[:, X1], a[:, Y1])
    cross = (o1 * o2 < 0) & (o3 * o4 < 0)
    return np.where(cross, 0.0, d)


def _seg_arc(s, c):
    """Exact distance between segments s[k] and arcs c[k]."""
    x0, y0, x1, y1 = s[:, X0], s[:, Y0], s[:, X1], s[:, Y1]
    d = np.minimum(_point_arc(x0, y0, c), _point_arc(x1, y1, c))
    d = np.minimum(d, _point_line(c[:, X0], c[:, Y0], x0, y0, x1, y1))
    d = np.minimum(d, _point_line(c[:, X1], c[:, Y1], x0, y0, x1, y1))
    dx, dy = x1 - x0, y1 - y0
    fx, fy = x0 - c[:, CX], y0 - c[:, CY]
    aa = dx * dx + dy * dy
    safe = np.where(aa > 0, aa, 1.0)
    t = np.clip(-(fx * dx + fy * dy) / safe, 0.0, 1.0)
    qx, qy = x0 + t * dx, y0 + t * dy
    dq = np.hypot(qx - c[:, CX], qy - c[:, CY])
    on = _on_arc(qx, qy, c[:, CX], c[:, CY], c[:, A0], c[:, SW])
    d = np.where(on & (dq >= c[:, R]), np.minimum(d, dq - c[:, R]), d)
    bb = 2 * (fx * dx + fy * dy)
    cc = fx * fx + fy * fy - c[:, R] ** 2
    disc = bb * bb - 4 * aa * cc
    ok = (aa > 0) & (disc >= 0)
    sq = np.sqrt(np.where(ok, disc, 0.0))
    for sgn in (-1.0, 1.0):
        tt = (-bb + sgn * sq) / (2 * safe)
        px, py = x0 + tt * dx, y0 + tt * dy
        hit = ok & (tt >= 0) & (tt <= 1) & _on_arc(px, py, c[:, CX], c[:, CY], c[:, A0], c[:, SW])
        d = np.where(hit, 0.0, d)
    return d


def _arc_arc_one(a, b) -> float:
    """Exact distance between two arcs: end points against the other arc, the
    points on the line of centres, and zero where they cross."""
    def pa(x, y, e):
        return float(_point_arc(np.array([x]), np.array([y]), np.array([e]))[0])

    def on(x, y, e):
        return bool(_on_arc(np.array([x]), np.array([y]), e[CX], e[CY], e[A0], e[SW])[0])

    d = min(pa(a[X0], a[Y0], b), pa(a[X1], a[Y1], b), pa(b[X0], b[Y0], a), pa(b[X1], b[Y1], a))
    dx, dy = b[CX] - a[CX], b[CY] - a[CY]
    dist = math.hypot(dx, dy)
    if dist <= 1e-15:
        return d
    ux, uy = dx / dist, dy / dist
    for p, q, sgn in ((a, b, 1.0), (b, a, -1.0)):
        for k in (1.0, -1.0):
            px, py = p[CX] + k * sgn * ux * p[R], p[CY] + k * sgn * uy * p[R]
            if on(px, py, p):
                d = min(d, pa(px, py, q))
    r0, r1 = a[R], b[R]
    if abs(r0 - r1) <= dist <= r0 + r1:
        m = (r0 * r0 - r1 * r1 + dist * dist) / (2 * dist)
        h = math.sqrt(max(r0 * r0 - m * m, 0.0))
        mx, my = a[CX] + m * ux, a[CY] + m * uy
        for sg in (1.0, -1.0):
            px, py = mx + sg * h * uy, my - sg * h * ux
            if on(px, py, a) and on(px, py, b):
                return 0.0
    return d


def element_distance(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Exact minimum distance between packed elements a[k] and b[k]."""
    out = np.empty(len(a))
    la, lb = a[:, K] == 0, b[:, K] == 0
    m = la & lb
    out[m] = _seg_seg(a[m], b[m])
    m = la & ~lb
    out[m] = _seg_arc(a[m], b[m])
    m = ~la & lb
    out[m] = _seg_arc(b[m], a[m])
    for k in np.nonzero(~la & ~lb)[0]:
        out[k] = _arc_arc_one(a[k], b[k])
    return out
