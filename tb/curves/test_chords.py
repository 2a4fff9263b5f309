# SPDX-License-Identifier: Apache-2.0
"""Time-division parabola chords (seed 002): chord-length behaviour, G-code."""

from __future__ import annotations

import math
import subprocess
import sys

import pytest

from halfpoint.curves.chords import chord_stats, parabola_chords
from halfpoint.cam.gcode import parse

GRID = [(a, f) for a in (0.01, 0.1, 1.0) for f in (0.02, 0.04, 0.06, 0.08)]


@pytest.mark.parametrize("a, f", GRID)
def test_points_on_the_parabola_and_chords_near_f(a, f):
    for alg in (1, 2):
        pts = parabola_chords(a, 0.0, 0.0, 10.0, f, alg)
        assert pts[0] == (0.0, 0.0) and pts[-1][0] == 10.0
        assert all(abs(y + a * x * x) < 1e-12 for x, y in pts)
        mean, worst, _, _ = chord_stats(pts, f)
        assert abs(mean - f) < 0.01 * f and abs(worst - f) < 0.05 * f


@pytest.mark.parametrize("a, f", GRID)
def test_algorithm_2_is_closer_to_f_than_algorithm_1(a, f):
    e1 = chord_stats(parabola_chords(a, 0.0, 0.0, 10.0, f, 1), f)[2]
    e2 = chord_stats(parabola_chords(a, 0.0, 0.0, 10.0, f, 2), f)[2]
    assert e2 < e1


@pytest.mark.parametrize("alg", [1, 2])
def test_error_shrinks_with_substeps(alg):
    errs = [chord_stats(parabola_chords(1.0, 0.5, -3.0, 4.0, 0.08, alg, n), 0.08)[2]
            for n in (1, 2, 4, 8)]
    assert all(b < a for a, b in zip(errs, errs[1:])), errs


def test_reverse_direction_and_b():
    pts = parabola_chords(0.2, 1.5, 8.0, -2.0, 0.05, 2, 3)
    assert pts[0][0] == 8.0 and pts[-1][0] == -2.0
    assert all(q[0] < p[0] for p, q in zip(pts, pts[1:]))


def test_cli_chords_run_through_the_core(tmp_path):
    p = subprocess.run([sys.executable, "-m", "halfpoint", "chords", "parabola", "--a", "0.5", "--b", "1",
                        "--x0", "0", "--x1", "2", "--feed", "600", "--period", "4", "--alg", "2"],
                       capture_output=True, text=True)
    assert p.returncode == 0, p.stderr
    assert p.stdout.splitlines()[1].startswith("G0 X0.000000 Y0.000000")
    moves = parse(p.stdout).moves
    f = 600 / 60000 * 4
    assert all(abs(math.dist(m.start[:2], m.end[:2]) - f) < 1e-3 for m in moves[1:-1])
    prog = tmp_path / "chords.ngc"
    prog.write_text(p.stdout)
    r = subprocess.run([sys.executable, "-m", "halfpoint", "run", str(prog)], capture_output=True, text=True)
    assert r.returncode == 0 and "max deviation" in r.stdout, r.stderr


@pytest.mark.parametrize("args, needle", [
    (["--a", "-1", "--b", "1", "--x0", "0", "--x1", "1"], "a must be positive"),
    (["--a", "1", "--b", "1", "--x0", "1", "--x1", "1"], "must differ"),
    (["--a", "1", "--b", "1", "--x0", "0", "--x1", "1", "--substeps", "0"], "substeps"),
])
def test_cli_chords_bad_arguments(args, needle):
    p = subprocess.run([sys.executable, "-m", "halfpoint", "chords", "parabola", *args,
                        "--feed", "600", "--period", "4"], capture_output=True, text=True)
    assert p.returncode == 2 and needle in p.stderr and p.stdout == ""
