# SPDX-License-Identifier: Apache-2.0
"""Random and systematic arc commands for the arc interpolator's tests."""

from __future__ import annotations

import math
import random

from halfpoint.spec.arc import ArcRun, before_in_order, frame, limits, step, validate
from halfpoint.spec.arc import lattice_point_near as nearest_on_circle


def start_point(rng: random.Random, r: float, theta: float, width: int) -> tuple[int, int]:
    """A start point near radius r and angle theta that the core accepts."""
    lim = limits(width)[1]
    while True:
        x, y = round(r * math.cos(theta)), round(r * math.sin(theta))
        if (x or y) and x * x + y * y <= lim:
            return x, y
        r *= 0.999


def quadrant_angle(rng: random.Random, q: int) -> float:
    """An angle strictly inside quadrant q (I..IV = 0..3)."""
    return (q + rng.uniform(0.02, 0.98)) * math.pi / 2


def arc_for_quadrants(rng, width, qs, qe, cw, rmin, rmax, jitter=True):
    """Arc command with start in quadrant qs and end in quadrant qe."""
    while True:
        r = rng.uniform(rmin, rmax)
        xs, ys = start_point(rng, r, quadrant_angle(rng, qs), width)
        r2 = xs * xs + ys * ys
        xe, ye = nearest_on_circle(r2, quadrant_angle(rng, qe))
        if jitter and rng.random() < 0.3:
            # an end point off the lattice path but inside the tolerance
            xe += rng.choice((-1, 0, 1))
            ye += rng.choice((-1, 0, 1))
        if (xe or ye) and validate(xs, ys, xe, ye, width) == 0:
            if frame(xs, ys, cw)[0] == qs and frame(xe, ye, cw)[0] == qe:
                return (cw, xs, ys, xe, ye)


def short_arc(rng, width, r, moves):
    """Arc of about ``moves`` lattice moves on a circle of radius about r."""
    cw = rng.randint(0, 1)
    th = rng.uniform(0, 2 * math.pi)
    xs, ys = start_point(rng, r, th, width)
    r2 = xs * xs + ys * ys
    span = moves / (math.sqrt(r2) * 4 * math.sqrt(2) / (2 * math.pi))
    te = th - span if cw else th + span
    xe, ye = nearest_on_circle(r2, te)
    return (cw, xs, ys, xe, ye)


def full_circle(r: int, theta: float, cw: int):
    if theta == 0.0:
        return (cw, r, 0, r, 0)
    x, y = round(r * math.cos(theta)), round(r * math.sin(theta))
    return (cw, x, y, x, y)


# The end test orders the points of E's quadrant by (v, -u) when E is in the
# quadrant's first octant (ve <= ue) and by (-u, v) otherwise.  The two orders
# agree on the lattice path (every move lowers u or raises v), so they differ
# only for an end off the path; the compare ve <= ue then decides where the
# arc stops.  A flip names a bit of ve or ue that, stuck at 0 or 1, would turn
# that compare: "ve_cleared" is an end with ve > ue whose compare turns when
# the bit is cleared from ve, and so on.
OCTANT_FLIPS = ("ve_cleared", "ve_set", "ue_cleared", "ue_set")


def _flip_end(rng: random.Random, bit: int, flip: str, top: int) -> tuple[int, int] | None:
    """(ue, ve), each 1..top, whose compare ve <= ue the flip turns."""
    b = 1 << bit
    # half of the tries with no higher bits: a radius of about 2^bit, where
    # an end up to 2^bit from the diagonal lies well inside the octant
    high = 0
    if rng.random() < 0.5:
        high = rng.randrange(max(1, (top + 1) >> (bit + 1))) << (bit + 1)
    low = rng.randrange(b)
    if flip == "ve_cleared":            # ve > ue >= ve - b
        ve = high | b | low
        ue = ve - 1 - rng.randrange(b)
    elif flip == "ve_set":              # ve <= ue < ve + b
        ve = high | low
        ue = ve + rng.randrange(b)
    elif flip == "ue_cleared":          # ue >= ve > ue - b
        ue = high | b | low
        ve = ue - rng.randrange(b)
    else:                               # ue < ve <= ue + b
        ue = high | low
        ve = ue + 1 + rng.randrange(b)
    if 1 <= ue <= top and 1 <= ve <= top:
        return ue, ve
    return None


def flips(ue: int, ve: int, bit: int, flip: str) -> bool:
    """Whether the flip of this bit turns the compare ve <= ue."""
    b = 1 << bit
    if flip == "ve_cleared":
        return bool(ve & b) and ve > ue >= ve - b
    if flip == "ve_set":
        return not ve & b and ve <= ue < (ve | b)
    if flip == "ue_cleared":
        return bool(ue & b) and ue >= ve > ue - b
    return not ue & b and ue < ve <= (ue | b)


class _OrderedRun(ArcRun):
    """The model's arc run with its end test in a forced order (the first
    octant's, or the second's) instead of the order E's octant picks."""

    __slots__ = ("first_octant",)

    def __init__(self, cmd, first_octant: bool, width: int):
        self.first_octant = first_octant
        cw, xs, ys, xe, ye = cmd
        super().__init__(xs, ys, xe, ye, cw, width, check=False)

    def before_end(self, u: int, v: int) -> bool:
        return before_in_order(u, v, self.ue, self.ve, self.first_octant)


def moves_with_order(cmd, first_octant: bool, limit: int, width: int = 32) -> int | None:
    """Moves of an accepted arc whose end test uses the given order, or None when
    it does not stop in ``limit`` moves."""
    run = _OrderedRun(cmd, first_octant, width)
    while not run.done and run.moves < limit:
        run.advance()
    return run.moves if run.done else None


def octant_order_end(rng: random.Random, width: int, bit: int, flip: str,
                     tries: int = 300) -> tuple[int, int, int, int, int] | None:
    """A short arc (about 15 moves) to an end off the path, next to the
    octant boundary as ``flip`` and ``bit`` say, where the other order would
    stop at another move; None if the tries find none (the small bits leave
    few such ends)."""
    top, r2_max = limits(width)
    for _ in range(tries):
        target = _flip_end(rng, bit, flip, top)
        if target is None or target[0] ** 2 + target[1] ** 2 > r2_max:
            continue
        r2 = target[0] ** 2 + target[1] ** 2
        theta = math.atan2(target[1], target[0]) - rng.uniform(8, 16) / math.sqrt(r2)
        xs, ys = nearest_on_circle(r2, theta)
        q, u, v = frame(xs, ys, 0)
        if q != 0 or xs * xs + ys * ys > r2_max:
            continue
        # the ends next to the path from this start, in its quadrant
        ends = set()
        f = 0
        for _ in range(40):
            for du in (-1, 0, 1):
                for dv in (-1, 0, 1):
                    if u + du >= 1 and v + dv >= 1 and flips(u + du, v + dv, bit, flip):
                        ends.add((u + du, v + dv))
            q, u, v, f = step(q, u, v, f, 0)[4:8]
            if q != 0:
                break
        found = []
        for ue, ve in sorted(ends):
            cmd = (0, xs, ys, ue, ve)
            if validate(xs, ys, ue, ve, width):
                continue
            first = ve <= ue
            moves = moves_with_order(cmd, first, 64, width)
            if moves is not None and moves_with_order(cmd, not first, 64, width) != moves:
                found.append(cmd)
        if not found:
            continue
        _, xs, ys, ue, ve = rng.choice(found)
        # the same arc in a random quadrant and direction: a quarter turn
        # (x, y) -> (-y, x) and the mirror (x, y) -> (x, -y) with the other
        # direction keep the frame (q, u, v) of every point
        turn = rng.randrange(4)
        cw = rng.randrange(2)
        points = [(xs, ys), (ue, ve)]
        for _ in range(turn):
            points = [(-y, x) for x, y in points]
        if cw:
            points = [(x, -y) for x, y in points]
        (xs, ys), (xe, ye) = points
        return (cw, xs, ys, xe, ye)
    return None


def octant_order_ends(rng: random.Random, width: int) -> list[tuple[int, int, int, int, int]]:
    """One octant_order_end for each bit of a magnitude and each flip, where
    the tries find one."""
    cmds = []
    for bit in range(width - 1):
        for flip in OCTANT_FLIPS:
            cmd = octant_order_end(rng, width, bit, flip, 1000 if bit < 5 else 300)
            if cmd is not None:
                cmds.append(cmd)
    return cmds


def range_edge_points(width: int, span: int = 4,
                      tries: int = 100_000) -> list[tuple[int, int, int]]:
    """Lattice points (x, y, R^2 - limit) whose R^2 = x^2 + y^2 is within ``span`` of
    the largest accepted R^2, (M-1)(M-2), on either side (one point per R^2 that is
    a sum of two squares, found among the ``tries`` largest x): the range check's
    compare sees its low bits decide only there (found by mutation testing: bit 1
    of R^2 inverted in the compare rejects R^2 = limit - 1, which the other tests
    never offered; at W = 16 that is 30425^2 + 12164^2)."""
    limit = limits(width)[1]
    points = []
    for r2 in range(limit - span, limit + span + 1):
        top = math.isqrt(r2)
        for x in range(top, max(top - tries, 0), -1):
            y = math.isqrt(r2 - x * x)
            if x * x + y * y == r2:
                points.append((x, y, r2 - limit))
                break
    return points
