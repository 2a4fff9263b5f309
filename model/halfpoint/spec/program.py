# SPDX-License-Identifier: Apache-2.0
"""Segment programs for the motion core: what the host expects of them.

``expect(cmds, axes, width)`` walks a list of encoded commands the way the
core will and returns the expected absolute position after every move, the
final position and the error codes of rejected commands, using the unit
models (arc stop points are the model's lattice prediction) and the
dispatcher's profile rules (``core.dispatch``).

``segment_moves`` gives a motion command's exact moves and their cost classes,
``profiled`` puts a PROFILE before every motion command of a program: planned by
``profile.plan_integer`` over the whole program (entry and exit at rest, junction
speeds given or random), so test programs accelerate and decelerate as the host's
do.
"""

from __future__ import annotations

import math

from . import encoding as enc
from . import profile as pf
from .arc import ArcRejected, arc_points
from .core import ARC_ERR_MAP, decode_for_core, dispatch
from .line import line_steps
from .rules import wrap


def segment_moves(dec, width: int = 32):
    """(steps per move, cost class per move) of a decoded motion command, or None
    for an arc the validator rejects."""
    if dec[0] == "line":
        steps = line_steps(dec[1])
        return steps, [pf.CLASS_LINE] * len(steps)
    cw, xs, ys, xe, ye = dec[1]
    try:
        pts = arc_points(xs, ys, xe, ye, cw, width)
    except ArcRejected:
        return None
    steps, classes = [], []
    for (x0, y0), (x1, y1) in zip(pts, pts[1:]):
        steps.append((x1 - x0, y1 - y0))
        classes.append(pf.CLASS_DIAG if x1 != x0 and y1 != y0 else pf.CLASS_AXIS)
    return steps, classes


def move_count(cmd: int, axes: int, width: int) -> int:
    """Moves a motion command makes (0 for anything else or a rejected arc)."""
    dec = decode_for_core(cmd, axes, width)
    moves = segment_moves(dec, width) if dec[0] in ("line", "arc") else None
    return len(moves[0]) if moves else 0


def expect(cmds, axes: int, width: int):
    pos = [0] * axes
    trace = []
    errors = []
    profile = None
    for c in cmds:
        dec, profile = dispatch(decode_for_core(c, axes, width), profile)
        if dec[0] == "err":
            errors.append(dec[1])
            continue
        if dec[0] in ("nop", "output"):
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


def line_cost(deltas) -> int:
    """One line iteration's cost (BLU x 2^16, nearest): Euclidean length over the
    iteration count (the longest axis)."""
    n = max(abs(d) for d in deltas)
    return max(1, round(math.sqrt(sum(d * d for d in deltas)) / n * (1 << pf.COST_FRAC)))


def profiled(cmds, axes: int, width: int, div: int, v_cruise, accel, junction=None,
             rng=None):
    """``cmds`` with a PROFILE before every motion command.  ``v_cruise`` and
    ``accel`` (field units) are numbers or callables of the segment index; junction
    speeds: ``junction`` (field units, or a callable) or, with ``rng``, random
    fractions of the cruise speed; the program starts and ends at rest (the last
    runnable segment's exit speed is 0).  Commands the core rejects get a profile
    too (an arc rejected by its validator a placeholder: it never runs);
    non-motion commands pass unchanged, and the segment before an OUTPUT command
    ends at rest (the core runs it once everything before it has moved)."""
    def value(x, k):
        return x(k) if callable(x) else x

    runnable = []            # (index in cmds, cost length, line cost, moves)
    rest_after = set()       # runnable indices followed by an OUTPUT
    for k, c in enumerate(cmds):
        dec = decode_for_core(c, axes, width)
        if dec[0] == "output" and runnable:
            rest_after.add(len(runnable) - 1)
        if dec[0] not in ("line", "arc"):
            continue
        moves = segment_moves(dec, width)
        if moves is None:
            continue
        lc = line_cost(dec[1]) if dec[0] == "line" else 0
        prm = pf.ProfileParams(1, 0, 1, lc)
        length = sum(pf.move_cost(cls, prm) for cls in moves[1])
        runnable.append((k, length, lc))
    n = len(runnable)
    vc = [value(v_cruise, j) for j in range(n)]
    acc = [value(accel, j) for j in range(n)]
    exits = []
    for j in range(n):
        if j == n - 1 or j in rest_after:
            exits.append(0)
        elif junction is not None:
            exits.append(min(value(junction, j), vc[j], vc[j + 1]))
        elif rng is not None:
            exits.append(int(min(vc[j], vc[j + 1]) * rng.choice((0.0, 0.3, 0.7, 1.0))))
        else:
            exits.append(0)
    plans = pf.plan_integer([r[1] for r in runnable], vc, exits, acc, div,
                            [r[2] for r in runnable]) if n else []
    by_index = {r[0]: p for r, p in zip(runnable, plans)}
    out = []
    for k, c in enumerate(cmds):
        dec = decode_for_core(c, axes, width)
        if k in by_index:
            p = by_index[k]
            out.append(enc.encode_profile(p.v_cruise, p.v_exit, p.accel, p.line_cost,
                                          p.d_exit, p.d_stop))
        elif dec[0] == "arc":       # rejected by the validator: any arc profile
            out.append(enc.encode_profile(1 << 28, 0, 1 << 30))
        out.append(c)
    return out


def random_arc(rng, cont=False, rmin=2, rmax=50):
    """A valid arc command (I, J, X, Y relative to the current position)."""
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
            return enc.encode_arc(rng.randint(0, 1), i, j, xe + i, ye + j, cont)


def random_line(rng, axes, cont=False, scale=40):
    d = [rng.randint(-scale, scale) for _ in range(axes)]
    return enc.encode_line(d, cont)
