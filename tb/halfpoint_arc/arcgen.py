# SPDX-License-Identifier: Apache-2.0
"""Random and systematic arc commands for the arc interpolator's tests."""

from __future__ import annotations

import math
import random

from halfpoint.spec.arc import frame, limits, validate
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
