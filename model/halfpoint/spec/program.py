# SPDX-License-Identifier: Apache-2.0
"""Segment programs for the motion core: what the host expects of them.

``expect(cmds, axes, width)`` walks a list of encoded commands the way the
core will and returns the expected absolute position after every move, the
final position and the error codes of rejected commands, using the unit
models (arc stop points are the model's lattice prediction).
"""

from __future__ import annotations

from . import encoding as enc
from .arc import ArcRejected, arc_points
from .core import ARC_ERR_MAP, decode_for_core
from .rules import wrap
from .line import line_steps


def expect(cmds, axes: int, width: int):
    pos = [0] * axes
    trace = []
    errors = []
    for c in cmds:
        dec = decode_for_core(c, axes, width)
        if dec[0] == "err":
            errors.append(dec[1])
            continue
        if dec[0] == "nop":
            continue
        if dec[0] == "line":
            for st in line_steps(dec[1]):
                pos = [wrap(p + s, width) for p, s in zip(pos, st)]
                trace.append(tuple(pos))
            continue
        cw, xs, ys, xe, ye = dec[1]
        try:
            pts = arc_points(xs, ys, xe, ye, cw, width)
        except ArcRejected as exc:
            errors.append(ARC_ERR_MAP[exc.code])
            continue
        for (x0, y0), (x1, y1) in zip(pts, pts[1:]):
            pos[0] = wrap(pos[0] + x1 - x0, width)
            pos[1] = wrap(pos[1] + y1 - y0, width)
            trace.append(tuple(pos))
    return trace, tuple(pos), errors


def random_arc(rng, rate=enc.RATE_ONE, cont=False, rmin=2, rmax=50):
    """A valid arc command (I, J, X, Y relative to the current position)."""
    import math

    from .arc import lattice_point_near, validate

    while True:
        r = rng.uniform(rmin, rmax)
        th = rng.uniform(0, 2 * math.pi)
        i, j = round(r * math.cos(th)), round(r * math.sin(th))
        if i == 0 and j == 0:
            continue
        xs, ys = -i, -j
        r2 = xs * xs + ys * ys
        te = math.atan2(ys, xs) + rng.uniform(-2 * math.pi, 2 * math.pi)
        xe, ye = lattice_point_near(r2, te)
        if validate(xs, ys, xe, ye, 32) == 0:
            return enc.encode_arc(rng.randint(0, 1), i, j, xe + i, ye + j, rate, cont)


def random_line(rng, axes, rate=enc.RATE_ONE, cont=False, scale=40):
    d = [rng.randint(-scale, scale) for _ in range(axes)]
    return enc.encode_line(d, rate, cont)
