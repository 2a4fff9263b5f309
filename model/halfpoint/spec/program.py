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
from .helix import map_arc
from .line import line_steps
from .rules import wrap


def segment_moves(dec, width: int = 32, axes: int = 3):
    """(signed steps per axis of each move, cost class per move) of a decoded motion
    command (an arc's moves mapped onto its plane's axes and its helix slots by
    ``spec.helix``), or None for an arc the validator rejects."""
    if dec[0] == "line":
        steps = line_steps(dec[1])
        return steps, [pf.CLASS_LINE] * len(steps)
    cw, xs, ys, xe, ye = dec[1]
    try:
        pts = arc_points(xs, ys, xe, ye, cw, width)
    except ArcRejected:
        return None
    plane, classes = [], []
    for (x0, y0), (x1, y1) in zip(pts, pts[1:]):
        plane.append((x1 - x0, y1 - y0))
        classes.append(pf.CLASS_DIAG if x1 != x0 and y1 != y0 else pf.CLASS_AXIS)
    return map_arc(plane, dec[3], axes), classes


def move_count(cmd: int, axes: int, width: int) -> int:
    """Moves a motion command makes (0 for anything else or a rejected arc)."""
    dec = decode_for_core(cmd, axes, width)
    moves = segment_moves(dec, width, axes) if dec[0] in ("line", "arc") else None
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
        if dec[0] == "arc":
            cw, xs, ys, xe, ye = dec[1]
            try:
                arc_points(xs, ys, xe, ye, cw, width)
            except ArcRejected as exc:
                errors.append(ARC_ERR_MAP[exc.code])
                continue
        steps, _ = segment_moves(dec, width, axes)
        for st in steps:
            pos = [wrap(p + s, width) for p, s in zip(pos, st)]
            trace.append(tuple(pos))
        if dec[0] == "arc" and dec[3].count and dec[3].count != len(steps):
            errors.append(enc.E_HELIX_COUNT)
    return trace, tuple(pos), errors


def line_cost(deltas) -> int:
    """One line iteration's cost (BLU x 2^16, nearest): Euclidean length over the
    iteration count (the longest axis)."""
    n = max(abs(d) for d in deltas)
    return max(1, round(math.sqrt(sum(d * d for d in deltas)) / n * (1 << pf.COST_FRAC)))


def profiled(cmds, axes: int, width: int, div: int, v_cruise, accel, junction=None,
             rng=None, power=None):
    """``cmds`` with a PROFILE before every motion command.  ``v_cruise`` and
    ``accel`` (field units) are numbers or callables of the segment index; junction
    speeds: ``junction`` (field units, or a callable) or, with ``rng``, random
    fractions of the cruise speed; the program starts and ends at rest (the last
    runnable segment's exit speed is 0).  Commands the core rejects get a profile
    too (an arc rejected by its validator a placeholder: it never runs);
    non-motion commands pass unchanged, and the segment before an OUTPUT command
    ends at rest (the core runs it once everything before it has moved).  ``power``:
    a callable of the segment index giving the power its PROFILE carries (set_power),
    or None for none."""
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
        moves = segment_moves(dec, width, axes)
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
    order = {r[0]: j for j, r in enumerate(runnable)}
    out = []
    for k, c in enumerate(cmds):
        dec = decode_for_core(c, axes, width)
        if k in by_index:
            p = by_index[k]
            j = order[k]
            pw = power(j) if power is not None else None
            out.append(enc.encode_profile(p.v_cruise, p.v_exit, p.accel, p.line_cost,
                                          p.d_exit, p.d_stop, int(pw is not None), pw or 0))
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


def random_helix(rng, axes: int, cont=False, rmin=2, rmax=50, count_error=0):
    """A valid arc command in a random plane of a core of ``axes`` axes (G17, G18,
    G19 when the axes exist, else any pair), its exact move count
    (``arc.arc_stop``), random helix deltas (at most the count) on its slots;
    ``count_error`` is added to the count (a command whose arc makes another number
    of moves: E_HELIX_COUNT)."""
    from .arc import arc_stop

    planes = [p for p in enc.PLANES.values() if max(p) < axes] or [(0, 1)]
    u, v = rng.choice(planes)
    dec = enc.decode(random_arc(rng, cont, rmin, rmax))
    i, j, x, y = dec["i"], dec["j"], dec["x"], dec["y"]
    n = arc_stop(-i, -j, x - i, y - j, dec["cw"])[2]
    slots = len(enc.helix_axes(u, v, axes))
    helix = [rng.randint(-n, n) if rng.random() < 0.8 else 0 for _ in range(slots)]
    return enc.encode_arc(dec["cw"], i, j, x, y, cont, plane=(u, v),
                          count=max(0, n + count_error), helix=helix)
