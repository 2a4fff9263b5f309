# SPDX-License-Identifier: Apache-2.0
"""Quantisation: moves in mm -> motion-core commands on the BLU lattice.

* One BLU per axis (default 0.001 mm); the two axes of an arc's plane must
  share it (arcs are circles on the lattice).
* Every lattice point the core visits lies within 1 BLU of the programmed
  block its command comes from, however many blocks follow each other (the
  bound; tb/cam/test_quant_bound.py checks it on the core model's positions).
  Every command is relative to where the core really is, and every target is
  chosen against the programmed absolute geometry, so nothing accumulates.
* Lines: the end is the nearest lattice point, or, where that would let the
  line stray too far, the one on the line's own lattice row (slid along the
  line to a whole major coordinate, then rounded: within 0.5 cos(angle) of
  it).  The line unit's points lie within 0.5 BLU along the minor axis of
  the straight line between its lattice ends, so a line strays at most its
  ends' offsets plus 0.5 cos(angle); when the core starts too far from a
  line (after an arc), a correcting step onto the line's row goes first.
* An arc whose sagitta is under a quarter BLU is run as its chord (a line,
  held within what the sagitta leaves of the bound).
* Arcs (``_Arcs``): cut into pieces, each with its own lattice centre and
  start chosen against the programmed circle, joined by correcting lines of
  a few BLU; every lattice point of every piece and correcting line is
  walked and measured (the walk that predicts the core's stop), and a piece
  with a point beyond 1 BLU is halved.  About 2.3 commands per arc on chains
  of off-lattice semicircles of 20-120 BLU.
* Arcs in G18 (Z X) and G19 (Y Z) are placed the same way in their plane's
  coordinates (the plane's two axes must share the BLU); the command names the
  plane's axes and the arc's exact move count (the walk's).  A helix (the
  normal axis moving with the arc) gives each arc piece the normal-axis delta
  that takes it to where the programmed helix is at the piece's end (the
  nearest lattice value, the programmed end exactly at the last piece); the
  core steps it in proportion to the piece's moves.  Correcting lines keep the
  normal axis still; a piece whose normal axis would move more BLU than the
  arc makes moves (steeper than the core's helix mapper steps) runs as short
  lines along the arc, the normal axis where the helix is there (``steep``
  names their lines).
* Every point and centre must fit the core's signed coordinate width; the
  error names the line.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace

from ..spec import encoding as enc
from ..spec.arc import ArcRun, lattice_point_near, validate
from ..spec.line import line_steps
from ..spec.rules import field_range, fits
from .gcode import PLANE_AXES, GcodeError, Move, full_circle
from .geom import Arc, Spiral

DEFAULT_BLU = 0.001
# lattice points and centres keep one value free at each end of the field
LATTICE_MARGIN = 1


@dataclass
class Quantised:
    cmds: list[int] = field(default_factory=list)
    moves_per_cmd: list[int] = field(default_factory=list)   # lattice moves each command makes
    src: list[Move] = field(default_factory=list)            # the move behind each command
    end: tuple[int, int, int] = (0, 0, 0)                     # lattice position at the end
    corrections: int = 0                                      # correcting lines inserted
    arcs: int = 0                                             # arc commands
    fallback: int = 0                                         # single-step lines for arcs
    steep: list[int] = field(default_factory=list)            # lines of helices run as lines


def _flat(m: Move):
    """Sagitta (mm) of an arc taken the short way round (at most half a
    turn), else None."""
    if full_circle(m) or not _minor(m):
        return None
    r_mm = math.hypot(m.start[0] - m.center[0], m.start[1] - m.center[1])
    chord = math.hypot(m.end[0] - m.start[0], m.end[1] - m.start[1])
    half = min(chord / (2 * r_mm), 1.0) if r_mm > 0 else 1.0
    return r_mm * (1 - math.sqrt(1 - half * half))


def _minor(m: Move) -> bool:
    """Is the arc's sweep at most half a turn?"""
    sx, sy = m.start[0] - m.center[0], m.start[1] - m.center[1]
    ex, ey = m.end[0] - m.center[0], m.end[1] - m.center[1]
    cross = sx * ey - sy * ex
    return (cross <= 0) if m.cw else (cross >= 0)


# Arcs are placed against the programmed absolute geometry (see _Arcs).
BOUND = 1.0             # BLU: every lattice point of an arc within this of the programmed arc
PIECE_TARGET = 0.5      # BLU: a piece's lattice circle predicted within this of the programmed one
ACCEPT_CUR = 0.1        # BLU: the current position is kept as a piece's start this close
LINE_BOUND = 1.0        # BLU: a line's start is corrected when it would stray further
MIN_SPLIT = 6.0         # BLU: pieces shorter than this are not split again
_SAMPLES = 7            # angles per piece at which a candidate circle is predicted


class _Arcs:
    """One programmed arc on the lattice, as one or more arc commands.

    The core runs an arc about an integer centre c from an integer start s,
    with the radius R0 = |s - c| of that start, every lattice point within
    0.5 BLU of that circle.  The programmed arc has a real centre P and radius
    R; at angle phi the core's circle lies

        g(phi) = sqrt(R0^2 + 2 R0 (c - P).u(phi) + |c - P|^2) - R

    from it (u the unit vector at phi), which varies by up to 2|c - P| round
    the arc.  So the arc is cut into pieces over which g varies little, and
    each piece gets its own c (one of the lattice points round P) and s (one
    of the lattice points round the programmed point where the piece starts,
    or where the core already is) that keep |g| smallest over the piece's
    angles; a piece predicted beyond PIECE_TARGET is halved.  When the core's
    stop is not the next piece's start, a correcting line goes there.

    The quantiser then walks every lattice point of each piece (the same walk
    that predicts the core's stop) and of each correcting line, and measures
    its distance to the programmed arc: a piece with a point beyond BOUND is
    halved too, and one too short to halve is sent as single-step lines to
    the lattice points nearest the programmed arc.  The bound therefore holds
    by construction, not by estimate."""

    def __init__(self, m: Move, b: float):
        self.m = m
        self.pcx, self.pcy = m.center[0] / b, m.center[1] / b
        el = Arc.from_points((self.pcx, self.pcy), (m.start[0] / b, m.start[1] / b),
                             (m.end[0] / b, m.end[1] / b), m.cw)
        self.full = full_circle(m)
        if self.full:                   # a whole turn, whatever rounding the end has
            el = Arc(el.c, el.r, el.a0, -2 * math.pi if m.cw else 2 * math.pi)
        self.el = el
        self.r = el.r
        self.a0, self.sweep = el.a0, el.sweep
        self.ps = el.start
        self.pe = el.start if self.full else (m.end[0] / b, m.end[1] / b)
        self.worst = 0.0
        # an end off the start's circle (within the arc end check's tolerance):
        # the programmed arc is LinuxCNC's spiral from the start's radius to the
        # end's (geom.Spiral), which every piece follows and is measured against
        sp = Spiral(el.c, el.r, math.hypot(self.pe[0] - self.pcx, self.pe[1] - self.pcy),
                    el.a0, el.sweep)
        self.sp = None if self.full or abs(sp.r1 - sp.r0) < 1e-9 else sp

    def radius(self, t: float) -> float:
        """The programmed radius at the fraction t of the sweep."""
        return self.r if self.sp is None else self.sp.radius(t)

    def dist(self, x: float, y: float) -> float:
        """Distance (BLU) of a lattice point from the programmed arc: radial
        in the arc's span, else to the nearer end (exact near the ends)."""
        if self.sp is not None:
            return self.sp.distance((x, y))
        dx, dy = x - self.pcx, y - self.pcy
        e = abs(math.sqrt(dx * dx + dy * dy) - self.r)
        ps, pe = self.ps, self.pe
        if abs(x - ps[0]) + abs(y - ps[1]) < 6 or abs(x - pe[0]) + abs(y - pe[1]) < 6:
            return self.el.distance((x, y))
        return e

    def angle(self, t: float) -> float:
        return self.a0 + self.sweep * t

    def place(self, t0: float, t1: float, cur):
        """(predicted error, centre, start) of the best circle for a piece."""
        pcx, pcy = self.pcx, self.pcy
        a, b = self.angle(t0), self.angle(t1)
        dirs = [(math.cos(a + (b - a) * k / (_SAMPLES - 1)),
                 math.sin(a + (b - a) * k / (_SAMPLES - 1))) for k in range(_SAMPLES)]
        radii = [self.radius(t0 + (t1 - t0) * k / (_SAMPLES - 1)) for k in range(_SAMPLES)]
        qx, qy = pcx + radii[0] * dirs[0][0], pcy + radii[0] * dirs[0][1]
        starts = {(x, y) for x in range(math.floor(qx) - 1, math.ceil(qx) + 2)
                  for y in range(math.floor(qy) - 1, math.ceil(qy) + 2)
                  if (x - qx) ** 2 + (y - qy) ** 2 <= 2.25}
        starts.add((cur[0], cur[1]))
        best = None
        for cx in {math.floor(pcx), math.ceil(pcx)}:
            for cy in {math.floor(pcy), math.ceil(pcy)}:
                dx, dy = cx - pcx, cy - pcy
                d2 = dx * dx + dy * dy
                proj = [dx * u + dy * v for u, v in dirs]
                for sx, sy in starts:
                    r02 = (sx - cx) ** 2 + (sy - cy) ** 2
                    if r02 == 0:
                        continue
                    r0 = math.sqrt(r02)
                    err = max(abs(math.sqrt(max(r02 + 2 * r0 * p + d2, 0.0)) - rk)
                              for p, rk in zip(proj, radii))
                    err = max(err, self.dist(sx, sy))
                    # within ACCEPT_CUR, staying where the core is (no
                    # correcting line) comes first
                    far = err > ACCEPT_CUR
                    key = (far, not far and (sx, sy) != (cur[0], cur[1]), err)
                    if best is None or key < best[0]:
                        best = (key, (cx, cy), (sx, sy))
        if best is None:
            return None
        return best[0][1], best[1], best[2]

    def walk(self, c, s, e, cw):
        """(stop x, stop y, moves, worst distance) of the core's arc from s
        to e about c (absolute lattice points), every point measured."""
        run = ArcRun(s[0] - c[0], s[1] - c[1], e[0] - c[0], e[1] - c[1], cw, check=False)
        adv = run.advance
        ox, oy = c[0] - self.pcx, c[1] - self.pcy
        r = self.r
        (sx, sy), (ex, ey) = self.ps, self.pe
        ax, ay = c[0], c[1]
        worst = 0.0
        if self.sp is not None:             # a spiral: every point against it
            sp = self.sp
            while not run.done:
                adv()
                worst = max(worst, sp.distance((run.x + ax, run.y + ay)))
            return run.x + ax, run.y + ay, run.moves, worst
        while not run.done:
            adv()
            x, y = run.x, run.y
            dx, dy = x + ox, y + oy
            d = abs(math.sqrt(dx * dx + dy * dy) - r)
            px, py = x + ax, y + ay
            if abs(px - sx) + abs(py - sy) < 6 or abs(px - ex) + abs(py - ey) < 6:
                d = self.el.distance((px, py))
            if d > worst:
                worst = d
        return run.x + ax, run.y + ay, run.moves, worst

    def line_worst(self, a, b) -> float:
        """Worst distance of the lattice points of a line from a to b."""
        x, y = a[0], a[1]
        worst = 0.0
        for sx, sy in line_steps([b[0] - a[0], b[1] - a[1]]):
            x += sx
            y += sy
            worst = max(worst, self.dist(x, y))
        return worst


def _end_point(r2: int, ex: float, ey: float):
    """Lattice point next to the programmed end (centre-relative, in BLU)
    nearest the lattice circle of R^2 = r2, then nearest the programmed end."""
    best = None
    for x in (math.floor(ex) - 1, math.floor(ex), math.ceil(ex), math.ceil(ex) + 1):
        for y in (math.floor(ey) - 1, math.floor(ey), math.ceil(ey), math.ceil(ey) + 1):
            if x == 0 and y == 0:
                continue
            key = (abs(math.sqrt(x * x + y * y) - math.sqrt(r2)) + math.hypot(x - ex, y - ey))
            if best is None or key < best[0]:
                best = (key, (x, y))
    return best[1]


def _on_line(sx: float, sy: float, ex: float, ey: float, px: float, py: float):
    """Lattice point near the point (px, py) of the line from (sx, sy) to
    (ex, ey): slid along the line to the nearest whole major coordinate, then
    the minor one rounded, so it lies within 0.5 cos(angle to the major axis)
    of the line and within 0.87 BLU of (px, py)."""
    ux, uy = ex - sx, ey - sy
    if abs(ux) >= abs(uy):
        x = round(px)
        return x, round(py + (x - px) * uy / ux)
    y = round(py)
    return round(px + (y - py) * ux / uy), y


def _line_ends(cur, sx: float, sy: float, ex: float, ey: float, bound: float):
    """Where a line from the programmed (sx, sy) to (ex, ey) (BLU) runs on the
    lattice from the core's position ``cur`` with every point within ``bound``
    of the programmed line: (the correcting step's lattice end or None, the
    line's lattice end, whether both hold the bound).

    A line's points lie within 0.5 BLU along the minor axis of the straight
    line between its lattice ends: near an end they are off the programmed
    line by that end's offset plus 0.5 cos(angle to the major axis).  A lattice
    end within bound - 0.5 of the programmed one keeps that within bound;
    beyond, the exact test, and a point on the line's own lattice row where the
    nearest one fails it.  That point is within 0.5 cos of the line, which holds
    a bound of 1 BLU whatever the angle but may not hold a smaller one (an
    arc's chord), so the answer says whether it did."""
    tx, ty = round(ex), round(ey)
    near = (bound - 0.5) * (bound - 0.5)
    fx, fy = tx - ex, ty - ey
    gx, gy = cur[0] - sx, cur[1] - sy
    far_end = fx * fx + fy * fy > near
    far_start = gx * gx + gy * gy > near
    fix, holds = None, True
    if (far_end or far_start) and (sx != ex or sy != ey):
        ux, uy = ex - sx, ey - sy
        n = math.sqrt(ux * ux + uy * uy)
        lim = bound - 0.5 * max(abs(ux), abs(uy)) / n

        def strays(px: float, py: float, end: bool) -> bool:
            along = (px * ux + py * uy) / n
            return abs(px * uy - py * ux) / n > lim or (along > bound if end
                                                        else along < -bound)

        if far_end and strays(fx, fy, True):
            # the nearest lattice point would let the line stray too far near
            # its end: the one on the line's own lattice row instead
            tx, ty = _on_line(sx, sy, ex, ey, ex, ey)
            holds = not strays(tx - ex, ty - ey, True)
        if far_start and strays(gx, gy, False):
            # the core is too far from the line's start (an arc stopped off it):
            # a correcting step onto the line's own lattice row
            fix = _on_line(sx, sy, ex, ey, sx, sy)
            holds = holds and not strays(fix[0] - sx, fix[1] - sy, False)
    elif far_start and math.hypot(gx, gy) > bound:
        fix = (round(sx), round(sy))
        holds = math.hypot(fix[0] - sx, fix[1] - sy) <= bound
    return fix, (tx, ty), holds


def _line_cmd(q: Quantised, m: Move, line_head: int, cur, to, correction: bool):
    dx, dy = to[0] - cur[0], to[1] - cur[1]
    if not (dx or dy):
        return cur
    mask = 0xFFFFFFFF
    q.cmds.append(line_head | ((dx & mask) << 64) | ((dy & mask) << 96))
    q.moves_per_cmd.append(max(abs(dx), abs(dy)))
    q.src.append(m)
    q.corrections += correction
    return [to[0], to[1], cur[2]]


def _plane_line(q: Quantised, m: Move, plane, cur, to, correction: bool):
    """A line command from ``cur`` to ``to`` (both (u, v, n): the plane's first,
    second and normal axis, ``plane`` = PLANE_AXES of the arc); returns ``to``."""
    deltas = [0, 0, 0]
    for axis, a, b in zip(plane, cur, to):
        deltas[axis] = b - a
    if not any(deltas):
        return list(cur)
    q.cmds.append(enc.encode_line(deltas))
    q.moves_per_cmd.append(max(abs(d) for d in deltas))
    q.src.append(m)
    q.corrections += correction
    return list(to)


class _Helix:
    """The normal axis of a helical arc: where it should be at a fraction t of the
    sweep (BLU, nearest lattice value; exactly the programmed end at t = 1)."""

    def __init__(self, n0: float, n1: float):
        self.n0, self.n1 = n0, n1
        self.end = round(n1)

    @classmethod
    def of(cls, m: Move, plane, blu) -> "_Helix":
        ap = plane[2]
        return cls(m.start[ap] / blu[ap], m.end[ap] / blu[ap])

    def at(self, t: float) -> int:
        return self.end if t >= 1.0 else round(self.n0 + (self.n1 - self.n0) * t)


def _view(m: Move, plane) -> Move:
    """The arc in its plane's coordinates (u, v, n) (``Move.center`` already is)."""
    def perm(p):
        return tuple(p[a] for a in plane)
    return replace(m, start=perm(m.start), end=perm(m.end), plane=17)


def _arc_cmds(q: Quantised, m: Move, b: float, cur, width: int, rate_q: int, line_head: int,
              plane=(0, 1, 2), helix: _Helix | None = None, src: Move | None = None):
    """The commands of one programmed arc (see _Arcs), ``m`` and ``cur`` in the
    plane's coordinates (u, v, n) (``_view``; ``src`` the programmed move the
    commands come from, default ``m``); returns the position after them (u, v, n).
    A helix's normal axis moves with each arc piece to where the programmed helix
    is at the piece's end (``_Helix``), stepped by the core in proportion to the
    piece's moves; correcting lines keep it still."""
    A = _Arcs(m, b)
    cw = int(m.cw)
    src = src or m
    if helix is None:
        helix = _Helix(cur[2], cur[2])
    stack = [(0.0, 1.0)]
    while stack:
        t0, t1 = stack.pop()
        length = abs(A.sweep) * (t1 - t0) * A.r
        mid = (t0 + t1) / 2
        placed = A.place(t0, t1, cur)
        if placed is None:
            raise GcodeError(m.lineno, "arc radius is below one BLU")
        err, c, s = placed
        if err > PIECE_TARGET and length > MIN_SPLIT:
            stack += [(mid, t1), (t0, mid)]
            continue
        if not all(fits(v, width, LATTICE_MARGIN) for v in c):
            raise GcodeError(m.lineno, f"arc centre outside the core's {width}-bit range "
                                       "at this BLU")
        xs, ys = s[0] - c[0], s[1] - c[1]
        r2 = xs * xs + ys * ys
        if A.full and t0 == 0.0 and t1 == 1.0:
            xe, ye = xs, ys             # a programmed full circle in one piece
        else:
            ang = A.angle(t1)
            ex = A.pcx + A.radius(t1) * math.cos(ang) - c[0]
            ey = A.pcy + A.radius(t1) * math.sin(ang) - c[1]
            if t1 == 1.0 and not A.full:
                ex, ey = A.pe[0] - c[0], A.pe[1] - c[1]
            xe, ye = _end_point(r2, ex, ey)
            if validate(xs, ys, xe, ye, width):
                xe, ye = lattice_point_near(r2, math.atan2(ey, ex))
            if (xe, ye) == (xs, ys):
                continue                # a piece shorter than the lattice: no motion
        if validate(xs, ys, xe, ye, width):
            raise GcodeError(m.lineno, "arc cannot be put on the lattice "
                                       "(radius too large for the width?)")
        stop_x, stop_y, n, worst = A.walk(c, s, (c[0] + xe, c[1] + ye), cw)
        if s != (cur[0], cur[1]):
            worst = max(worst, A.line_worst(cur, s))
        if worst > BOUND:
            if length > MIN_SPLIT:
                stack += [(mid, t1), (t0, mid)]
                continue
            cur = _fallback_lines(q, src, A, t0, t1, cur, plane, helix)
            continue
        dn = helix.at(t1) - cur[2]
        if abs(dn) > n:
            # steeper than the helix mapper's one step of the normal axis per arc
            # move (gcodetools plunges in its first arc): the piece runs as short
            # lines through the lattice points nearest the arc, the normal axis
            # where the helix is there (LinuxCNC and grbl run it)
            if src.lineno not in q.steep:
                q.steep.append(src.lineno)
            cur = _fallback_lines(q, src, A, t0, t1, cur, plane, helix)
            continue
        A.worst = max(A.worst, worst)
        # a short correcting line onto the chosen start (a few BLU at most)
        cur = _plane_line(q, src, plane, cur, (s[0], s[1], cur[2]), True)
        if dn and n >= 1 << 32:
            raise GcodeError(m.lineno, "helix too long for the core: its arc makes more moves "
                                       "than the 32-bit count holds")
        if not fits(cur[2] + dn, width, LATTICE_MARGIN):
            raise GcodeError(m.lineno, f"helix leaves the core's {width}-bit range at this BLU")
        q.cmds.append(enc.encode_arc(cw, c[0] - cur[0], c[1] - cur[1],
                                     c[0] + xe - cur[0], c[1] + ye - cur[1],
                                     plane=plane[:2], count=n if n < 1 << 32 else 0,
                                     helix=(dn,) if dn else ()))
        q.moves_per_cmd.append(n)
        q.src.append(src)
        q.arcs += 1
        cur = [stop_x, stop_y, cur[2] + dn]
        if not all(fits(v, width, LATTICE_MARGIN) for v in cur):
            raise GcodeError(m.lineno, f"arc leaves the core's {width}-bit range at this BLU")
    return cur


def _fallback_lines(q: Quantised, m: Move, A: _Arcs, t0: float, t1: float, cur, plane,
                    helix: _Helix):
    """A short piece the arc unit cannot hold within BOUND: single-step lines
    through the lattice points nearest the programmed arc (each within
    0.71 BLU of it; a helix's normal axis where the helix is there)."""
    n = max(2, math.ceil(abs(A.sweep) * (t1 - t0) * A.r / 0.4))
    for k in range(n + 1):
        t = t0 + (t1 - t0) * k / n
        a, rt = A.angle(t), A.radius(t)
        to = (round(A.pcx + rt * math.cos(a)), round(A.pcy + rt * math.sin(a)))
        if k == n and t1 == 1.0 and not A.full:
            to = (round(A.pe[0]), round(A.pe[1]))
        cur = _plane_line(q, m, plane, cur, (to[0], to[1], helix.at(t)), False)
        q.fallback += 1
    return cur


def quantise(moves: list[Move], blu=(DEFAULT_BLU,) * 3, width: int = 32,
             rate: float = 2.0) -> Quantised:
    if min(blu) <= 0:
        raise ValueError("a BLU must be positive")
    q = Quantised()
    cur = [0, 0, 0]

    def lat(p, k):
        return round(p / blu[k])

    bx, by, bz = blu
    lo, hi = field_range(width, LATTICE_MARGIN)
    mask = 0xFFFFFFFF
    line_head = enc.OP_LINE     # no rate: a PROFILE gives each command its speeds
    for m in moves:
        bound, chord = LINE_BOUND, None
        if m.kind == "arc":
            plane = PLANE_AXES[m.plane]
            a0, a1, ap = plane
            if abs(blu[a0] - blu[a1]) > 1e-15:
                raise GcodeError(m.lineno, f"an arc in G{m.plane} needs axes {'XYZ'[a0]} and "
                                           f"{'XYZ'[a1]} to share the BLU (blu_mm "
                                           f"{blu[a0]:g} and {blu[a1]:g})")
            flat_xy = m.plane == 17 and abs(m.end[2] - m.start[2]) <= 1e-12
            sag = _flat(m) if flat_xy else None
            if sag is not None and sag < 0.25 * bx:
                # an arc whose sagitta is under a quarter BLU is its chord on the
                # lattice: run it as a line (CAM corner rounds, short joins), held
                # within what the sagitta leaves of the bound, if the chord's
                # lattice ends can hold that (ends far off the lattice may not)
                bound = LINE_BOUND - sag / bx
                chord = _line_ends(cur, m.start[0] / bx, m.start[1] / by, m.end[0] / bx,
                                   m.end[1] / by, bound)
            if chord is None or not chord[2]:
                # the arc on the lattice is placed against the programmed absolute
                # geometry, never against where the previous arc stopped (_Arcs);
                # G18/G19 arcs and helices in their plane's coordinates (u, v, n)
                view = _view(m, plane)
                at = _arc_cmds(q, view, blu[a0], [cur[a] for a in plane], width, 0,
                               line_head, plane, _Helix.of(m, plane, blu), m)
                for a, value in zip(plane, at):
                    cur[a] = value
                continue
        sx, sy = m.start[0] / bx, m.start[1] / by
        fix, (tx, ty), _ = chord or _line_ends(cur, sx, sy, m.end[0] / bx, m.end[1] / by,
                                               bound)
        tz = round(m.end[2] / bz)
        if fix is not None:
            # the core is too far from the line's start (an arc stopped off
            # it): a correcting step onto the line first
            cur = _line_cmd(q, m, line_head, cur, fix, True)
        if not (lo <= tx <= hi and lo <= ty <= hi and lo <= tz <= hi):
            raise GcodeError(m.lineno, f"end point outside the core's {width}-bit range "
                                       "at this BLU")
        dx, dy, dz = tx - cur[0], ty - cur[1], tz - cur[2]
        if not (dx or dy or dz):
            continue
        # encoding.encode_line, inlined for speed (the deltas fit: checked above)
        q.cmds.append(line_head | ((dx & mask) << 64) | ((dy & mask) << 96)
                      | ((dz & mask) << 128))
        q.moves_per_cmd.append(max(abs(dx), abs(dy), abs(dz)))
        q.src.append(m)
        cur = [tx, ty, tz]
    q.end = tuple(cur)
    return q
