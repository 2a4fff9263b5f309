# SPDX-License-Identifier: Apache-2.0
"""Model-only tests of the line interpolator (no simulator)."""

from __future__ import annotations

import random

import pytest

from halfpoint.spec.line import (
    ERR_EMPTY, LineInputs, LineRejected, LineUnitModel, line_latency, line_steps,
)


def test_seed_001_worked_example():
    """O(0,0,0) -> E(6,5,3): six iterations, x every time, y five, z three.

    Per iteration (F += |d|; step when 2F > Max = 6, then F -= 6):
      it  Fy before->after  Fz before->after  steps (x, y, z)
      1   0+5=5  -> -1      0+3=3 -> 3        (1, 1, 0)
      2  -1+5=4  -> -2      3+3=6 -> 0        (1, 1, 1)
      3  -2+5=3  ->  3      0+3=3 -> 3        (1, 0, 0)   2*3 = 6 is not > 6
      4   3+5=8  ->  2      3+3=6 -> 0        (1, 1, 1)
      5   2+5=7  ->  1      0+3=3 -> 3        (1, 1, 0)
      6   1+5=6  ->  0      3+3=6 -> 0        (1, 1, 1)
    """
    assert line_steps((6, 5, 3)) == [
        (1, 1, 0), (1, 1, 1), (1, 0, 0), (1, 1, 1), (1, 1, 0), (1, 1, 1),
    ]
    assert line_steps((-6, 5, -3)) == [
        (-1, 1, 0), (-1, 1, -1), (-1, 0, 0), (-1, 1, -1), (-1, 1, 0), (-1, 1, -1),
    ]


def test_error_within_half_blu_and_exact_end():
    rng = random.Random(3)
    for _ in range(400):
        na = rng.randint(1, 6)
        d = [rng.randint(-300, 300) for _ in range(na)]
        if not any(d):
            continue
        steps = line_steps(d)
        n = max(abs(v) for v in d)
        assert len(steps) == n
        pos = [0] * na
        for k, s in enumerate(steps, start=1):
            pos = [p + q for p, q in zip(pos, s)]
            t = k / n        # the base axis has advanced k of n
            for i in range(na):
                assert abs(pos[i] - d[i] * t) <= 0.5 + 1e-12, (d, k, i)
        assert pos == d


def test_base_axis_steps_every_iteration():
    for d in [(7, 3), (3, -7), (5, 5, 5), (-9, 0, 4, 2)]:
        m = max(range(len(d)), key=lambda i: abs(d[i]))
        assert all(s[m] != 0 for s in line_steps(d))


def test_empty_line_rejected():
    with pytest.raises(LineRejected) as exc:
        line_steps((0, 0, 0))
    assert exc.value.code == ERR_EMPTY


def test_cycle_model_latency():
    m = LineUnitModel(3, 16)
    m.clock(LineInputs(rst=1))
    m.clock(LineInputs(s_valid=1, s_delta=(4, 1, 0)))
    first = None
    for cyc in range(1, 50):
        if m.outputs().move:
            first = cyc
            break
        m.clock(LineInputs(s_delta=(0, 0, 0)))
    assert first == line_latency(3) + 2
