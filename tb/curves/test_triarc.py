# SPDX-License-Identifier: Apache-2.0
"""Tri-arc fitting (seed 003): every fit within tolerance and tangent-continuous,
checked by dense sampling; the seed's ellipse example; end to end through the core."""

from __future__ import annotations

import math
import subprocess
from pathlib import Path
import sys

import pytest

from halfpoint.curves import triarc


@pytest.mark.parametrize(
    "name, curve, tol",
    [
        ("ellipse Q2 50x30", triarc.ellipse(50, 30, math.pi / 2, math.pi), 0.01),
        ("ellipse Q1 40x10", triarc.ellipse(40, 10, 0, math.pi / 2), 0.005),
        ("full ellipse 20x12", triarc.ellipse(20, 12, 0, 2 * math.pi), 0.02),
        ("parabola", triarc.parabola(0.05, -0.3, 1.0, -15, 20), 0.01),
        ("hyperbola", triarc.hyperbola(10, 6, -1.2, 1.0), 0.02),
        ("explicit cubic (inflection)", triarc.explicit(lambda x: 0.002 * x ** 3, lambda x: 0.006 * x ** 2,
                                                        lambda x: 0.012 * x, -15, 15), 0.01),
    ],
)
def test_fit_within_tolerance_and_tangent(name, curve, tol):
    arcs, groups = triarc.fit(curve, tol)
    dev, tangent = triarc.verify(curve, arcs, tol)
    assert dev <= tol * (1 + 1e-6), f"{name}: deviation {dev}"
    assert tangent < 1e-9, f"{name}: tangent jump {tangent}"
    assert arcs[0].start == pytest.approx(curve.p(curve.t0), abs=1e-9)
    assert arcs[-1].end == pytest.approx(curve.p(curve.t1), abs=1e-9)
    assert all(a.end == b.start for a, b in zip(arcs, arcs[1:]))
    assert all(hi - lo in (2, 3) for lo, hi in groups)


def test_split_points_of_a_full_ellipse_are_its_vertices():
    cuts = triarc.split_points(triarc.ellipse(20, 12, 0, 2 * math.pi))
    assert len(cuts) == 3          # pi/2, pi, 3pi/2 (0 and 2pi are the ends)
    for c, want in zip(cuts, (math.pi / 2, math.pi, 3 * math.pi / 2)):
        assert abs(c - want) < 2e-3


def test_seed_example_ellipse_counts():
    """Seed 003: ellipse 50 x 30, second quadrant, 0.01 mm: 7 groups, 20 arcs
    in the paper.  Ours takes fewer (the node criterion uses the measured
    deviation of the chain); the count is pinned so a change is noticed."""
    arcs, groups = triarc.fit(triarc.ellipse(50, 30, math.pi / 2, math.pi), 0.01)
    assert (len(groups), len(arcs)) == (3, 9)


@pytest.mark.parametrize("engine", ["model", "rtl"])
def test_fitted_ellipse_runs_end_to_end(tmp_path, engine):
    g = subprocess.run([sys.executable, "-m", "halfpoint", "fit", "ellipse", "--a", "8", "--b", "5",
                        "--tol", "0.01", "--full"], capture_output=True, text=True)
    assert g.returncode == 0, g.stderr
    prog = tmp_path / "ellipse.ngc"
    # at the machine's speed (the fit writes F600), so that the RTL run stays short
    prog.write_text(g.stdout.replace("F600", "F240000"))
    # the shipped simulation machine with a 2 um lattice (its speeds scaled to match)
    sim = (Path(__file__).resolve().parents[2] / "examples" / "machine_sim.toml").read_text()
    machine = tmp_path / "machine.toml"
    machine.write_text(sim.replace("blu_mm = 0.01 ", "blu_mm = 0.002")
                       .replace("blu_mm = 0.01\n", "blu_mm = 0.002\n")
                       .replace("max_velocity_mm_s = 20000.0", "max_velocity_mm_s = 4000.0")
                       .replace("max_velocity_mm_s = 10000.0", "max_velocity_mm_s = 2000.0")
                       .replace("max_accel_mm_s2 = 20000000.0", "max_accel_mm_s2 = 4000000.0")
                       .replace("max_accel_mm_s2 = 10000000.0", "max_accel_mm_s2 = 2000000.0"))
    r = subprocess.run([sys.executable, "-m", "halfpoint", "run", str(prog), "--engine", engine,
                        "--machine", str(machine)], capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    final = next(ln for ln in r.stdout.splitlines() if ln.startswith("final position:"))
    x, y, _ = (float(v) for v in final.split(":")[1].replace("mm", "").split(","))
    # the closed chain comes back to its start within the arc unit's 1 BLU per axis
    assert abs(x - 8.0) <= 0.002 + 1e-9 and abs(y) <= 0.002 + 1e-9


def test_curvature_discontinuity_is_a_split_point():
    """Two parabolas joined with equal value and slope but a jump in f'' at
    x = 0: split at the jump (and at the left parabola's vertex, x = -5)."""
    f = lambda x: 0.01 * (x + 5) ** 2 if x < 0 else 0.25 + 0.1 * x + 0.03 * x * x   # noqa: E731
    df = lambda x: 0.02 * (x + 5) if x < 0 else 0.1 + 0.06 * x                       # noqa: E731
    d2 = lambda x: 0.02 if x < 0 else 0.06                                            # noqa: E731
    curve = triarc.explicit(f, df, d2, -20, 15)
    cuts = triarc.split_points(curve)
    assert len(cuts) == 2 and abs(cuts[0] + 5) < 1e-2 and abs(cuts[1]) < 1e-9
    arcs, _ = triarc.fit(curve, 0.01)
    dev, tangent = triarc.verify(curve, arcs, 0.01)
    assert dev <= 0.01 * (1 + 1e-6) and tangent < 1e-9
