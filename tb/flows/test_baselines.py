# SPDX-License-Identifier: Apache-2.0
"""The bench's baseline interpolators (model/halfpoint/flows/baselines.py) behave as
the classic methods do, so the comparison with the half-point method is fair."""

import math

import numpy as np
import pytest

from halfpoint.spec.arc import arc_points
from halfpoint.flows.baselines import compare, dda_circle, pbp_circle, radial_error

RADII = list(range(1, 40)) + [64, 100, 257, 1000]


@pytest.mark.parametrize("cw", [False, True])
def test_pbp_rule_and_closure(cw):
    for r in RADII:
        p = pbp_circle(r, cw)
        assert (p[-1] == p[0]).all() and len(p) - 1 == 8 * r
        d = np.diff(p, axis=0)
        assert (np.abs(d).sum(axis=1) == 1).all(), "point-by-point moves one axis at a time"
        # every move goes toward the circle: inward when on or outside it, outward inside
        f = p[:-1, 0] ** 2 + p[:-1, 1] ** 2 - r * r
        nxt = p[1:, 0] ** 2 + p[1:, 1] ** 2 - r * r
        assert (nxt[f >= 0] <= f[f >= 0]).all() and (nxt[f < 0] >= f[f < 0]).all()
        # the direction of travel never reverses (angle increases for CCW)
        ang = np.unwrap(np.arctan2(p[:, 1], p[:, 0]))
        steps = np.diff(ang) * (-1 if cw else 1)
        assert (steps >= -1e-12).all()
        assert radial_error(p, r) <= 1.0


@pytest.mark.parametrize("half", [False, True])
@pytest.mark.parametrize("cw", [False, True])
def test_dda_quadrants(cw, half):
    for r in RADII:
        p, it = dda_circle(r, cw, half_preset=half)
        assert (p[-1] == p[0]).all(), f"R={r}: DDA circle does not close"
        d = np.diff(p, axis=0)
        assert (np.abs(d).max(axis=1) == 1).all(), "unit moves (axis or diagonal)"
        assert np.abs(d[:, 0]).sum() == 4 * r and np.abs(d[:, 1]).sum() == 4 * r
        assert it >= len(d)
        ang = np.unwrap(np.arctan2(p[:, 1], p[:, 0]))
        assert ((np.diff(ang) * (-1 if cw else 1)) >= -1e-12).all()


def test_half_point_beats_both():
    rows = compare([5, 10, 50, 100, 1000], lambda r: np.array(arc_points(r, 0, r, 0, 0)))
    for row in rows:
        hp = row["half_point"]
        assert hp["err"] < 0.5
        assert hp["err"] < row["pbp"]["err"] and hp["err"] < row["dda"]["err"]
        assert hp["moves"] < row["dda"]["moves"] < row["pbp"]["moves"]
    # moves per circle: 4*sqrt(2)*R for half-point, 8R for point-by-point
    assert abs(rows[-1]["half_point"]["moves"] / 1000 - 4 * math.sqrt(2)) < 0.01
