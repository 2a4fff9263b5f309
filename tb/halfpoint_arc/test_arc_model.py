# SPDX-License-Identifier: Apache-2.0
"""Model-only tests of the arc interpolator (no simulator)."""

from __future__ import annotations

import math
import random

import numpy as np
import pytest

from arcgen import OCTANT_FLIPS, flips, moves_with_order, octant_order_end, range_edge_points

from halfpoint.spec.arc import (
    ERR_END_OFF, ERR_NONE, ERR_RADIUS_ZERO, ERR_RANGE, ArcRejected, ArcRun,
    ArcInputs, ArcUnitModel, arc_points, frame, full_circle_stats, limits,
    move_bound, validate, validate_latency,
)

RADII = np.arange(1, 2049)


@pytest.mark.parametrize("cw", [0, 1])
def test_full_circles_1_to_2048_error_and_move_count(cw):
    moves, err = full_circle_stats(RADII, cw)
    assert err.max() < 0.5, f"max radial error {err.max()} at R={RADII[err.argmax()]}"
    ratio = moves / RADII
    # 4*sqrt(2)*R moves per circle (SEEDS.md); small radii round coarsely
    big = RADII >= 64
    assert np.all(np.abs(ratio[big] / (4 * math.sqrt(2)) - 1) < 0.01)
    assert np.all((ratio >= 4) & (ratio <= 6))


@pytest.mark.parametrize("cw", [0, 1])
def test_vectorised_sweep_matches_reference_model(cw):
    radii = np.arange(1, 160)
    moves, err = full_circle_stats(radii, cw)
    for r, n, e in zip(radii, moves, err):
        pts = arc_points(int(r), 0, int(r), 0, cw)
        assert len(pts) - 1 == n and pts[-1] == (r, 0)
        assert abs(max(abs(math.hypot(*p) - r) for p in pts) - e) < 1e-12


def test_decision_table_against_brute_force_minimum_deviation():
    """Each move is the one of B, A, C that minimises |F| (seed 000's claim:
    the same feed directions as the classic minimum-deviation method)."""
    for r in range(1, 120):
        for cw in (0, 1):
            run = ArcRun(r, 0, r, 0, cw)
            while not run.done:
                u, v, f = run.u, run.v, run.f
                cand = {"B": f - 2 * u + 1, "C": f + 2 * v + 1, "A": f - 2 * u + 2 * v + 2}
                best = min(abs(c) for c in cand.values())
                kind = run.move().kind
                assert abs(cand[kind]) == best, (r, cw, kind, cand)


def test_worked_start_frames():
    # SEEDS.md quadrant table, one point per row
    assert frame(5, 0, 0) == (0, 5, 0)     # CCW I: u=|x|, axis point enters I
    assert frame(0, 5, 0) == (1, 5, 0)     # CCW II: u=|y|
    assert frame(-5, 0, 0) == (2, 5, 0)
    assert frame(0, -5, 0) == (3, 5, 0)
    assert frame(0, 5, 1) == (0, 5, 0)     # CW I: u=|y|
    assert frame(-5, 0, 1) == (1, 5, 0)
    assert frame(0, -5, 1) == (2, 5, 0)
    assert frame(5, 0, 1) == (3, 5, 0)


def test_end_point_contract_exhaustive_small_radii():
    """Every accepted end point: the arc stops within the move bound; every
    end within 0.5 BLU of the circle: stop within 1 BLU per axis; start = end:
    exactly back at the start."""
    rng = random.Random(5)
    checked = 0
    for _ in range(40):
        xs, ys = 0, 0
        while xs == 0 and ys == 0:
            xs, ys = rng.randint(-30, 30), rng.randint(-30, 30)
        cw = rng.randint(0, 1)
        r = math.hypot(xs, ys)
        full = arc_points(xs, ys, xs, ys, cw)
        assert full[-1] == (xs, ys)
        ri = int(r) + 2
        for xe in range(-ri, ri + 1):
            for ye in range(-ri, ri + 1):
                if validate(xs, ys, xe, ye, 32):
                    continue
                pts = arc_points(xs, ys, xe, ye, cw)
                checked += 1
                assert len(pts) - 1 <= min(move_bound(xs, ys), len(full) - 1)
                if abs(math.hypot(xe, ye) - r) <= 0.5:
                    fx, fy = pts[-1]
                    assert max(abs(fx - xe), abs(fy - ye)) <= 1, ((xs, ys, xe, ye, cw), pts[-1])
                if (xe, ye) in pts[1:]:
                    # an end point on the lattice path is reached exactly
                    assert pts[-1] == (xe, ye)
    assert checked > 10000


def test_validate_boundaries():
    assert validate(0, 0, 1, 0, 16) == ERR_RADIUS_ZERO
    m = 1 << 15
    r2max = limits(16)[1]
    assert r2max == (m - 1) * (m - 2)
    assert validate(m - 2, 0, m - 2, 0, 16) == ERR_NONE
    assert validate(m - 1, 0, m - 1, 0, 16) == ERR_RANGE
    assert validate(-m, 0, -m, 0, 16) == ERR_RANGE
    # tolerance |F_e| <= 2*max(|xs|,|ys|): start (6, 8), R^2 = 100, |F_e| <= 16
    assert validate(6, 8, 10, 4, 16) == ERR_NONE         # F_e = 16
    assert validate(6, 8, 9, 6, 16) == ERR_END_OFF       # F_e = 17
    assert validate(6, 8, 8, 6, 16) == ERR_NONE          # F_e = 0
    assert validate(6, 8, 2, 9, 16) == ERR_NONE          # F_e = -15
    assert validate(6, 8, 9, 1, 16) == ERR_END_OFF       # F_e = -18
    with pytest.raises(ArcRejected) as exc:
        arc_points(10, 0, 2, 11, 0, 16)
    assert exc.value.code == ERR_END_OFF


def test_every_end_within_half_blu_is_accepted_and_beyond_one_rejected():
    rng = random.Random(9)
    for _ in range(3000):
        xs, ys = rng.randint(-5000, 5000), rng.randint(-5000, 5000)
        if xs == 0 and ys == 0:
            continue
        r = math.hypot(xs, ys)
        th = rng.uniform(0, 2 * math.pi)
        for dr in (-1.2, -0.49, 0.0, 0.49, 1.2):
            xe, ye = round((r + dr) * math.cos(th)), round((r + dr) * math.sin(th))
            d = math.hypot(xe, ye) - r
            code = validate(xs, ys, xe, ye, 32)
            if abs(d) <= 0.5:
                assert code == ERR_NONE
            elif abs(d) > 1.0:
                assert code == ERR_END_OFF


def test_cycle_model_timing():
    """Latency from the accepting edge to the first move, and the pending slot."""
    w = 16
    m = ArcUnitModel(w)
    m.clock(ArcInputs(rst=1))
    o = m.outputs()
    assert o.s_ready and not o.busy
    m.clock(ArcInputs(s_valid=1, s_xs=10, s_ys=0, s_xe=0, s_ye=10))
    first = None
    for cyc in range(1, 100):
        o = m.outputs()
        if o.move:
            first = cyc
            break
        m.clock(ArcInputs())
    # W+5 validator clocks to HOLD, one load edge, one move edge
    assert first == validate_latency(w) + 2



def test_lean_stop_predictor_equals_the_model():
    """arc_stop (the host's fast predictor) stops where ArcRun stops."""
    from halfpoint.spec.arc import arc_stop

    rng = random.Random(11)
    for _ in range(800):
        xs, ys = rng.randint(-150, 150), rng.randint(-150, 150)
        if xs == 0 and ys == 0:
            continue
        cw = rng.randint(0, 1)
        r2 = xs * xs + ys * ys
        from halfpoint.spec.arc import lattice_point_near
        xe, ye = lattice_point_near(r2, rng.uniform(0, 2 * math.pi))
        if rng.random() < 0.1:
            xe, ye = xs, ys
        if validate(xs, ys, xe, ye, 32):
            continue
        pts = arc_points(xs, ys, xe, ye, cw)
        assert arc_stop(xs, ys, xe, ye, cw) == (*pts[-1], len(pts) - 1)


def test_cycle_model_arc_to_arc_boundary():
    """A pending arc enters only an idle run stage: with the second arc ready
    long before the first ends, the cycle that shows the first arc's last move
    (done) is followed by one cycle without a move that shows the second arc's
    start (the load), and its first move strobes in the cycle after."""
    w = 16
    m = ArcUnitModel(w)
    m.clock(ArcInputs(rst=1))
    a = (0, 40, 0, 0, 40)       # a quarter circle, much longer than W + 5 moves
    b = (0, 0, 40, -40, 0)
    queue = [a, b]
    seen = []
    for _ in range(400):
        o = m.outputs()
        seen.append(o)
        if queue and o.s_ready:
            cw, xs, ys, xe, ye = queue.pop(0)
            m.clock(ArcInputs(s_valid=1, s_cw=cw, s_xs=xs, s_ys=ys, s_xe=xe, s_ye=ye))
        else:
            m.clock(ArcInputs())
    done = [k for k, o in enumerate(seen) if o.done]
    assert len(done) == 2
    k = done[0]
    assert (seen[k].x, seen[k].y) == (0, 40)
    gap = seen[k + 1]
    assert not gap.move and gap.busy and (gap.x, gap.y, gap.f) == (0, 40, 0)
    assert seen[k + 2].move and (seen[k + 2].x, seen[k + 2].y) != (0, 40)
    moves = [k for k, o in enumerate(seen) if o.move]
    # every clock from the first move to the last but the boundary's one
    assert moves[-1] - moves[0] + 1 == len(moves) + 1


@pytest.mark.parametrize("width", [16, 23, 32])
def test_octant_order_ends_cover_every_bit_from_3(width):
    """The RTL test octant_order_ends_every_bit has, for every bit from 3 up
    and each of the four flips, an accepted arc whose stop moves when the
    end's progress order is the other one (bits 0..2 leave few or no such
    ends: the radius is a few BLU)."""
    rng = random.Random(102)
    for bit in range(3, width - 1):
        for flip in OCTANT_FLIPS:
            cmd = octant_order_end(rng, width, bit, flip, 1000 if bit < 5 else 300)
            assert cmd is not None, (bit, flip)
            cw, xs, ys, xe, ye = cmd
            assert validate(xs, ys, xe, ye, width) == ERR_NONE
            _, ue, ve = frame(xe, ye, cw)
            assert flips(ue, ve, bit, flip)
            moves = len(arc_points(xs, ys, xe, ye, cw, width)) - 1
            assert moves_with_order(cmd, ve <= ue, 64, width) == moves
            assert moves_with_order(cmd, ve > ue, 64, width) != moves


def test_range_edge_points():
    """range_edge_points finds starts at the range limit's edge: at W = 16 the
    limit - 1 and - 2 (R^2 = limit - 1 is what kills the range compare with bit 1
    of R^2 inverted) and one just above."""
    limit = limits(16)[1]
    points = range_edge_points(16)
    assert (30425, 12164, -1) in points
    assert {a for _, _, a in points} >= {-2, -1, 2}
    for x, y, above in points:
        assert x * x + y * y == limit + above
        assert (validate(x, y, x, y, 16) == ERR_RANGE) == (above > 0)


def test_no_entry_into_the_end_quadrant_before_a_second_octant_end():
    """The ground of the arc's equivalent mutants #124 and #195: an arc entering
    E's quadrant by a crossing, armed, with E in that quadrant's second octant
    (ve > ue), never enters at u' < ue (past E in the order (-u, v)).  Above
    R^2 = 32 it cannot (u' >= v > R - 1 at the crossing, 2 ue^2 < R^2 + 2R by the
    end tolerance, so R - 1 < ue needs R < 5.65); every accepted arc below, with
    its end anywhere within 8 BLU of the centre, is run here."""
    width = 16
    arcs = entries = 0
    for xs in range(-6, 7):
        for ys in range(-6, 7):
            if not 0 < xs * xs + ys * ys < 40:
                continue
            for xe in range(-8, 9):
                for ye in range(-8, 9):
                    if validate(xs, ys, xe, ye, width):
                        continue
                    for cw in (0, 1):
                        run = ArcRun(xs, ys, xe, ye, cw, width)
                        arcs += 1
                        while not run.done:
                            q, armed = run.q, run.armed
                            run.advance()
                            if armed and q != run.qe and run.q == run.qe:
                                entries += 1
                                assert not (run.ve > run.ue and run.u < run.ue), \
                                    (cw, xs, ys, xe, ye)
    assert arcs > 10_000 and entries > 10_000
