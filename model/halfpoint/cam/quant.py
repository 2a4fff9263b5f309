# SPDX-License-Identifier: Apache-2.0
"""Quantisation: moves in mm -> motion-core commands on the BLU lattice.

* One BLU per axis (default 0.001 mm); X and Y must share it (arcs are
  circles on the lattice).
* Every target point is rounded to the lattice and every command is relative
  to where the core really is, so segments chain exactly and no rounding error
  accumulates.
* An arc whose sagitta is under a quarter BLU is run as its chord (a line):
  on the lattice the two are the same within that quarter BLU.
* Arcs: the centre is rounded to the lattice; the radius is the distance from
  the current lattice point (the core's definition); the end is the lattice
  point at the programmed end's angle that the core accepts, and the current
  point afterwards is where the core's arc unit will actually stop (the
  model's prediction, within 1 BLU per axis of that end).
* Every point and centre must fit the core's signed coordinate width; the
  error names the line.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

from ..spec import encoding as enc
from ..spec.arc import arc_stop, lattice_point_near, validate
from ..spec.rules import field_range, fits
from .gcode import GcodeError, Move

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


def _minor(m: Move) -> bool:
    """Is the arc's sweep at most half a turn?"""
    sx, sy = m.start[0] - m.center[0], m.start[1] - m.center[1]
    ex, ey = m.end[0] - m.center[0], m.end[1] - m.center[1]
    cross = sx * ey - sy * ex
    return (cross <= 0) if m.cw else (cross >= 0)


def _place_arc(m: Move, b: float, cur):
    """Lattice centre and centre-relative start of an arc: of the lattice
    points around the programmed centre and start, the pair whose circle
    stays nearest the programmed arc over the arc's own angles (the radial
    error at angle phi is rho - R + |dc| cos(phi - psi) for a centre offset
    dc at angle psi); the current position wins ties, so a chain that is on
    track stays there."""
    pcx, pcy = m.center[0] / b, m.center[1] / b
    psx, psy = m.start[0] / b, m.start[1] / b
    radius = math.hypot(psx - pcx, psy - pcy)
    a0 = math.atan2(psy - pcy, psx - pcx)
    a1 = math.atan2(m.end[1] / b - pcy, m.end[0] / b - pcx)
    if m.start[:2] == m.end[:2]:
        sweep = -2 * math.pi if m.cw else 2 * math.pi
    else:
        sweep = -((a0 - a1) % (2 * math.pi)) if m.cw else (a1 - a0) % (2 * math.pi)
    angles = [a0 + sweep * k / 8 for k in range(9)]
    cosines = [(math.cos(t), math.sin(t)) for t in angles]
    best = None
    for cx in {math.floor(pcx), math.ceil(pcx)}:
        for cy in {math.floor(pcy), math.ceil(pcy)}:
            dcx, dcy = cx - pcx, cy - pcy
            for sx in {math.floor(psx), math.ceil(psx), cur[0]}:
                for sy in {math.floor(psy), math.ceil(psy), cur[1]}:
                    if abs(sx - psx) > 1 or abs(sy - psy) > 1 or (sx == cx and sy == cy):
                        continue
                    dr = math.hypot(sx - cx, sy - cy) - radius
                    err = max(abs(dr + dcx * u + dcy * v) for u, v in cosines)
                    key = (round(err, 9), (sx, sy) != (cur[0], cur[1]),
                           math.hypot(sx - psx, sy - psy))
                    if best is None or key < best[0]:
                        best = (key, (cx, cy), (sx - cx, sy - cy))
    if best is None:
        raise GcodeError(m.lineno, "arc radius is below one BLU")
    return best[1], best[2]


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


def quantise(moves: list[Move], blu=(DEFAULT_BLU,) * 3, width: int = 32,
             rate: float = 2.0) -> Quantised:
    if abs(blu[0] - blu[1]) > 1e-15:
        raise ValueError("X and Y must have the same BLU (arcs are circles on the lattice)")
    if min(blu) <= 0:
        raise ValueError("a BLU must be positive")
    rate_q = max(1, round(rate * enc.RATE_ONE))
    q = Quantised()
    cur = [0, 0, 0]

    def lat(p, k):
        return round(p / blu[k])

    bx, by, bz = blu
    lo, hi = field_range(width, LATTICE_MARGIN)
    mask = 0xFFFFFFFF
    line_head = enc.OP_LINE | (rate_q << 32)
    for m in moves:
        if m.kind != "arc":
            ex, ey, ez = m.end
            tx, ty, tz = round(ex / bx), round(ey / by), round(ez / bz)
            if not (lo <= tx <= hi and lo <= ty <= hi and lo <= tz <= hi):
                raise GcodeError(m.lineno, f"end point outside the core's {width}-bit range at this BLU")
            dx, dy, dz = tx - cur[0], ty - cur[1], tz - cur[2]
            if not (dx or dy or dz):
                continue
            # encoding.encode_line, inlined for speed (the deltas fit: checked above)
            q.cmds.append(line_head | ((dx & mask) << 64) | ((dy & mask) << 96) | ((dz & mask) << 128))
            q.moves_per_cmd.append(max(abs(dx), abs(dy), abs(dz)))
            q.src.append(m)
            cur = [tx, ty, tz]
            continue
        if m.plane != 17:
            raise GcodeError(m.lineno, "the core interpolates arcs in the XY plane (G17) only")
        if m.start[:2] != m.end[:2]:
            # an arc whose sagitta is under a quarter BLU is its chord on the
            # lattice: run it as a line (CAM corner rounds, short joins)
            r_mm = math.hypot(m.start[0] - m.center[0], m.start[1] - m.center[1])
            chord = math.hypot(m.end[0] - m.start[0], m.end[1] - m.start[1])
            half = min(chord / (2 * r_mm), 1.0) if r_mm > 0 else 1.0
            sag = r_mm * (1 - math.sqrt(1 - half * half))
            short = math.asin(half) * 2 <= math.pi      # the short way round
            if short and sag < 0.25 * bx and _minor(m):
                tx, ty = round(m.end[0] / bx), round(m.end[1] / by)
                dx, dy = tx - cur[0], ty - cur[1]
                if dx or dy:
                    q.cmds.append(line_head | ((dx & mask) << 64) | ((dy & mask) << 96))
                    q.moves_per_cmd.append(max(abs(dx), abs(dy)))
                    q.src.append(m)
                    cur = [tx, ty, cur[2]]
                continue
        # the arc on the lattice is chosen against the programmed absolute
        # geometry, never against where the previous arc stopped: the centre
        # and start among the lattice points next to the programmed ones that
        # give the circle nearest the programmed circle
        c, (xs, ys) = _place_arc(m, bx, cur)
        if not all(fits(v, width, LATTICE_MARGIN) for v in c):
            raise GcodeError(m.lineno, f"arc centre outside the core's {width}-bit range at this BLU")
        start = (c[0] + xs, c[1] + ys)
        if (start[0], start[1]) != (cur[0], cur[1]):
            # a short correcting line onto the chosen start (a few BLU at most)
            dx, dy = start[0] - cur[0], start[1] - cur[1]
            q.cmds.append(line_head | ((dx & mask) << 64) | ((dy & mask) << 96))
            q.moves_per_cmd.append(max(abs(dx), abs(dy)))
            q.src.append(m)
            q.corrections += 1
            cur = [start[0], start[1], cur[2]]
        full = m.start[:2] == m.end[:2]          # a programmed full circle
        r2 = xs * xs + ys * ys
        if full:
            xe, ye = xs, ys
        else:
            ex, ey = m.end[0] / bx - c[0], m.end[1] / by - c[1]
            xe, ye = _end_point(r2, ex, ey)
            if validate(xs, ys, xe, ye, width):
                ang = math.atan2(m.end[1] - m.center[1], m.end[0] - m.center[0])
                xe, ye = lattice_point_near(r2, ang)
            if (xe, ye) == (xs, ys):
                continue        # an arc shorter than the lattice: no motion
        code = validate(xs, ys, xe, ye, width)
        if code:
            raise GcodeError(m.lineno, "arc cannot be put on the lattice (radius too large for the width?)")
        sx, sy, n = arc_stop(xs, ys, xe, ye, int(m.cw))
        q.cmds.append(enc.encode_arc(int(m.cw), c[0] - cur[0], c[1] - cur[1],
                                     c[0] + xe - cur[0], c[1] + ye - cur[1], rate_q))
        q.moves_per_cmd.append(n)
        q.src.append(m)
        cur = [c[0] + sx, c[1] + sy, cur[2]]
        if not all(fits(v, width, LATTICE_MARGIN) for v in cur):
            raise GcodeError(m.lineno, f"arc leaves the core's {width}-bit range at this BLU")
    q.end = tuple(cur)
    return q
