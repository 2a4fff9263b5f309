# SPDX-License-Identifier: Apache-2.0
"""Time-division (sampled-data) parabola interpolation, seed 002.

Every interpolation period T the controller advances by one chord of the
curve whose ideal length is f = F * T (F the feed); the motion core's line
unit then runs each chord within its period.  Parabola y = -a x^2 + b x.

* Algorithm 1 (tangent): K_i = -2 a x_i + b, dx_i = f / sqrt(1 + K_i^2).
* Algorithm 2 (corrected secant): the next chord's slope is estimated as the
  previous chord's slope minus 2 a dx_{i-1}; then dx as above.  The first
  chord has no predecessor: its slope is the secant slope over an algorithm-1
  step, -a (2 x_0 + dx) + b.
* n substeps: n steps of f / n with either algorithm; the period's chord is
  from the period's first point to its last.

The x direction follows x0 -> x1; the last chord ends exactly at x1.
"""

from __future__ import annotations

import math
from dataclasses import dataclass


@dataclass
class Parabola:
    a: float
    b: float

    def y(self, x: float) -> float:
        return -self.a * x * x + self.b * x

    def slope(self, x: float) -> float:
        return -2 * self.a * x + self.b


def _steps(p: Parabola, x0: float, x1: float, step: float, alg: int):
    """x positions of successive steps of (ideal) length ``step`` from x0 to x1."""
    sgn = 1.0 if x1 >= x0 else -1.0
    xs = [x0]
    x = x0
    prev_dx = None
    prev_slope = None
    while (x1 - x) * sgn > 1e-15:
        if alg == 1 or prev_dx is None:
            k = p.slope(x)
            dx = step / math.sqrt(1 + k * k)
            if alg == 2:
                # first chord of algorithm 2: secant slope over this step
                k = -p.a * (2 * x + sgn * dx) + p.b
                dx = step / math.sqrt(1 + k * k)
        else:
            k = prev_slope - 2 * p.a * prev_dx * sgn
            dx = step / math.sqrt(1 + k * k)
        nx = x + sgn * dx
        if (x1 - nx) * sgn < 0:
            nx = x1
        # slope of the chord just made, for algorithm 2's next estimate
        prev_slope = (p.y(nx) - p.y(x)) / (nx - x) if nx != x else p.slope(x)
        prev_dx = abs(nx - x)
        x = nx
        xs.append(x)
    return xs


def parabola_chords(a: float, b: float, x0: float, x1: float, f: float,
                    alg: int = 1, substeps: int = 1) -> list[tuple[float, float]]:
    """Chord end points (x, y), starting with the start point."""
    if a <= 0:
        raise ValueError("a must be positive (y = -a x^2 + b x)")
    if b < 0:
        raise ValueError("b must not be negative")
    if f <= 0:
        raise ValueError("the chord length F*T must be positive")
    if alg not in (1, 2):
        raise ValueError("algorithm must be 1 or 2")
    if substeps < 1:
        raise ValueError("substeps must be at least 1")
    if x0 == x1:
        raise ValueError("x0 and x1 must differ")
    p = Parabola(a, b)
    xs = _steps(p, x0, x1, f / substeps, alg)
    pts = xs[::substeps]
    if pts[-1] != xs[-1]:
        pts.append(xs[-1])
    return [(x, p.y(x)) for x in pts]


def chord_stats(points, f: float):
    """(mean, worst) chord length over the full periods (the last, partial
    chord is left out), and the mean and worst |chord - f|."""
    lens = [math.dist(p, q) for p, q in zip(points, points[1:])][:-1]
    if not lens:
        return float("nan"), float("nan"), float("nan"), float("nan")
    errs = [abs(c - f) for c in lens]
    worst = max(lens, key=lambda c: abs(c - f))
    return sum(lens) / len(lens), worst, sum(errs) / len(errs), max(errs)


def chords_gcode(points, feed: float) -> str:
    """G90 mm G-code: G0 to the first point, then one G1 per chord."""
    out = ["G21 G90 G91.1 G17", f"G0 X{points[0][0]:.6f} Y{points[0][1]:.6f}"]
    out.append(f"G1 X{points[1][0]:.6f} Y{points[1][1]:.6f} F{feed:g}")
    out += [f"X{x:.6f} Y{y:.6f}" for x, y in points[2:]]
    out.append("M2")
    return "\n".join(out) + "\n"
