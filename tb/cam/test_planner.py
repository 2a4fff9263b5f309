# SPDX-License-Identifier: Apache-2.0
"""The lookahead planner against closed forms and an independent checker.

The checker (``check_plan``) takes nothing from the planner but the numbers it
reports per segment and re-derives from the program's geometry and the machine's
limits what must hold: every phase's speed change matches its acceleration and
time, the phases integrate to the segment's length, speeds are continuous at
every junction and zero at the start, the end and either side of a dwell, no
feed move exceeds its F, and no axis exceeds its speed or acceleration limit
(arcs sampled along the profile, with the centripetal acceleration).

``HALFPOINT_PLANNER_CASES`` sets the number of random programs in the property
test (default 12; each takes a few milliseconds).
"""

from __future__ import annotations

import math
import os
import random

import numpy as np
import pytest

from halfpoint.cam.gcode import GcodeError, Move, parse
from halfpoint.cam.machine import MachineError, from_dict
from halfpoint.cam.planner import (ARC_TANGENTIAL_SHARE, Dwell, Segment, estimate_time,
                                   line_iterations, plan, to_core)
from halfpoint.spec.arc import arc_points, lattice_point_near

REL = 1e-9


def machine(vel=(100.0, 100.0, 50.0), acc=(1000.0, 1000.0, 500.0), jd=0.01, blu=0.001,
            blu_y=None, clock=50_000_000):
    axes = {}
    for k, name in enumerate("xyz"):
        b = blu_y if (name == "y" and blu_y is not None) else blu
        # fast STEP timing so that every speed used here is a legal one
        axes[name] = {"blu_mm": b, "max_velocity_mm_s": vel[k], "max_accel_mm_s2": acc[k],
                      "steplen_ns": 0, "stepspace_ns": 0}
    return from_dict({"clock_hz": clock, "axis": axes,
                      "planner": {"junction_deviation_mm": jd}})


def line(a, b, f=6000.0, n=1):
    return Move("line", tuple(map(float, a)), tuple(map(float, b)), n, f)


def rapid(a, b, n=1):
    return Move("rapid", tuple(map(float, a)), tuple(map(float, b)), n, 0.0)


def arc(a, b, c, cw, f=6000.0, n=1):
    return Move("arc", tuple(map(float, a)), tuple(map(float, b)), n, f, center=c, cw=cw)


# --- the independent checker ------------------------------------------------------------------

def _arc_geometry(m: Move):
    """Start angle, signed sweep and radius, from the move alone."""
    cx, cy = m.center
    r = math.hypot(m.start[0] - cx, m.start[1] - cy)
    a0 = math.atan2(m.start[1] - cy, m.start[0] - cx)
    if m.start[:2] == m.end[:2]:
        sweep = 2 * math.pi
    else:
        a1 = math.atan2(m.end[1] - cy, m.end[0] - cx)
        sweep = (a1 - a0) % (2 * math.pi) if not m.cw else (a0 - a1) % (2 * math.pi)
    return a0, (-sweep if m.cw else sweep), r


def _length(m: Move) -> float:
    if m.kind == "arc":
        _, sweep, r = _arc_geometry(m)
        return abs(sweep) * r
    return math.dist(m.start, m.end)


def _profile_samples(s: Segment, n: int):
    """Times, speeds, tangential accelerations and distances sampled over the profile,
    built from the reported phase values only; distance by trapezoid integration."""
    ts, vs, ats = [], [], []
    phases = [(s.t_accel, s.v_entry, s.accel), (s.t_cruise, s.v_cruise, 0.0),
              (s.t_decel, s.v_cruise, -s.accel)]
    t0 = 0.0
    for dur, v0, a in phases:
        if dur <= 0:
            continue
        tt = np.linspace(0.0, dur, n)
        ts.append(t0 + tt)
        vs.append(v0 + a * tt)
        ats.append(np.full(n, a))
        t0 += dur
    t = np.concatenate(ts)
    v = np.concatenate(vs)
    d = np.concatenate([[0.0], np.cumsum(0.5 * (v[1:] + v[:-1]) * np.diff(t))])
    return t, v, np.concatenate(ats), d


def check_plan(items, planned, mach, samples=200):
    vel, acc = mach.max_velocity, mach.max_accel
    assert len(planned) == len(items)
    prev_exit = 0.0                                   # the program starts at rest
    for item, p in zip(items, planned):
        if isinstance(item, Dwell):
            assert p is item
            assert prev_exit == 0.0, "motion does not stop before a dwell"
            continue
        assert isinstance(p, Segment) and p.move is item
        length = _length(item)
        assert p.length == pytest.approx(length, rel=REL, abs=1e-12)
        if length == 0.0:
            assert p.duration == 0.0 and p.v_entry == p.v_exit == prev_exit
            continue
        # continuity at the junction
        assert p.v_entry == pytest.approx(prev_exit, rel=1e-9, abs=1e-9)
        prev_exit = p.v_exit
        # phases: non-negative times, speed changes match accel * time, cruise is the top
        for t in (p.t_accel, p.t_cruise, p.t_decel):
            assert t >= 0.0
        assert p.v_cruise >= max(p.v_entry, p.v_exit) - 1e-9
        assert p.v_cruise - p.v_entry == pytest.approx(p.accel * p.t_accel, rel=1e-9, abs=1e-9)
        assert p.v_cruise - p.v_exit == pytest.approx(p.accel * p.t_decel, rel=1e-9, abs=1e-9)
        # exact integral of the piecewise-linear speed is the length
        dist = ((p.v_entry + p.v_cruise) / 2 * p.t_accel + p.v_cruise * p.t_cruise
                + (p.v_cruise + p.v_exit) / 2 * p.t_decel)
        assert dist == pytest.approx(length, rel=1e-7, abs=1e-9)
        assert p.d_decel_start == pytest.approx(
            length - (p.v_cruise + p.v_exit) / 2 * p.t_decel, rel=1e-7, abs=1e-9)
        if item.kind != "rapid":
            assert p.v_cruise <= item.feed / 60.0 * (1 + REL), "F exceeded"
        if item.kind != "arc":
            u = [(e - s) / length for s, e in zip(item.start, item.end)]
            for k in range(3):
                assert p.v_cruise * abs(u[k]) <= vel[k] * (1 + REL), f"axis {k} speed"
                assert p.accel * abs(u[k]) <= acc[k] * (1 + REL), f"axis {k} acceleration"
        else:
            a0, sweep, r = _arc_geometry(item)
            t, v, at, d = _profile_samples(p, samples)
            assert d[-1] == pytest.approx(length, rel=1e-4)
            sign = -1.0 if item.cw else 1.0
            phi = a0 + sign * d / r
            tx, ty = -sign * np.sin(phi), sign * np.cos(phi)        # unit tangent
            nx, ny = -np.cos(phi), -np.sin(phi)                     # unit normal, inwards
            an = v * v / r
            ax, ay = at * tx + an * nx, at * ty + an * ny
            assert np.all(np.abs(v * tx) <= vel[0] * (1 + REL)), "X speed on the arc"
            assert np.all(np.abs(v * ty) <= vel[1] * (1 + REL)), "Y speed on the arc"
            assert np.all(np.abs(ax) <= acc[0] * (1 + 1e-7)), "X acceleration on the arc"
            assert np.all(np.abs(ay) <= acc[1] * (1 + 1e-7)), "Y acceleration on the arc"
    assert prev_exit == 0.0, "the program does not end at rest"


# --- closed forms -----------------------------------------------------------------------------

def test_single_line_is_the_closed_form_trapezoid():
    m = machine()
    items = [line((0, 0, 0), (100, 0, 0), f=3000)]      # 50 mm/s, 1000 mm/s^2
    (s,) = plan(items, m)
    check_plan(items, [s], m)
    v, a, length = 50.0, 1000.0, 100.0
    assert (s.v_entry, s.v_exit) == (0.0, 0.0)
    assert s.v_cruise == pytest.approx(v, rel=REL)
    assert s.accel == pytest.approx(a, rel=REL)
    assert s.t_accel == pytest.approx(v / a, rel=REL)                  # 0.05 s
    assert s.t_decel == pytest.approx(v / a, rel=REL)
    assert s.d_accel == pytest.approx(v * v / (2 * a), rel=REL)        # 1.25 mm
    assert s.d_decel_start == pytest.approx(length - v * v / (2 * a), rel=REL)
    assert s.t_cruise == pytest.approx((length - v * v / a) / v, rel=REL)   # 1.95 s
    assert estimate_time([s]) == pytest.approx(length / v + v / a, rel=REL)  # 2.05 s
    # the profile as functions of time: s(t) = a t^2 / 2 while accelerating, ...
    assert s.distance_at(0.02) == pytest.approx(0.5 * a * 0.02 ** 2, rel=REL)
    assert s.speed_at(0.02) == pytest.approx(a * 0.02, rel=REL)
    assert s.distance_at(1.0) == pytest.approx(v * v / (2 * a) + v * (1.0 - v / a), rel=REL)
    assert s.speed_at(2.04) == pytest.approx(a * 0.01, rel=1e-6)
    assert s.distance_at(2.04) == pytest.approx(length - 0.5 * a * 0.01 ** 2, rel=REL)
    assert s.distance_at(99.0) == length and s.speed_at(99.0) == 0.0


@pytest.mark.parametrize("length", [0.001, 0.1, 1.0, 2.4])
def test_short_lines_never_reach_cruise_and_are_triangles(length):
    # 100 mm/s would need 5 mm to reach and 5 mm to leave at 1000 mm/s^2
    m = machine()
    items = [line((0, 0, 0), (0, length, 0), f=6000)]
    (s,) = plan(items, m)
    check_plan(items, [s], m)
    a = 1000.0
    peak = math.sqrt(a * length)                     # reached at half the length
    assert s.v_cruise == pytest.approx(peak, rel=REL)
    assert s.t_cruise == pytest.approx(0.0, abs=1e-12)
    assert s.t_accel == pytest.approx(peak / a, rel=REL)
    assert s.d_accel == pytest.approx(length / 2, rel=REL)
    assert s.duration == pytest.approx(2 * math.sqrt(length / a), rel=REL)


def test_triangle_between_two_junction_speeds():
    # three collinear pieces: the middle one enters and leaves at known speeds
    m = machine(vel=(1000.0, 1000.0, 1000.0))
    items = [line((0, 0, 0), (10, 0, 0), f=60000), line((10, 0, 0), (10.5, 0, 0), f=600),
             line((10.5, 0, 0), (20, 0, 0), f=60000)]
    planned = plan(items, m)
    check_plan(items, planned, m)
    mid = planned[1]
    # the F10 mm/s piece caps both junctions at 10 mm/s and cruises at 10 mm/s
    assert mid.v_entry == pytest.approx(10.0) and mid.v_exit == pytest.approx(10.0)
    assert mid.v_cruise == pytest.approx(10.0) and mid.t_cruise == pytest.approx(0.05)
    # the first piece: accelerate from 0, then decelerate to 10 mm/s; 10 mm is not enough
    # to reach 1000 mm/s, so its peak is where the two ramps meet: v^2 = (2aL + 0 + 10^2)/2
    first = planned[0]
    assert first.v_cruise == pytest.approx(math.sqrt((2 * 1000 * 10 + 100) / 2), rel=REL)
    assert first.t_cruise == pytest.approx(0.0, abs=1e-12)


def test_diagonal_line_takes_the_per_axis_limits_projected():
    # X 1000 mm/s^2 and 100 mm/s, Y 500 mm/s^2 and 50 mm/s; direction (0.6, 0.8)
    m = machine(vel=(100.0, 50.0, 50.0), acc=(1000.0, 500.0, 500.0))
    items = [line((0, 0, 0), (30, 40, 0), f=6000)]
    (s,) = plan(items, m)
    check_plan(items, [s], m)
    assert s.accel == pytest.approx(min(1000 / 0.6, 500 / 0.8), rel=REL)     # 625, Y binds
    assert s.v_cruise == pytest.approx(min(100 / 0.6, 50 / 0.8), rel=REL)    # 62.5
    # Y runs exactly at its limits
    assert s.v_cruise * 0.8 == pytest.approx(50.0, rel=REL)
    assert s.accel * 0.8 == pytest.approx(500.0, rel=REL)
    assert s.duration == pytest.approx(50 / 62.5 + 62.5 / 625, rel=REL)


def test_rapid_runs_at_the_axes_maximum_speed():
    m = machine(vel=(100.0, 100.0, 50.0))
    items = [rapid((0, 0, 0), (300, 0, 0)), rapid((300, 0, 0), (310, 10, 10))]
    planned = plan(items, m)
    check_plan(items, planned, m)
    assert planned[0].v_cruise == pytest.approx(100.0, rel=REL)
    # (1, 1, 1)/sqrt(3): Z's 50 mm/s binds, 50 * sqrt(3) along the path
    assert planned[1].v_limit == pytest.approx(50 * math.sqrt(3), rel=REL)


def test_feed_is_honoured_and_g20_feed_is_in_inches():
    m = machine()
    prog = parse("G20 G1 X4 F60\nG21 G1 X200 F1200\nM2")      # 60 in/min = 25.4 mm/s
    planned = plan(prog.moves, m)
    check_plan(prog.moves, planned, m)
    assert planned[0].v_cruise == pytest.approx(25.4, rel=REL)
    assert planned[1].v_cruise == pytest.approx(20.0, rel=REL)


# --- junctions --------------------------------------------------------------------------------

@pytest.mark.parametrize("turn_deg", [0, 30, 90, 150, 180])
def test_junction_speed_follows_the_junction_deviation_formula(turn_deg):
    """Two 100 mm lines meeting at a direction change of ``turn_deg`` (grbl's junction
    angle theta = 180 - turn: 180 is straight on, 0 a full reversal).  The lines are
    placed symmetrically about X, so the velocity change u_out - u_in is along +Y and
    the junction acceleration is Y's limit."""
    ay, delta, feed = 800.0, 0.02, 200.0
    m = machine(vel=(500.0, 500.0, 500.0), acc=(3000.0, ay, 3000.0), jd=delta)
    half = math.radians(turn_deg) / 2
    u_in = (math.cos(half), -math.sin(half), 0.0)
    u_out = (math.cos(half), math.sin(half), 0.0)
    if turn_deg == 180:
        u_in, u_out = (0.0, -1.0, 0.0), (0.0, 1.0, 0.0)
    corner = tuple(100 * c for c in u_in)
    end = tuple(c + 100 * d for c, d in zip(corner, u_out))
    items = [line((0, 0, 0), corner, f=feed * 60), line(corner, end, f=feed * 60)]
    planned = plan(items, m)
    check_plan(items, planned, m)
    theta = math.radians(180 - turn_deg)
    sin_half = math.sin(theta / 2)
    if turn_deg == 0:
        expected = feed                      # straight on: only F limits
    elif turn_deg == 180:
        expected = 0.0                       # a reversal stops
    else:
        expected = min(feed, math.sqrt(ay * delta * sin_half / (1 - sin_half)))
    assert planned[0].v_exit == pytest.approx(expected, rel=1e-9, abs=1e-12)
    if 0 < turn_deg < 180:                   # the formula, not F, sets these three
        assert expected < feed


def test_zero_junction_deviation_stops_at_every_corner_but_not_on_straights():
    m = machine(jd=0.0)
    items = [line((0, 0, 0), (10, 0, 0)), line((10, 0, 0), (20, 0, 0)),
             line((20, 0, 0), (20, 10, 0))]
    planned = plan(items, m)
    check_plan(items, planned, m)
    assert planned[0].v_exit > 0 and planned[1].v_exit == 0.0


def test_exact_stop_g61_1_stops_at_the_end_of_every_block():
    """LinuxCNC's G61.1: "movement will stop at the end of each programmed segment",
    collinear ones included; G61 and G64 blend (the lattice path is exact in all three:
    the core never rounds a corner).  The mode is modal and acts on the block it is in
    force for: the junction after a G61.1 block is a stop."""
    text = ("G21 G90 G61.1 G1 F3000\nX1\nX2\nX3\nG64\nX4\nX5\n"
            "G61\nX6\nX7\nG61.1 X8\nG64 X9\nM2\n")
    prog = parse(text)
    m = machine()
    planned = plan(prog.moves, m)
    check_plan(prog.moves, planned, m)
    exits = [p.v_exit for p in planned]
    # blocks X1..X3 and X8 end at rest; X4..X7 and X9's neighbours blend
    assert [e == 0.0 for e in exits] == [True, True, True, False, False, False, False,
                                         True, True]
    assert all(p.v_cruise > 0 for p in planned)
    blended = plan(parse(text.replace("G61.1", "G64")).moves, m)
    assert estimate_time(planned) > estimate_time(blended) + 0.02


def test_arc_meets_its_neighbours_with_its_tangent():
    # a line along +X into a CCW quarter arc starting with tangent +X: straight, no slowdown
    m = machine(acc=(2000.0, 2000.0, 500.0))
    items = [line((-50, -10, 0), (0, -10, 0), f=1200),
             arc((0, -10, 0), (10, 0, 0), (0.0, 0.0), cw=False, f=1200),
             line((10, 0, 0), (10, 50, 0), f=1200)]
    planned = plan(items, m)
    check_plan(items, planned, m)
    # R = 10: centripetal limit sqrt(0.5 * 2000 * 10) = 100 mm/s, above F = 20 mm/s
    assert planned[0].v_exit == pytest.approx(20.0, rel=REL)
    assert planned[1].v_exit == pytest.approx(20.0, rel=REL)
    # the same arc entered against its tangent (line along -X) is a reversal: a stop
    items[0] = line((50, -10, 0), (0, -10, 0), f=1200)
    planned = plan(items, m)
    check_plan(items, planned, m)
    assert planned[0].v_exit == 0.0


# --- arcs -------------------------------------------------------------------------------------

@pytest.mark.parametrize("radius", [0.05, 0.2, 1.0, 3.0])
def test_small_full_circles_are_held_to_the_centripetal_limit(radius):
    a = 1000.0
    m = machine(acc=(a, a, 500.0))
    start = (radius, 0.0, 0.0)
    items = [arc(start, start, (0.0, 0.0), cw=True, f=6000)]
    (s,) = plan(items, m)
    check_plan(items, [s], m, samples=400)
    # the centripetal share of the budget: v^2 / R <= (1 - share) * a
    v_c = math.sqrt((1 - ARC_TANGENTIAL_SHARE) * a * radius)
    assert v_c < 100.0
    assert s.v_limit == pytest.approx(v_c, rel=REL)
    assert s.v_cruise <= v_c * (1 + REL)
    assert s.length == pytest.approx(2 * math.pi * radius, rel=REL)
    if 2 * math.pi * radius > v_c ** 2 / (ARC_TANGENTIAL_SHARE * a):
        assert s.v_cruise == pytest.approx(v_c, rel=REL)     # long enough to reach it
    # the acceleration actually reached at cruise is the centripetal limit, not more
    assert s.v_cruise ** 2 / radius <= (1 - ARC_TANGENTIAL_SHARE) * a * (1 + REL)


def test_large_arc_runs_at_feed_and_short_arc_uses_only_its_swept_angles():
    m = machine(vel=(100.0, 20.0, 50.0), acc=(1000.0, 1000.0, 500.0))
    # a short CCW arc about the +X axis moves mostly in Y: Y's 20 mm/s binds along it
    r = 50.0
    a0, a1 = math.radians(-10), math.radians(10)
    p0 = (r * math.cos(a0), r * math.sin(a0), 0.0)
    p1 = (r * math.cos(a1), r * math.sin(a1), 0.0)
    items = [arc(p0, p1, (0.0, 0.0), cw=False, f=6000)]
    (s,) = plan(items, m)
    check_plan(items, [s], m)
    assert s.v_limit == pytest.approx(20.0, rel=REL)        # tangent (~0, 1) at 0 degrees
    # the same radius, an arc about the +Y axis, moves mostly in X: the worst |t_y| over
    # +-10 degrees about 90 degrees is sin(10 deg)
    b0, b1 = math.radians(80), math.radians(100)
    q0 = (r * math.cos(b0), r * math.sin(b0), 0.0)
    q1 = (r * math.cos(b1), r * math.sin(b1), 0.0)
    items = [arc(q0, q1, (0.0, 0.0), cw=False, f=6000)]
    (s,) = plan(items, m)
    check_plan(items, [s], m)
    assert s.v_limit == pytest.approx(min(100.0, 20.0 / math.sin(math.radians(10))), rel=REL)


def test_arcs_in_other_planes_take_those_axes_limits():
    # G18: a half circle in XZ about (x 1, z 0), R 1; Z is the slow axis
    m = machine(vel=(100.0, 100.0, 10.0), acc=(1000.0, 1000.0, 100.0))
    prog = parse("G21 G18 G2 X2 Z0 I1 K0 F6000\nM2")
    (s,) = plan(prog.moves, m)
    assert s.length == pytest.approx(math.pi, rel=REL)
    # the half circle passes through both the X and Z directions: Z's limits bind
    assert s.v_limit == pytest.approx(min(10.0, math.sqrt((1 - ARC_TANGENTIAL_SHARE) * 100.0)),
                                      rel=REL)
    assert s.accel == pytest.approx(ARC_TANGENTIAL_SHARE * 100.0, rel=REL)
    assert s.dir_start[1] == 0.0 and abs(s.dir_start[2]) == pytest.approx(1.0)


# --- lookahead --------------------------------------------------------------------------------

def test_two_thousand_tiny_collinear_segments_cruise_at_feed():
    """grbl #1144: a CAM chain of tiny collinear segments must not stop at every junction.
    2,000 segments of 0.05 mm on a slanted line (parsed from G-code, so the points carry
    the rounding of 4-decimal text), F3000 = 50 mm/s."""
    ang = math.radians(30)
    lines = ["G21 G90 G1 F3000"]
    for k in range(1, 2001):
        d = 0.05 * k
        lines.append(f"X{d * math.cos(ang):.4f} Y{d * math.sin(ang):.4f}")
    lines.append("M2")
    prog = parse("\n".join(lines))
    m = machine()
    planned = plan(prog.moves, m)
    check_plan(prog.moves, planned, m, samples=2)
    assert len(planned) == 2000
    v, length = 50.0, sum(p.length for p in planned)
    a = min(1000 / math.cos(ang), 1000 / math.sin(ang))
    ramp = v * v / (2 * a)
    pos = 0.0
    cruising = 0
    for p in planned:
        if pos >= ramp + 1e-6 and pos + p.length <= length - ramp - 1e-6:
            assert p.v_entry == pytest.approx(v, rel=1e-9)
            assert p.v_exit == pytest.approx(v, rel=1e-9)
            cruising += 1
        pos += p.length
    assert cruising >= 1950
    # the whole chain takes what one straight line of the same length takes
    assert estimate_time(planned) == pytest.approx(length / v + v / a, rel=1e-6)


def test_tiny_chords_round_a_tight_curve_are_held_to_its_centripetal_limit():
    """Chords of 0.05 mm round a 1 mm circle at F6000: grbl's junction deviation alone
    would allow about sqrt(8 a delta R^2 / c^2) = 179 mm/s at each 2.9-degree turn;
    Klipper's cap (the cornering circle touches both chords at their middles, which is
    the polygon's incircle, radius R cos(turn/2)) holds the junction speed to that
    circle's centripetal limit with the axes' acceleration in the turn's direction."""
    a, radius, n = 1000.0, 1.0, 126
    m = machine(acc=(a, a, 500.0))
    pts = [(radius * math.cos(2 * math.pi * k / n), radius * math.sin(2 * math.pi * k / n), 0.0)
           for k in range(n + 1)]
    items = [line(pts[k], pts[k + 1], f=6000, n=k + 1) for k in range(n)]
    planned = plan(items, m)
    check_plan(items, planned, m)
    turn = 2 * math.pi / n
    r_in = radius * math.cos(turn / 2)
    for k in range(n - 1):
        u_in = np.subtract(pts[k + 1], pts[k])
        u_out = np.subtract(pts[k + 2], pts[k + 1])
        u_in, u_out = u_in / np.linalg.norm(u_in), u_out / np.linalg.norm(u_out)
        j = (u_out - u_in) / np.linalg.norm(u_out - u_in)
        a_j = min(a / abs(c) for c in j[:2] if abs(c) > 1e-12)
        v2 = planned[k].v_exit ** 2
        assert v2 <= a_j * r_in * (1 + 1e-9)
        # and each axis's centripetal acceleration on that circle is within its limit
        assert v2 / r_in * np.max(np.abs(j[:2])) <= a * (1 + 1e-9)
    # away from the start and the stop the chain runs at that limit, not slower
    assert planned[n // 2].v_exit ** 2 == pytest.approx(
        min(a / abs(c) for c in (math.cos(math.pi + turn * (n // 2 + 1)),
                                 math.sin(math.pi + turn * (n // 2 + 1))) if abs(c) > 1e-12)
        * r_in, rel=1e-6)


def test_program_starts_and_ends_at_rest_and_dwells_stay_in_order():
    m = machine()
    items = [rapid((0, 0, 0), (10, 0, 5), n=1),
             line((10, 0, 5), (10, 0, 0), f=300, n=2),
             Dwell(0.5, 3),
             line((10, 0, 0), (40, 0, 0), f=1200, n=4),
             line((40, 0, 0), (40, 30, 0), f=1200, n=5),
             Dwell(1.25, 6),
             Dwell(0.0, 7),
             arc((40, 30, 0), (40, 30, 0), (35.0, 30.0), cw=True, f=600, n=8),
             rapid((40, 30, 0), (0, 0, 5), n=9)]
    planned = plan(items, m)
    check_plan(items, planned, m)
    assert [type(p).__name__ for p in planned] == ["Segment", "Segment", "Dwell", "Segment",
                                                   "Segment", "Dwell", "Dwell", "Segment",
                                                   "Segment"]
    assert [p.lineno for p in planned] == [1, 2, 3, 4, 5, 6, 7, 8, 9]
    assert planned[1].v_exit == 0.0 and planned[3].v_entry == 0.0
    assert planned[4].v_exit == 0.0 and planned[7].v_entry == 0.0
    assert planned[3].v_exit > 0.0                  # no stop at the 90-degree corner
    motion = sum(p.duration for p in planned if isinstance(p, Segment))
    assert estimate_time(planned) == pytest.approx(motion + 1.75, rel=REL)


def test_zero_length_move_keeps_the_speed_of_the_path():
    m = machine()
    items = [line((0, 0, 0), (50, 0, 0)), line((50, 0, 0), (50, 0, 0), n=2),
             line((50, 0, 0), (100, 0, 0), n=3)]
    planned = plan(items, m)
    check_plan(items, planned, m)
    assert planned[1].length == 0.0 and planned[1].duration == 0.0
    assert planned[1].v_entry == pytest.approx(100.0) == planned[0].v_exit


def test_bad_input_names_the_line():
    m = machine()
    with pytest.raises(GcodeError, match="line 7: dwell time must be >= 0 s"):
        plan([line((0, 0, 0), (1, 0, 0)), Dwell(-1.0, 7)], m)
    with pytest.raises(GcodeError, match="line 3: no usable feed rate"):
        plan([line((0, 0, 0), (1, 0, 0), f=0.0, n=3)], m)
    with pytest.raises(GcodeError, match="line 4: arc radius is zero"):
        plan([arc((1, 1, 0), (2, 2, 0), (1.0, 1.0), cw=True, n=4)], m)
    # a helix is planned (issue 14, item 2), along its 3-D path
    helix = plan([arc((1, 0, 0), (0, 1, 1), (0.0, 0.0), cw=False, n=5)], m)[0]
    assert helix.length == pytest.approx(math.hypot(math.pi / 2, 1))
    with pytest.raises(TypeError):
        plan(["G1 X1"], m)


# --- random programs --------------------------------------------------------------------------

def _random_program(rng: random.Random):
    items, pos, n = [], (0.0, 0.0, 0.0), 1
    heading = rng.uniform(0, 2 * math.pi)
    for _ in range(rng.randint(5, 60)):
        kind = rng.random()
        f = rng.choice([60.0, 600.0, 3000.0, 12000.0])
        if kind < 0.08:
            items.append(Dwell(rng.uniform(0, 0.3), n))
        elif kind < 0.5:
            heading += rng.gauss(0, 0.6)
            d = rng.choice([0.002, 0.05, 0.5, 5.0, 40.0])
            z = pos[2] + (rng.uniform(-1, 1) if rng.random() < 0.2 else 0.0)
            end = (pos[0] + d * math.cos(heading), pos[1] + d * math.sin(heading), z)
            items.append(rapid(pos, end, n) if rng.random() < 0.15 else line(pos, end, f, n))
            pos = end
        else:
            r = rng.choice([0.01, 0.3, 2.0, 25.0])
            cw = rng.random() < 0.5
            # centre to the side of the current heading, so the arc continues it tangentially
            side = -1.0 if cw else 1.0
            c = (pos[0] - side * r * math.sin(heading), pos[1] + side * r * math.cos(heading))
            sweep = rng.uniform(0.05, 2 * math.pi)
            a0 = math.atan2(pos[1] - c[1], pos[0] - c[0])
            a1 = a0 + (-sweep if cw else sweep)
            end = (c[0] + r * math.cos(a1), c[1] + r * math.sin(a1), pos[2])
            items.append(arc(pos, end, c, cw, f, n))
            heading = a1 + (-math.pi / 2 if cw else math.pi / 2)
            pos = end
        n += 1
    return items


def test_random_programs_satisfy_every_limit():
    cases = int(os.environ.get("HALFPOINT_PLANNER_CASES", "12"))
    rng = random.Random(13)
    for _ in range(cases):
        vel = tuple(rng.choice([20.0, 100.0, 300.0]) for _ in range(3))
        acc = tuple(rng.choice([50.0, 1000.0, 20000.0]) for _ in range(3))
        m = machine(vel=vel, acc=acc, jd=rng.choice([0.0, 0.005, 0.05]))
        items = _random_program(rng)
        check_plan(items, plan(items, m), m, samples=60)


# --- core units -------------------------------------------------------------------------------

def test_core_units_for_lines_are_iterations_and_for_arcs_blu():
    m = machine(clock=50_000_000)
    items = [line((0, 0, 0), (3, 4, 0), f=3000), arc((3, 4, 0), (3, 4, 0), (0.0, 0.0), cw=True,
                                                     f=3000)]
    lin, circ = plan(items, m)
    c = to_core(lin, m)
    assert line_iterations(lin.move.start, lin.move.end, m.blu) == 4000
    assert c.unit_mm == pytest.approx(5.0 / 4000, rel=REL)            # 1.25 um per iteration
    assert c.units == 4000
    assert c.v_cruise == pytest.approx(lin.v_cruise / (5.0 / 4000) / 50e6, rel=REL)
    assert c.accel == pytest.approx(lin.accel / (5.0 / 4000) / 50e6 ** 2, rel=REL)
    # accelerating at c.accel per clock^2 for t_accel clocks reaches the cruise rate
    t_clocks = lin.t_accel * 50e6
    assert c.v_entry + c.accel * t_clocks == pytest.approx(c.v_cruise, rel=1e-9)
    assert c.clocks == pytest.approx(lin.duration * 50e6, rel=1e-9)
    assert c.decel_start == pytest.approx(lin.d_decel_start / c.unit_mm, rel=1e-9)
    k = to_core(circ, m)
    assert k.unit_mm == 0.001
    assert k.v_cruise * 0.001 * 50e6 == pytest.approx(circ.v_cruise, rel=REL)
    assert k.units == pytest.approx(16 * (math.sqrt(2) - 1) * 5000, rel=REL)   # 6.627 R
    # the credit trapezoid: ends at v_exit exactly at units, longer than the true arc
    assert k.decel_start == pytest.approx(
        k.units - (k.v_cruise ** 2 - k.v_exit ** 2) / (2 * k.accel), rel=1e-12)
    assert k.clocks > circ.duration * 50e6
    # a line that stays on its lattice point has no core motion
    tiny = plan([line((0, 0, 0), (0.0004, 0, 0))], m)[0]
    assert to_core(tiny, m).units == 0.0
    # an arc with X and Y on different BLUs cannot be put on the lattice
    m2 = machine(blu_y=0.002)
    with pytest.raises(MachineError, match=r"axis\.y\.blu_mm.*line 1"):
        to_core(plan(items, m2)[1], m2)


@pytest.mark.parametrize("radius, deg0, deg1, cw", [
    (3000, 0, 0, 1),                 # full circle from an axis
    (3000, 45, 165, 0),              # from 45 degrees, CCW across a quadrant boundary
    (4123, -76, 0, 0),               # short arc
    (2600, 105, 16, 1),              # CW across the axis
    (777, 10, 350, 0),               # almost a full turn
])
def test_arc_credit_length_matches_the_arc_models_lattice_moves(radius, deg0, deg1, cw):
    """The core spends 1 per axis move and sqrt(2) per diagonal move; the planner's
    lattice length of an arc must agree with the moves the bit-exact arc model makes."""
    xs = round(radius * math.cos(math.radians(deg0)))
    ys = round(radius * math.sin(math.radians(deg0)))
    if deg0 == deg1:
        xe, ye = xs, ys
    else:
        xe, ye = lattice_point_near(xs * xs + ys * ys, math.radians(deg1))
    pts = arc_points(xs, ys, xe, ye, cw)
    credit = sum(math.sqrt(2) if (b[0] != a[0] and b[1] != a[1]) else 1.0
                 for a, b in zip(pts, pts[1:]))
    blu = 0.001
    r = math.hypot(xs, ys) * blu
    start, end = (xs * blu, ys * blu, 0.0), (xe * blu, ye * blu, 0.0)
    m = machine()
    (s,) = plan([arc(start, end, (0.0, 0.0), cw=bool(cw), f=600)], m)
    assert s.radius == pytest.approx(r, rel=REL)
    k = to_core(s, m)
    # within a couple of moves (the model stops at the lattice point nearest the end)
    assert k.units == pytest.approx(credit, abs=3.0)
    assert abs(k.units - credit) / credit < 2e-3
