# SPDX-License-Identifier: Apache-2.0
"""Plane geometry for cutter compensation: lines, arcs, offsets, intersections.

Arcs store centre, radius, start angle and signed sweep (negative = CW).  An
intersection is accepted on an arc by the quadrant-split test of seed 004:
the arc is cut at the quadrant boundaries into pieces that are monotone in x
and in y, so "is this circle point on the arc" becomes a range comparison on
one piece.  Every pairwise test first rejects pairs whose bounding boxes do
not overlap.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

EPS = 1e-9
TAU = 2 * math.pi


@dataclass
class Line:
    p0: tuple[float, float]
    p1: tuple[float, float]
    src: int = 0                # source line number of the G-code block
    corner: bool = False        # a join inserted at a convex corner

    @property
    def start(self):
        return self.p0

    @property
    def end(self):
        return self.p1

    def length(self) -> float:
        return math.hypot(self.p1[0] - self.p0[0], self.p1[1] - self.p0[1])

    def point(self, t: float):
        return (self.p0[0] + t * (self.p1[0] - self.p0[0]),
                self.p0[1] + t * (self.p1[1] - self.p0[1]))

    def tangent(self, t: float):
        n = self.length() or 1.0
        return ((self.p1[0] - self.p0[0]) / n, (self.p1[1] - self.p0[1]) / n)

    def bbox(self):
        bb = self.__dict__.get("_bb")
        if bb is None:
            bb = self.__dict__["_bb"] = (min(self.p0[0], self.p1[0]), min(self.p0[1], self.p1[1]),
                                         max(self.p0[0], self.p1[0]), max(self.p0[1], self.p1[1]))
        return bb

    def param(self, p) -> float:
        dx, dy = self.p1[0] - self.p0[0], self.p1[1] - self.p0[1]
        n2 = dx * dx + dy * dy
        return ((p[0] - self.p0[0]) * dx + (p[1] - self.p0[1]) * dy) / n2 if n2 else 0.0

    def with_start(self, p):
        return Line(p, self.p1, self.src, self.corner)

    def with_end(self, p):
        return Line(self.p0, p, self.src, self.corner)

    def distance(self, p) -> float:
        t = min(max(self.param(p), 0.0), 1.0)
        q = self.point(t)
        return math.hypot(p[0] - q[0], p[1] - q[1])


@dataclass
class Arc:
    c: tuple[float, float]
    r: float
    a0: float                   # start angle
    sweep: float                # signed, negative = clockwise
    src: int = 0
    corner: bool = False

    @staticmethod
    def from_points(c, s, e, cw: bool, src: int = 0, corner: bool = False, full_if_closed=True):
        r = math.hypot(s[0] - c[0], s[1] - c[1])
        a0 = math.atan2(s[1] - c[1], s[0] - c[0])
        a1 = math.atan2(e[1] - c[1], e[0] - c[0])
        if cw:
            sw = -((a0 - a1) % TAU)
        else:
            sw = (a1 - a0) % TAU
        if abs(sw) < 1e-12 and full_if_closed:
            sw = -TAU if cw else TAU
        return Arc(c, r, a0, sw, src, corner)

    @property
    def cw(self) -> bool:
        return self.sweep < 0

    def point(self, t: float):
        a = self.a0 + t * self.sweep
        return (self.c[0] + self.r * math.cos(a), self.c[1] + self.r * math.sin(a))

    @property
    def start(self):
        p = self.__dict__.get("_s")
        if p is None:
            p = self.__dict__["_s"] = self.point(0.0)
        return p

    @property
    def end(self):
        p = self.__dict__.get("_e")
        if p is None:
            p = self.__dict__["_e"] = self.point(1.0)
        return p

    def length(self) -> float:
        return abs(self.sweep) * self.r

    def tangent(self, t: float):
        a = self.a0 + t * self.sweep
        s = 1 if self.sweep > 0 else -1
        return (-s * math.sin(a), s * math.cos(a))

    def _pieces(self):
        """Quadrant-monotone pieces as (t_lo, t_hi) parameter ranges."""
        q = math.pi / 2
        cuts = [0.0, 1.0]
        if self.sweep > 0:
            k = math.floor(self.a0 / q) + 1
            while k * q < self.a0 + self.sweep - 1e-12:
                cuts.append((k * q - self.a0) / self.sweep)
                k += 1
        elif self.sweep < 0:
            k = math.ceil(self.a0 / q) - 1
            while k * q > self.a0 + self.sweep + 1e-12:
                cuts.append((k * q - self.a0) / self.sweep)
                k -= 1
        cuts = sorted(set(t for t in cuts if 0.0 <= t <= 1.0))
        return list(zip(cuts, cuts[1:]))

    def bbox(self):
        bb = self.__dict__.get("_bb")
        if bb is None:
            pts = [self.point(t) for piece in self._pieces() for t in piece]
            xs, ys = [p[0] for p in pts], [p[1] for p in pts]
            bb = self.__dict__["_bb"] = (min(xs), min(ys), max(xs), max(ys))
        return bb

    def param(self, p) -> float | None:
        """Parameter of a circle point p on this arc, or None if off the arc
        (quadrant-split membership: a range test on a monotone piece)."""
        for lo, hi in self._pieces():
            q0, q1 = self.point(lo), self.point(hi)
            if (min(q0[0], q1[0]) - 1e-9 <= p[0] <= max(q0[0], q1[0]) + 1e-9 and
                    min(q0[1], q1[1]) - 1e-9 <= p[1] <= max(q0[1], q1[1]) + 1e-9):
                a = math.atan2(p[1] - self.c[1], p[0] - self.c[0])
                t = ((a - self.a0) / self.sweep) if self.sweep else 0.0
                # bring t into this piece's range (angles wrap by 2*pi)
                per = TAU / abs(self.sweep)
                while t < lo - 1e-9:
                    t += per
                while t > hi + 1e-9:
                    t -= per
                if lo - 1e-6 <= t <= hi + 1e-6:
                    return min(max(t, 0.0), 1.0)
        return None

    def with_start(self, p):
        t = self.param(p)
        t = 0.0 if t is None else t
        a = math.atan2(p[1] - self.c[1], p[0] - self.c[0])
        return Arc(self.c, self.r, a, self.sweep * (1 - t), self.src, self.corner)

    def with_end(self, p):
        t = self.param(p)
        t = 1.0 if t is None else t
        return Arc(self.c, self.r, self.a0, self.sweep * t, self.src, self.corner)

    def distance(self, p) -> float:
        d = math.hypot(p[0] - self.c[0], p[1] - self.c[1])
        if d > 0:
            q = (self.c[0] + (p[0] - self.c[0]) * self.r / d,
                 self.c[1] + (p[1] - self.c[1]) * self.r / d)
            if self.param(q) is not None:
                return abs(d - self.r)
        s, e = self.start, self.end
        return min(math.hypot(p[0] - s[0], p[1] - s[1]), math.hypot(p[0] - e[0], p[1] - e[1]))


@dataclass
class Spiral:
    """A programmed arc as LinuxCNC runs it when its end is not on the start's
    circle (within the arc end check's tolerance): about the programmed centre,
    the radius changing in proportion to the angle from the start's radius r0
    to the end's r1, so that it ends at the programmed end.  With r0 == r1 it is
    the circular arc."""
    c: tuple[float, float]
    r0: float
    r1: float
    a0: float                   # start angle
    sweep: float                # signed, negative = clockwise

    @staticmethod
    def from_points(c, s, e, cw: bool, full_if_closed=True):
        arc = Arc.from_points(c, s, e, cw, full_if_closed=full_if_closed)
        return Spiral(c, arc.r, math.hypot(e[0] - c[0], e[1] - c[1]), arc.a0, arc.sweep)

    def radius(self, t: float) -> float:
        return self.r0 + (self.r1 - self.r0) * t

    def point(self, t: float):
        a, r = self.a0 + t * self.sweep, self.radius(t)
        return (self.c[0] + r * math.cos(a), self.c[1] + r * math.sin(a))

    def param(self, p) -> float | None:
        """The parameter t in [0, 1] of the spiral's point in the direction of p
        from the centre, None outside the sweep."""
        a = math.atan2(p[1] - self.c[1], p[0] - self.c[0])
        d = (a - self.a0) % TAU if self.sweep > 0 else (self.a0 - a) % TAU
        t = d / abs(self.sweep) if self.sweep else 0.0
        return t if t <= 1.0 else None

    def distance(self, p) -> float:
        """Distance of p from the spiral: radial within the sweep (an upper bound
        of the exact distance, equal to it for a circle), else to the nearer end."""
        d = math.hypot(p[0] - self.c[0], p[1] - self.c[1])
        t = self.param(p) if d > 0 else None
        if t is not None:
            return abs(d - self.radius(t))
        s, e = self.point(0.0), self.point(1.0)
        return min(math.hypot(p[0] - s[0], p[1] - s[1]), math.hypot(p[0] - e[0], p[1] - e[1]))


def boxes_overlap(a, b, tol=1e-9) -> bool:
    return not (a[2] < b[0] - tol or b[2] < a[0] - tol or a[3] < b[1] - tol or b[3] < a[1] - tol)


def _circle_line(c, r, p0, p1):
    dx, dy = p1[0] - p0[0], p1[1] - p0[1]
    fx, fy = p0[0] - c[0], p0[1] - c[1]
    a = dx * dx + dy * dy
    b = 2 * (fx * dx + fy * dy)
    cc = fx * fx + fy * fy - r * r
    disc = b * b - 4 * a * cc
    if a == 0 or disc < -1e-12:
        return []
    disc = max(disc, 0.0)
    sq = math.sqrt(disc)
    ts = {(-b - sq) / (2 * a), (-b + sq) / (2 * a)}
    return [(p0[0] + t * dx, p0[1] + t * dy) for t in ts]


def _circle_circle(c0, r0, c1, r1):
    dx, dy = c1[0] - c0[0], c1[1] - c0[1]
    d = math.hypot(dx, dy)
    if d < 1e-12 or d > r0 + r1 + 1e-12 or d < abs(r0 - r1) - 1e-12:
        return []
    a = (r0 * r0 - r1 * r1 + d * d) / (2 * d)
    h = math.sqrt(max(r0 * r0 - a * a, 0.0))
    mx, my = c0[0] + a * dx / d, c0[1] + a * dy / d
    if h < 1e-12:
        return [(mx, my)]
    return [(mx + h * dy / d, my - h * dx / d), (mx - h * dy / d, my + h * dx / d)]


def intersect(a, b):
    """Intersections of two elements: list of (t_a, t_b, point)."""
    if not boxes_overlap(a.bbox(), b.bbox()):
        return []
    out = []
    if isinstance(a, Line) and isinstance(b, Line):
        (x1, y1), (x2, y2) = a.p0, a.p1
        (x3, y3), (x4, y4) = b.p0, b.p1
        den = (x1 - x2) * (y3 - y4) - (y1 - y2) * (x3 - x4)
        if abs(den) < 1e-15:
            return []
        ta = ((x1 - x3) * (y3 - y4) - (y1 - y3) * (x3 - x4)) / den
        tb = -((x1 - x2) * (y1 - y3) - (y1 - y2) * (x1 - x3)) / den
        if -EPS <= ta <= 1 + EPS and -EPS <= tb <= 1 + EPS:
            out.append((ta, tb, a.point(ta)))
        return out
    if isinstance(a, Line) or isinstance(b, Line):
        line, arc = (a, b) if isinstance(a, Line) else (b, a)
        for p in _circle_line(arc.c, arc.r, line.p0, line.p1):
            tl = line.param(p)
            if not -EPS <= tl <= 1 + EPS:
                continue
            tc = arc.param(p)
            if tc is None:
                continue
            out.append((tl, tc, p) if line is a else (tc, tl, p))
        return out
    for p in _circle_circle(a.c, a.r, b.c, b.r):
        ta, tb = a.param(p), b.param(p)
        if ta is not None and tb is not None:
            out.append((ta, tb, p))
    return out
