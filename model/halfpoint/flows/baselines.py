# SPDX-License-Identifier: Apache-2.0
"""Classic circle interpolators, as baselines for ``make bench``.

* Point-by-point comparison (PBP, "逐点比较法"): each step tests the sign of
  F = x^2 + y^2 - R^2 and moves one axis, inward when F >= 0 and outward
  otherwise; axis moves only, 8R moves per full circle, radial error
  below 1 BLU.
* DDA (digital differential analyser) circle: two N-bit integrators, one per
  axis, with integrands |y| (for x) and |x| (for y), 2^N > R; an overflow
  steps its axis, and a step updates the other axis' integrand.  The
  remainders start at 0 (classic) or at half scale (the usual rounding
  improvement).  Both axes may step in one iteration (a diagonal move).

Both trace a full circle from (R, 0); each returns the lattice points
visited (start included) so that the bench measures them exactly as it
measures the half-point method.
"""

from __future__ import annotations

import numpy as np


def pbp_circle(r: int, cw: bool = False) -> np.ndarray:
    """Full circle from (r, 0) by point-by-point comparison; (n+1, 2) points."""
    if r < 1:
        raise ValueError("radius must be at least 1")
    x, y = r, 0
    pts = [(x, y)]
    # counter-clockwise in a mirrored frame for cw (y -> -y)
    s = -1 if cw else 1
    for _ in range(8 * r):
        yy = s * y
        f = x * x + yy * yy - r * r
        # quadrant by the direction of motion (CCW): Q1 x>0,y>=0; Q2 x<=0,y>0;
        # Q3 x<0,y<=0; Q4 x>=0,y<0; (inward, outward) moves of Q1 rotated by 90 deg
        if x > 0 and yy >= 0:
            inward, outward = (-1, 0), (0, 1)
        elif x <= 0 and yy > 0:
            inward, outward = (0, -1), (-1, 0)
        elif x < 0 and yy <= 0:
            inward, outward = (1, 0), (0, -1)
        else:
            inward, outward = (0, 1), (1, 0)
        dx, dy = inward if f >= 0 else outward
        x += dx
        yy += dy
        y = s * yy
        pts.append((x, y))
    return np.array(pts, dtype=np.int64)


def dda_circle(r: int, cw: bool = False, half_preset: bool = False) -> tuple[np.ndarray, int]:
    """Full circle from (r, 0) by DDA, one quadrant at a time as the classic
    method does (each quadrant set up afresh: remainders preset, each axis
    counting down its r steps and stopping there); returns (points after each
    move, iterations)."""
    if r < 1:
        raise ValueError("radius must be at least 1")
    n = int(r).bit_length()                  # 2^n > r
    full = 1 << n
    s = -1 if cw else 1
    x, yy = r, 0                             # counter-clockwise in the mirrored frame
    pts = [(x, s * yy)]
    it = 0
    for _ in range(4):
        jx = jy = (full >> 1) if half_preset else 0
        left_x = left_y = r
        # signs of the motion in this quadrant: dx/dt = -y, dy/dt = x
        dir_x = -1 if (yy > 0 or (yy == 0 and x < 0)) else 1
        dir_y = 1 if (x > 0 or (x == 0 and yy > 0)) else -1
        if yy == 0:                          # on the x axis: x moves toward 0
            dir_x = -1 if x > 0 else 1
        if x == 0:                           # on the y axis: y moves toward 0
            dir_y = -1 if yy > 0 else 1
        while left_x or left_y:
            it += 1
            sx = sy = 0
            if left_x:
                jx += abs(yy)
                if jx >= full:
                    jx -= full
                    sx = dir_x
            if left_y:
                jy += abs(x)
                if jy >= full:
                    jy -= full
                    sy = dir_y
            if sx or sy:
                x += sx
                yy += sy
                left_x -= abs(sx)
                left_y -= abs(sy)
                pts.append((x, s * yy))
    return np.array(pts, dtype=np.int64), it


def radial_error(pts: np.ndarray, r: int) -> float:
    """Largest |sqrt(x^2 + y^2) - r| over the points."""
    return float(np.max(np.abs(np.hypot(pts[:, 0], pts[:, 1]) - r)))


def compare(radii, half_point_points) -> list[dict]:
    """Max radial error and moves per full circle of the three methods, per
    radius; `half_point_points(r)` gives the half-point method's lattice points
    of a full circle (start included)."""
    rows = []
    for r in radii:
        hp = half_point_points(r)
        pbp = pbp_circle(r)
        dda0, it0 = dda_circle(r)
        dda1, it1 = dda_circle(r, half_preset=True)
        rows.append({
            "r": r,
            "half_point": {"err": radial_error(hp, r), "moves": len(hp) - 1,
                           "closes": bool((hp[-1] == hp[0]).all())},
            "pbp": {"err": radial_error(pbp, r), "moves": len(pbp) - 1,
                    "closes": bool((pbp[-1] == pbp[0]).all())},
            "dda": {"err": radial_error(dda0, r), "moves": len(dda0) - 1, "iterations": it0,
                    "closes": bool((dda0[-1] == dda0[0]).all())},
            "dda_half": {"err": radial_error(dda1, r), "moves": len(dda1) - 1, "iterations": it1,
                         "closes": bool((dda1[-1] == dda1[0]).all())},
        })
    return rows
