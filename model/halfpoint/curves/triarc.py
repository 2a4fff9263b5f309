# SPDX-License-Identifier: Apache-2.0
"""Tri-arc approximation of non-circular curves (seed 003), reconstructed.

The seed's equations were lost; this is the construction rebuilt from the
geometry it describes, and every fit is verified by dense sampling.

For a piece of curve whose curvature is monotone (so its osculating circles
are nested, Tait-Kneser), a group starts at node A and ends at node C:

* circle_X: the osculating circle at X (centre O_X, radius R_X);
* arc 1 passes through A with its centre on A's normal (O1 = A + R1 n_A, so
  it is tangent to the curve at A) and touches circle_B at E.  Tangency of
  two circles, |O1 - O_B| = |R1 - R_B|, squared, is linear in R1:
      R1 = (R_B^2 - |A - O_B|^2) / (2 (n_A . (A - O_B) + R_B));
* arc 3 passes through C, centre on C's normal, touches circle_B at F
  (the same formula with C);
* arc 2 is circle_B from E to F (it passes near B).

Node B is the furthest point after A for which the chain arc 1 + circle_B
(A -> E -> B) stays within the tolerance of the curve between A and B: the
seed's z1(D) = deviation - tolerance, which starts at -tolerance and grows
as D moves on; C is found from B the same way (z2) with circle_B + arc 3.
Consecutive groups share the node and the curve's normal there, so the whole
chain is tangent-continuous.  A piece that runs out gives a shorter last
group.  Curves are split at curvature extrema, inflection points and
curvature discontinuities first.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Callable

import numpy as np


@dataclass
class Curve:
    """A parametric plane curve with first and second derivatives."""

    p: Callable[[float], tuple[float, float]]
    d1: Callable[[float], tuple[float, float]]
    d2: Callable[[float], tuple[float, float]]
    t0: float
    t1: float

    def curvature(self, t: float) -> float:
        (x1, y1), (x2, y2) = self.d1(t), self.d2(t)
        return (x1 * y2 - y1 * x2) / (x1 * x1 + y1 * y1) ** 1.5

    def normal(self, t: float, ccw: bool | None = None) -> tuple[float, float]:
        """Unit normal towards the centre of curvature (to the left when the
        curve turns counter-clockwise; ``ccw`` decides where the curvature
        vanishes, at an inflection)."""
        x1, y1 = self.d1(t)
        n = math.hypot(x1, y1)
        left = (-y1 / n, x1 / n)
        turn_left = self.curvature(t) > 0 if ccw is None else ccw
        return left if turn_left else (-left[0], -left[1])

    def osculating(self, t: float):
        k = self.curvature(t)
        r = 1.0 / abs(k)
        px, py = self.p(t)
        n = self.normal(t)
        return (px + r * n[0], py + r * n[1]), r


def explicit(f, df, d2f, x0, x1) -> Curve:
    """y = f(x) over [x0, x1] as a parametric curve (t = x)."""
    return Curve(lambda t: (t, f(t)), lambda t: (1.0, df(t)), lambda t: (0.0, d2f(t)), x0, x1)


def ellipse(a: float, b: float, t0: float, t1: float) -> Curve:
    """x = a cos t, y = b sin t (counter-clockwise for t0 < t1)."""
    return Curve(lambda t: (a * math.cos(t), b * math.sin(t)),
                 lambda t: (-a * math.sin(t), b * math.cos(t)),
                 lambda t: (-a * math.cos(t), -b * math.sin(t)), t0, t1)


@dataclass
class FitArc:
    start: tuple[float, float]
    end: tuple[float, float]
    center: tuple[float, float]
    r: float
    ccw: bool

    def sweep(self) -> float:
        a0 = math.atan2(self.start[1] - self.center[1], self.start[0] - self.center[0])
        a1 = math.atan2(self.end[1] - self.center[1], self.end[0] - self.center[0])
        return (a1 - a0) % (2 * math.pi) if self.ccw else -((a0 - a1) % (2 * math.pi))

    def points(self, n: int):
        a0 = math.atan2(self.start[1] - self.center[1], self.start[0] - self.center[0])
        sw = self.sweep()
        ts = np.linspace(0, 1, n)
        return np.stack([self.center[0] + self.r * np.cos(a0 + ts * sw),
                         self.center[1] + self.r * np.sin(a0 + ts * sw)], axis=1)


def _tangent_arc(curve: Curve, t: float, ob, rb, ccw: bool):
    """Arc through curve(t), centre on its normal, touching circle (ob, rb):
    (centre, radius, touching point)."""
    a = curve.p(t)
    n = curve.normal(t, ccw)
    ax, ay = a[0] - ob[0], a[1] - ob[1]
    den = 2 * (n[0] * ax + n[1] * ay + rb)
    r1 = (rb * rb - ax * ax - ay * ay) / den
    o1 = (a[0] + r1 * n[0], a[1] + r1 * n[1])
    dx, dy = o1[0] - ob[0], o1[1] - ob[1]
    d = math.hypot(dx, dy) or 1e-300
    cands = [(ob[0] + rb * dx / d, ob[1] + rb * dy / d), (ob[0] - rb * dx / d, ob[1] - rb * dy / d)]
    e = min(cands, key=lambda q: abs(math.hypot(q[0] - o1[0], q[1] - o1[1]) - abs(r1)))
    return o1, abs(r1), e


def _chain_dev(curve: Curve, ta: float, tb: float, arcs, n: int = 200) -> float:
    """Largest distance from the curve on [ta, tb] to a chain of arcs, and from
    the arcs to the curve (sampled both ways)."""
    cpts = np.array([curve.p(t) for t in np.linspace(ta, tb, n)])
    apts = np.concatenate([a.points(max(8, n // len(arcs))) for a in arcs])

    def far(src, dst):
        d2 = ((src[:, None, :] - dst[None, :, :]) ** 2).sum(axis=2)
        return float(np.sqrt(d2.min(axis=1)).max())

    # distance to the arcs is measured exactly (radially), to the curve by a
    # dense sample refined near the nearest sample
    dev_c = 0.0
    for q in cpts:
        best = min(_dist_to_arc(q, a) for a in arcs)
        dev_c = max(dev_c, best)
    dense = np.array([curve.p(t) for t in np.linspace(ta, tb, 8 * n)])
    dev_a = far(apts, dense)
    return max(dev_c, dev_a)


def _dist_to_arc(q, a: FitArc) -> float:
    d = math.hypot(q[0] - a.center[0], q[1] - a.center[1])
    ang = math.atan2(q[1] - a.center[1], q[0] - a.center[0])
    a0 = math.atan2(a.start[1] - a.center[1], a.start[0] - a.center[0])
    sw = a.sweep()
    rel = (ang - a0) % (2 * math.pi) if sw > 0 else -((a0 - ang) % (2 * math.pi))
    if (sw > 0 and rel <= sw) or (sw < 0 and rel >= sw):
        return abs(d - a.r)
    return min(math.dist(q, a.start), math.dist(q, a.end))


def _arc(start, end, center, r, ccw) -> FitArc:
    return FitArc(tuple(start), tuple(end), tuple(center), r, ccw)


def _first_half(curve, ta, tb, ccw):
    """Chain arc 1 + circle_B from node A (ta) to node B (tb)."""
    ob, rb = curve.osculating(tb)
    o1, r1, e = _tangent_arc(curve, ta, ob, rb, ccw)
    return [_arc(curve.p(ta), e, o1, r1, ccw), _arc(e, curve.p(tb), ob, rb, ccw)], (ob, rb, e)


def _second_half(curve, tb, tc, ccw):
    """Chain circle_B + arc 3 from node B (tb) to node C (tc)."""
    ob, rb = curve.osculating(tb)
    o3, r3, f = _tangent_arc(curve, tc, ob, rb, ccw)
    return [_arc(curve.p(tb), f, ob, rb, ccw), _arc(f, curve.p(tc), o3, r3, ccw)], (o3, r3, f)


def _furthest(curve, t_from, t_end, tol, build):
    """Furthest t in (t_from, t_end] whose chain stays within tol (bisection
    on z(t) = deviation - tol after a forward scan)."""
    ccw = curve.curvature(0.5 * (t_from + t_end)) > 0

    def z(t):
        arcs, _ = build(curve, t_from, t, ccw)
        return _chain_dev(curve, t_from, t, arcs) - tol

    if z(t_end) <= 0:
        return t_end
    lo, hi = t_from, t_end
    step = (t_end - t_from) / 64
    t = t_from + step
    while t < t_end and z(t) <= 0:
        lo, t = t, t + step
    hi = min(t, t_end)
    for _ in range(40):
        mid = 0.5 * (lo + hi)
        if z(mid) <= 0:
            lo = mid
        else:
            hi = mid
    t = lo if lo > t_from else hi
    return t_end if t_end - t < 1e-9 * (t_end - t_from) else t


def split_points(curve: Curve, n: int = 4000) -> list[float]:
    """Parameters of curvature extrema, inflections and curvature
    discontinuities inside (t0, t1)."""
    ts = np.linspace(curve.t0, curve.t1, n)
    k = np.array([curve.curvature(t) for t in ts])
    cuts = []
    for i in range(1, n):
        if k[i - 1] * k[i] < 0:                          # inflection
            # refine by bisection on the sign of the curvature
            lo, hi = ts[i - 1], ts[i]
            for _ in range(60):
                mid = 0.5 * (lo + hi)
                if curve.curvature(mid) * k[i - 1] > 0:
                    lo = mid
                else:
                    hi = mid
            cuts.append(0.5 * (lo + hi))
    # curvature discontinuities: a jump far larger than the steps around it,
    # narrowed down by bisection (a real jump stays as the interval shrinks)
    dk = np.abs(np.diff(k))
    scale = float(np.abs(k).max()) or 1.0
    for i in range(1, n):
        around = np.concatenate([dk[max(0, i - 9):i - 1], dk[i:i + 8]])
        typical = float(np.median(around)) if len(around) else 0.0
        if dk[i - 1] > 50 * typical + 1e-6 * scale:
            lo, hi = ts[i - 1], ts[i]
            for _ in range(60):
                mid = 0.5 * (lo + hi)
                km = curve.curvature(mid)
                if abs(km - curve.curvature(lo)) > abs(curve.curvature(hi) - km):
                    hi = mid
                else:
                    lo = mid
            t_jump = 0.5 * (lo + hi)
            if not any(abs(t_jump - c) < 2 * (ts[1] - ts[0]) for c in cuts):
                cuts.append(t_jump)
    # extrema of |k|: sign changes of its slope (flat steps carry the last sign)
    ak = np.abs(k)
    last, last_i = 0, 0
    for i in range(1, n):
        d = ak[i] - ak[i - 1]
        s = 1 if d > 1e-12 * max(1.0, ak[i]) else -1 if d < -1e-12 * max(1.0, ak[i]) else 0
        if s == 0:
            continue
        if last and s != last and not any(abs(ts[last_i] - c) < 2 * (ts[1] - ts[0]) for c in cuts):
            cuts.append(0.5 * (ts[last_i] + ts[i - 1]))
        last, last_i = s, i
    return sorted(cuts)


def fit(curve: Curve, tol: float):
    """Tri-arc fit: (list of arcs, list of groups (index ranges))."""
    if tol <= 0:
        raise ValueError("tolerance must be positive")
    bounds = [curve.t0] + split_points(curve) + [curve.t1]
    arcs, groups = [], []
    for ta0, tend in zip(bounds, bounds[1:]):
        ccw = curve.curvature(0.5 * (ta0 + tend)) > 0
        ta = ta0
        kmax = max(abs(curve.curvature(t)) for t in np.linspace(ta0, tend, 64))
        flat_end = abs(curve.curvature(tend)) < 1e-6 * kmax     # ends at an inflection
        while ta < tend:
            tb = _furthest(curve, ta, tend, tol, _first_half)
            if tb >= tend and flat_end:
                # node B cannot sit where the osculating circle is a line:
                # put it half way and end the group with arc 3 at the inflection
                tb = ta + 0.5 * (tend - ta)
            first, (ob, rb, e) = _first_half(curve, ta, tb, ccw)
            if tb >= tend:
                groups.append((len(arcs), len(arcs) + 2))
                arcs += first
                break
            tc = _furthest(curve, tb, tend, tol, _second_half)
            second, (o3, r3, f) = _second_half(curve, tb, tc, ccw)
            group = [first[0], _arc(e, f, ob, rb, ccw), second[1]]
            groups.append((len(arcs), len(arcs) + 3))
            arcs += group
            ta = tc
    return arcs, groups


def verify(curve: Curve, arcs, tol: float):
    """(max deviation, max tangent direction change at a joint in rad)."""
    dev = 0.0
    for t in np.linspace(curve.t0, curve.t1, 4001):
        q = curve.p(t)
        dev = max(dev, min(_dist_to_arc(q, a) for a in arcs))
    dense = np.array([curve.p(t) for t in np.linspace(curve.t0, curve.t1, 40001)])
    for a in arcs:
        pts = a.points(64)
        d2 = ((pts[:, None, :] - dense[None, :, :]) ** 2).sum(axis=2)
        dev = max(dev, float(np.sqrt(d2.min(axis=1)).max()))
    worst = 0.0
    for a, b in zip(arcs, arcs[1:]):
        ta = _tan(a, a.end)
        tb = _tan(b, b.start)
        worst = max(worst, abs(math.atan2(ta[0] * tb[1] - ta[1] * tb[0], ta[0] * tb[0] + ta[1] * tb[1])))
    return dev, worst


def _tan(a: FitArc, p):
    rx, ry = p[0] - a.center[0], p[1] - a.center[1]
    s = 1 if a.sweep() > 0 else -1
    n = math.hypot(rx, ry)
    return (-s * ry / n, s * rx / n)


def parabola(a: float, b: float, c: float, x0: float, x1: float) -> Curve:
    """y = a x^2 + b x + c over [x0, x1]."""
    return explicit(lambda x: a * x * x + b * x + c, lambda x: 2 * a * x + b, lambda x: 2 * a, x0, x1)


def hyperbola(a: float, b: float, t0: float, t1: float) -> Curve:
    """Right branch of x^2/a^2 - y^2/b^2 = 1: x = a cosh t, y = b sinh t."""
    return Curve(lambda t: (a * math.cosh(t), b * math.sinh(t)),
                 lambda t: (a * math.sinh(t), b * math.cosh(t)),
                 lambda t: (a * math.cosh(t), b * math.sinh(t)), t0, t1)


def to_gcode(arcs, feed: float = 600.0) -> str:
    """G90 G91.1 mm: a G0 to the first point, then G2/G3 arcs."""
    out = ["G21 G90 G91.1 G17", f"G0 X{arcs[0].start[0]:.6f} Y{arcs[0].start[1]:.6f}"]
    first = True
    for a in arcs:
        i, j = a.center[0] - a.start[0], a.center[1] - a.start[1]
        word = "G3" if a.sweep() > 0 else "G2"
        fw = f" F{feed:g}" if first else ""
        out.append(f"{word} X{a.end[0]:.6f} Y{a.end[1]:.6f} I{i:.6f} J{j:.6f}{fw}")
        first = False
    out.append("M2")
    return "\n".join(out) + "\n"
