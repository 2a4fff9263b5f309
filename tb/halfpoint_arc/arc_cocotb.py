# SPDX-License-Identifier: Apache-2.0
"""cocotb tests of halfpoint_arc: the RTL against the model on every clock.

Run by ``test_arc_rtl.py`` (pytest) through cocotb's Python runner; the
coordinate width is read from the design (its parameter W).
"""

from __future__ import annotations

import itertools
import math
import os
import random

import cocotb

from arcgen import (
    arc_for_quadrants, full_circle, nearest_on_circle, octant_order_ends, range_edge_points,
    short_arc, start_point,
)
from halfpoint.spec.arc import (
    ERR_END_OFF, ERR_RADIUS_ZERO, ERR_RANGE, ArcRun, arc_points, limits, validate,
    validate_latency,
)
from halfpoint.sim.arcbench import ArcBench
from halfpoint.sim.design import read_parameters

W = 0          # the design's coordinate width: bind() reads it


def bind(dut) -> None:
    """Take W from the design under test (its parameters)."""
    global W
    (W,) = read_parameters(dut, "W")

SEED = int(os.environ.get("HP_SEED", "1"))


def check_results(results, cmds):
    """Each accepted command ran exactly the model's lattice path."""
    assert [r.cmd for r in results] == [tuple(c) for c in cmds]
    for r in results:
        if r.rejected:
            continue
        assert r.finished, f"{r.cmd} did not finish"
        assert ArcBench.points(r) == arc_points(*r.cmd[1:], r.cmd[0], W), f"path of {r.cmd}"


async def run_accepted(dut, bench, cmds, what: str, **idle):
    """Run cmds (none of them to be rejected) and check each against the
    model's lattice path; idle: the bench's valid_idle / en_idle rates."""
    results, stats = await bench.run(cmds, **idle)
    check_results(results, cmds)
    assert not any(r.rejected for r in results), f"{what}: a command was rejected"
    dut._log.info("%s: %d arcs, %d moves, %d cycles", what, len(cmds), stats.moves,
                  stats.cycles)
    return results, stats


@cocotb.test()
async def full_circles(dut):
    """Every full circle of radius 1..64, both directions, on and off an axis,
    and the circle R^2 = 2."""
    bind(dut)
    bench = ArcBench(dut, W, seed=SEED)
    await bench.start()
    cmds = []
    for r in range(1, 65):
        for cw in (0, 1):
            cmds.append(full_circle(r, 0.0, cw))
            cmds.append(full_circle(r, 0.7 + r * 0.37, cw))
    # the smallest circle off an axis, R^2 = 2: a B crossing from (1, 1) lands
    # on u = 1 again (found by mutation testing: the look-ahead of u == 1
    # from v == 1 was never used)
    cmds += [(cw, x, y, x, y) for cw in (0, 1) for x, y in ((1, 1), (-1, -1))]
    cmds = [(c[0], c[1], c[2], c[3], c[4]) for c in cmds]
    results, stats = await bench.run(cmds)
    check_results(results, cmds)
    for r in results:
        assert r.moves[-1] == r.cmd[1:3], f"full circle {r.cmd} did not close"
    dut._log.info("full circles: %d arcs, %d moves, %d cycles", len(cmds), stats.moves, stats.cycles)


@cocotb.test()
async def quadrant_pairs(dut):
    """Random arcs over all start/end quadrant pairs, both directions,
    random enable gaps and random gaps in s_valid."""
    bind(dut)
    rng = random.Random(SEED * 7 + 1)
    bench = ArcBench(dut, W, seed=SEED + 11)
    await bench.start()
    cmds = []
    for cw in (0, 1):
        for qs in range(4):
            for qe in range(4):
                for _ in range(2):
                    cmds.append(arc_for_quadrants(rng, W, qs, qe, cw, 1.5, 120))
    rng.shuffle(cmds)
    await run_accepted(dut, bench, cmds, "quadrant pairs", valid_idle=0.3, en_idle=0.25)


@cocotb.test()
async def radii_to_width_limit(dut):
    """Short and long arcs on radii from 1 up to the largest the width allows."""
    bind(dut)
    rng = random.Random(SEED * 13 + 5)
    bench = ArcBench(dut, W, seed=SEED + 23)
    await bench.start()
    rmax = math.sqrt(limits(W)[1])
    cmds = []
    for k in range(24):
        # radii spread logarithmically up to the limit
        r = min(rmax, 2 ** rng.uniform(0, math.log2(rmax)))
        moves = rng.randint(3, 250)
        cmds.append(short_arc(rng, W, r, moves))
    cmds.append(short_arc(rng, W, rmax, 40))             # the largest radius
    half = 1 << (W - 1)
    cmds.append((0, half - 2, 0, half - 2, 40))          # R = M - 2 on an axis
    cmds.append((1, -(half - 2), 0, -(half - 2), 3))
    results, stats = await bench.run(cmds, valid_idle=0.2, en_idle=0.2)
    check_results(results, cmds)
    for r in results:
        cw, xs, ys, xe, ye = r.cmd
        if not r.rejected:
            fx, fy = r.moves[-1]
            assert max(abs(fx - xe), abs(fy - ye)) <= 1, f"{r.cmd} stopped at {r.moves[-1]}"
    dut._log.info("radii: %d arcs, %d moves", len(cmds), stats.moves)


@cocotb.test()
async def rejects_then_valid(dut):
    """Each reject case makes no move, reports its code, and the next runs; a start
    just inside the range limit runs."""
    bind(dut)
    bench = ArcBench(dut, W, seed=SEED + 31)
    await bench.start()
    half = 1 << (W - 1)
    bad = [
        ((0, 0, 0, 5, 0), ERR_RADIUS_ZERO),
        ((1, 0, 0, 0, 0), ERR_RADIUS_ZERO),
        ((0, half - 1, 0, half - 1, 0), ERR_RANGE),         # R = M - 1
        ((0, -half, 0, -half, 0), ERR_RANGE),               # most negative field
        ((1, half - 1, half - 1, half - 1, half - 1), ERR_RANGE),
        # R^2 = (M - 2)^2 + ys^2 just above the limit (M - 1)(M - 2), one
        # move from the end (found by mutation testing: R^2 with bit 15
        # cleared in the range check at W = 16 passed it)
        ((0, half - 2, math.isqrt(half - 2) + 1, half - 2, math.isqrt(half - 2) + 2),
         ERR_RANGE),
        ((0, 100, 0, 0, 103), ERR_END_OFF),                 # 3 BLU outside
        ((1, 100, 0, 0, 98), ERR_END_OFF),                  # 2 BLU inside
        ((0, 5, 0, -5, 5), ERR_END_OFF),
        ((0, 1, 0, 2, 2), ERR_END_OFF),
    ]
    # starts with R^2 within 4 of the limit: a short arc when at or below it, a
    # reject above it
    for x, y, above in range_edge_points(W):
        if above > 0:
            bad.append(((1, x, y, x, y), ERR_RANGE))
            continue
        run = ArcRun(x, y, x, y, 1, W)
        for _ in range(3):
            run.move()
        assert validate(x, y, run.x, run.y, W) == 0
        bad.append(((1, x, y, run.x, run.y), 0))
    good = (0, 7, 3, -3, 7)
    cmds = []
    for cmd, _ in bad:
        cmds += [cmd, good]
    results, _ = await bench.run(cmds, valid_idle=0.1)
    check_results(results, cmds)
    for k, (cmd, code) in enumerate(bad):
        r_bad, r_good = results[2 * k], results[2 * k + 1]
        assert r_bad.rejected == code, f"{cmd}: code {r_bad.rejected}, expected {code}"
        if code:
            assert r_bad.moves == [], f"{cmd} moved"
        else:
            assert r_bad.finished and len(r_bad.moves) == 3, f"{cmd}: {len(r_bad.moves)} moves"
        assert not r_good.rejected and r_good.finished


@cocotb.test()
async def back_to_back(dut):
    """Commands queued ahead run with exactly one clock without a move between
    them: the next arc enters only an idle run stage, at the edge after the
    running arc's last move (its start point shows in that clock)."""
    bind(dut)
    rng = random.Random(SEED * 17 + 3)
    bench = ArcBench(dut, W, seed=SEED + 41)
    await bench.start()
    lat = validate_latency(W)
    cmds = []
    while len(cmds) < 12:
        c = arc_for_quadrants(rng, W, rng.randrange(4), rng.randrange(4), rng.randint(0, 1), 20, 60)
        if len(arc_points(*c[1:], c[0], W)) - 1 > lat + 2:
            cmds.append(c)
    results, stats = await bench.run(cmds)
    check_results(results, cmds)
    span = stats.last_done - stats.first_move + 1
    idle = span - stats.moves
    assert idle == len(cmds) - 1, f"{idle} idle clocks between the first and last move"
    dut._log.info("back to back: %d arcs, %d moves in %d clocks", len(cmds), stats.moves, span)


def tolerance_edge_commands(width: int) -> list[tuple[int, int, int, int, int]]:
    """End points whose deviation |xe^2 + ye^2 - R^2| is exactly the tolerance
    2 max(|xs|, |ys|) (accepted) or one more (rejected), on both sides of the
    circle: every such end around a few small starts, and, near the largest
    coordinates, starts (a, 1) and (a, 0) with clockwise ends one step away
    (deviations +2a, -2a and 2a + 1), where the checks' carries run through
    every bit; and the closest end beyond the tolerance on each side of the
    small circles."""
    cmds = []
    for xs, ys in ((5, 0), (7, 3), (-4, 6), (2, -9), (-11, -11)):
        r2, tol = xs * xs + ys * ys, 2 * max(abs(xs), abs(ys))
        span = abs(xs) + abs(ys) + 2
        nearest = {}                # side -> (|deviation| - tol, end) beyond tol
        for xe in range(-span, span + 1):
            for ye in range(-span, span + 1):
                dev = xe * xe + ye * ye - r2
                if abs(dev) in (tol, tol + 1):
                    cmds.append((1, xs, ys, xe, ye))
                elif abs(dev) > tol:
                    side = dev > 0
                    if side not in nearest or abs(dev) - tol < nearest[side][0]:
                        nearest[side] = (abs(dev) - tol, (xe, ye))
        # the closest rejected end on each side (there is none at tol + 1
        # inside these circles)
        cmds += [(1, xs, ys, xe, ye) for _, (xe, ye) in sorted(nearest.values())]
    a = (1 << (width - 2)) + 12345 % (1 << (width - 3))
    for sign in (1, -1):
        cmds.append((1, sign * a, sign, sign * (a + 1), 0))    # +tol: accepted
        cmds.append((1, sign * a, sign, sign * (a - 1), 0))    # -tol: accepted
        cmds.append((1, sign * a, 0, sign * (a + 1), 0))       # tol + 1: rejected
    return cmds


@cocotb.test()
async def tolerance_edges(dut):
    """End points exactly at the tolerance of reject code 3 and just beyond,
    on both sides of the circle and on radii of every magnitude, and
    accepted ends across every power-of-two boundary of R^2 (found by
    mutation testing: no rejected end lay inside the circle, and the checks'
    carries at the higher bits were not exercised)."""
    bind(dut)
    bench = ArcBench(dut, W, seed=SEED + 53)
    await bench.start()
    rng = random.Random(SEED * 37 + 1)
    cmds = (tolerance_edge_commands(W) + tolerance_family_commands(rng, W)
            + square_boundary_commands(rng, W))
    results, _ = await bench.run(cmds, valid_idle=0.1)
    check_results(results, cmds)
    codes = [r.rejected for r in results]
    expected = [validate(*c[1:], W) for c in cmds]
    assert codes == expected
    assert ERR_END_OFF in codes and 0 in codes, "both sides of the edge"
    dut._log.info("tolerance edges: %d commands, %d rejected", len(cmds), codes.count(ERR_END_OFF))


def control_commands(rng: random.Random, width: int, count: int) -> list[tuple]:
    """Commands for control_and_sequencing: short arcs over every quadrant pair
    on small radii (a few to about 30 moves), small full circles, and commands
    the validator rejects (radius zero, end point off the circle, fields at
    random over the whole width)."""
    half = 1 << (width - 1)
    cmds = []
    while len(cmds) < count:
        kind = rng.random()
        if kind < 0.6:
            cmds.append(arc_for_quadrants(rng, width, rng.randrange(4), rng.randrange(4),
                                          rng.randint(0, 1), 1.0, 6.0))
        elif kind < 0.75:
            r = rng.randint(1, 4)
            cmds.append(full_circle(r, rng.choice((0.0, 0.7 + r * 0.37)), rng.randint(0, 1)))
        elif kind < 0.85:
            cmds.append((rng.randint(0, 1), 0, 0, rng.randint(-9, 9), rng.randint(-9, 9)))
        elif kind < 0.93:
            xs, ys = rng.randint(-9, 9) or 3, rng.randint(-9, 9)
            cmds.append((rng.randint(0, 1), xs, ys, xs + rng.choice((-4, 4)), -ys))
        else:
            cmds.append((rng.randint(0, 1),) + tuple(rng.randrange(-half, half)
                                                    for _ in range(4)))
    return cmds


def next_move_view(run) -> dict:
    """The combinational next-move outputs the model implies for the running
    arc: nx_step (X bit 0, Y bit 1) and nx_diag from the next move (peek);
    nx_dir the direction each axis steps in in the current quadrant (the
    README's table: B steps u towards the axis, C steps v away from it),
    which for a stepping axis is the sign of its step."""
    from halfpoint.spec.arc import MOVE_A, u_is_x

    kind, dx, dy = run.peek()
    x_positive = run.q in (0, 3)
    y_positive = run.q < 2
    if u_is_x(run.q, run.cw):
        dir_x, dir_y = not x_positive, y_positive
    else:
        dir_x, dir_y = x_positive, not y_positive
    assert (dx == 0 or (dx > 0) == dir_x) and (dy == 0 or (dy > 0) == dir_y), "model"
    return {"nx_step": int(dx != 0) | int(dy != 0) << 1,
            "nx_dir": int(dir_x) | int(dir_y) << 1,
            "nx_diag": int(kind == MOVE_A)}


@cocotb.test()
async def control_and_sequencing(dut):
    """rst, abort_now, start_en, en and s_valid at random on every clock, with
    short arcs, small full circles and rejected commands: every output equals
    the model on every clock, and so do the sequencing outputs the motion core
    uses (running, pending, loading, ending, and nx_step / nx_dir / nx_diag
    while running).  The other tests hold start_en high and abort_now low and
    read no sequencing output (as the line unit's control_and_sequencing)."""
    import copy

    from cocotb.triggers import FallingEdge, ReadOnly
    from halfpoint.spec.arc import V_HOLD

    bind(dut)
    rng = random.Random(SEED * 19 + 7)
    bench = ArcBench(dut, W, seed=SEED + 61)
    await bench.start()
    model = bench.model
    fields = ArcBench.FIELDS
    pool = control_commands(rng, W, 200)
    counts = {"abort": 0, "reject": 0, "done": 0, "loading": 0, "reloaded": 0,
              "stalled": 0, "diagonal": 0}
    for cycle in range(4000):
        await FallingEdge(dut.clk)
        r = rng.random()
        if rng.random() < 0.5:
            inp = bench.command_inputs(rng.choice(pool))
        else:
            inp = bench.idle_inputs()
        inp.en = int(rng.random() < 0.8)
        inp.rst = int(r < 0.003)
        inp.start_en = int(rng.random() < 0.7)
        inp.abort = int(0.003 <= r < 0.015)
        bench.drive(inp)
        await ReadOnly()
        got = bench._read()
        exp = vars(model.outputs(abort=inp.abort))
        bad = [k for k in fields if got[k] != exp[k]]
        assert not bad, f"cycle {cycle}: " + ", ".join(
            f"{k}: rtl={got[k]} model={exp[k]}" for k in bad)
        run = model.run
        running = run is not None
        pending = model.vstate == V_HOLD
        ending = False
        if running and inp.en and not inp.abort:
            ahead = copy.copy(run)
            ahead.advance()
            ending = ahead.done
        # the pending arc enters only an idle run stage (not at a last move)
        loading = pending and bool(inp.start_en) and not inp.abort and not running
        seq = {"running": int(running), "pending": int(pending),
               "ending": int(ending), "loading": int(loading)}
        if running:
            seq.update(next_move_view(run))
        for k, want in seq.items():
            assert int(getattr(dut, k).value) == want, \
                f"cycle {cycle}: {k}: rtl={int(getattr(dut, k).value)} model={want}"
        counts["abort"] += inp.abort
        counts["reject"] += got["reject"]
        counts["done"] += got["done"]
        counts["loading"] += int(loading)
        # a load in the clock after a last move (the arc-to-arc boundary)
        counts["reloaded"] += int(loading and bool(got["done"]))
        counts["stalled"] += int(pending and not inp.start_en)
        counts["diagonal"] += seq.get("nx_diag", 0)
        model.clock(inp)
    dut._log.info("control mix: %s", counts)
    assert all(counts.values()), f"a case never happened: {counts}"


def large_radius_commands(rng: random.Random, width: int) -> list[tuple]:
    """Short arcs (about 8 moves) on radii from 4 up to the largest the width
    allows, two per power of two: across each of the four axes on every
    radius (B crossings with u = 1 and v = every radius, so the new frame's
    v-terms see every bit), and on the three largest radii from five angles
    in every quadrant (0.125, 0.4, 0.5, 0.6, 0.875 of it) in both directions:
    B moves with u above half the coordinate range, where the -2u terms have
    their high bits clear."""
    rmax = math.sqrt(limits(width)[1])
    radii = [r for k in range(2, width - 1) for r in (2.0 ** k + 0.37 * k, 1.5 * 2 ** k)
             if r <= rmax]
    big = [rmax, 0.93 * rmax, 0.78 * rmax]
    cmds = []

    def arc(r, theta, cw, moves=8):
        span = moves / r * 0.8
        xs, ys = start_point(rng, r, theta - (span / 2 if not cw else -span / 2), width)
        r2 = xs * xs + ys * ys
        th = math.atan2(ys, xs)
        xe, ye = nearest_on_circle(r2, th - span if cw else th + span)
        if (xe, ye) != (xs, ys) and validate(xs, ys, xe, ye, width) == 0:
            cmds.append((cw, xs, ys, xe, ye))

    for r in radii + big:
        for axis in range(4):
            arc(r, axis * math.pi / 2, rng.randint(0, 1))
    for r in big:
        for quadrant in range(4):
            for f in (0.125, 0.4, 0.5, 0.6, 0.875):
                for cw in (0, 1):
                    arc(r, (quadrant + f) * math.pi / 2, cw)
    return cmds


@cocotb.test()
async def large_radius_crossings(dut):
    """Short arcs across every axis on radii of every magnitude up to the
    width's limit, and from every octant on the largest radii.  Found by
    mutation testing: the other tests cross axes on large radii only by
    chance, and make few moves where u exceeds half the coordinate range."""
    bind(dut)
    rng = random.Random(SEED * 23 + 9)
    bench = ArcBench(dut, W, seed=SEED + 71)
    await bench.start()
    cmds = large_radius_commands(rng, W)
    await run_accepted(dut, bench, cmds, "large radii", en_idle=0.1)


def diagonal_crossing_commands(rng: random.Random, width: int) -> list[tuple]:
    """Arcs that cross an axis with an A (diagonal) move: from (a, a^2 - 1)
    the path runs along v = a^2 - 1 to u = 1 and crosses diagonally (F = -v
    there, between -2v and -v), the only way the path crosses with A.  For a
    spread of a (v with every bit below the width's top set somewhere), once
    counter-clockwise and once clockwise, about a random axis; each ends 39
    moves after the crossing (or closes as a full circle, if smaller), so
    that D1 and D2 as set by the crossing decide a few moves.  For a <= 16
    also the quarter turn from (a^2 - 1, a) to (-a, a^2 - 1): v climbs to the
    crossing's v = a^2 - 1, which is the end's ue."""
    from halfpoint.spec.arc import ArcRun

    lim = limits(width)[1]
    cmds = []
    for a in (2, 3, 4, 5, 6, 7, 11, 16, 23, 32, 45, 64, 91, 128, 181):
        xs, ys = a, a * a - 1
        if xs * xs + ys * ys > lim:
            continue
        for cw in (0, 1):
            x, y = (-xs, ys) if cw else (xs, ys)        # clockwise: mirrored
            turns = rng.randrange(4)                    # quarter turns about the centre
            for _ in range(turns):
                x, y = -y, x
            run = ArcRun(x, y, x, y, cw, width)
            for _ in range(a - 1 + 40):         # (a small circle closes: full)
                if not run.done:
                    run.move()
            cmds.append((cw, x, y, run.x, run.y))
            if a <= 16:
                # the quarter turn before: from (a^2 - 1, a) (v climbs to a^2 - 1
                # on the way) to (-a, a^2 - 1), whose ue is the v of the crossing
                xs2, ys2, xe2, ye2 = (ys, xs, -xs, ys)
                if cw:
                    xs2, xe2 = -xs2, -xe2
                for _ in range(turns):
                    xs2, ys2, xe2, ye2 = -ys2, xs2, -ye2, xe2
                cmds.append((cw, xs2, ys2, xe2, ye2))
    return cmds


@cocotb.test()
async def diagonal_crossings(dut):
    """Arcs crossing an axis with a diagonal move, on radii up to about 2^15.
    Found by mutation testing: such crossings need R^2 = v^2 + v + 1 and the
    other tests make few."""
    bind(dut)
    rng = random.Random(SEED * 29 + 11)
    bench = ArcBench(dut, W, seed=SEED + 83)
    await bench.start()
    cmds = diagonal_crossing_commands(rng, W)
    await run_accepted(dut, bench, cmds, "diagonal crossings", en_idle=0.1)


def near_end_commands(rng: random.Random, width: int, count: int) -> list[tuple]:
    """Arcs that end within a few moves of their start: a start at a random
    angle on a radius spread logarithmically up to the width's limit (a fifth
    of them near a diagonal on the largest radii, where u and v both exceed
    half the coordinate range), the end
    1 to 4 moves along the path, or that point moved by one BLU (kept when
    the validator accepts it and the arc stops within 8 moves).  The start's comparison flags (u, v against
    the end's ue, ve, ue + 1, ve - 1) then decide the stop directly."""
    from halfpoint.spec.arc import ArcRun

    rmax = math.sqrt(limits(width)[1])
    cmds = []
    while len(cmds) < count:
        if len(cmds) < count // 5:      # near a diagonal on the largest radii
            r = rng.uniform(0.75, 1.0) * rmax
            theta = (rng.randrange(4) + 0.5) * math.pi / 2 + rng.uniform(-0.08, 0.08)
        else:
            r = min(rmax, 2 ** rng.uniform(0, math.log2(rmax)))
            theta = rng.uniform(0, 2 * math.pi)
        xs, ys = start_point(rng, r, theta, width)
        cw = rng.randint(0, 1)
        run = ArcRun(xs, ys, xs, ys, cw, width)
        for _ in range(rng.randint(1, 4)):
            run.move()
        xe, ye = run.x, run.y
        if rng.random() < 0.5:
            xe += rng.choice((-1, 0, 1))
            ye += rng.choice((-1, 0, 1))
        if (xe, ye) == (xs, ys) or validate(xs, ys, xe, ye, width):
            continue
        check = ArcRun(xs, ys, xe, ye, cw, width)
        for _ in range(8):
            if not check.done:
                check.move()
        if check.done:              # not an end behind the start (a full turn)
            cmds.append((cw, xs, ys, xe, ye))
    return cmds


def crossing_end_commands(rng: random.Random, width: int) -> list[tuple]:
    """Arcs that cross one axis and end 1 to 4 moves after it: the start 2 to
    20 moves before the axis, on a radius between 2^k and 2^(k+1) for every
    k the width allows (four arcs each), the end on the path or one BLU off it
    (when accepted).  The end's ue is then close to the v the path has at the
    crossing, so the comparisons of v, v + 1 with ue (start flags and their
    look-ahead through the v-moves before the axis) decide the stop."""
    from halfpoint.spec.arc import ArcRun

    rmax = math.sqrt(limits(width)[1])
    cmds = []
    for k in range(1, width - 1):
        for _ in range(4):
            r = min(rmax, rng.uniform(2 ** k, 2 ** (k + 1)))
            cw = rng.randint(0, 1)
            sense = -1 if cw else 1
            axis = rng.randrange(4) * math.pi / 2
            before = rng.randint(2, 20)
            xs, ys = start_point(rng, r, axis - sense * min(before / r, 1.2), width)
            run = ArcRun(xs, ys, xs, ys, cw, width)
            q = run.q
            while run.q == q and not run.done:
                run.move()
            for _ in range(rng.randint(0, 3)):
                run.move()
            xe, ye = run.x, run.y
            if rng.random() < 0.5:
                xe += rng.choice((-1, 0, 1))
                ye += rng.choice((-1, 0, 1))
            if (xe, ye) == (xs, ys) or validate(xs, ys, xe, ye, width):
                continue
            check = ArcRun(xs, ys, xe, ye, cw, width)
            for _ in range(run.moves + 4):
                if not check.done:
                    check.move()
            if check.done:
                cmds.append((cw, xs, ys, xe, ye))
    # radii 2^k .. 2^(k+1), k = 6 .. min(16, W - 2): from a start whose v is 70 below the
    # radius (v climbs past ue - 65 .. ue - 1 before the axis) to the point
    # just after the crossing moved one BLU outward along its u axis (ue one
    # above the path's u there), when accepted
    # (k up to 16 where the width allows: bit 14 of ue - 2 decides the look-ahead's
    # v + 1 == ue at W = 16 only on radii of 2^14 and more, found by mutation
    # testing; at 70 below, a radius of 2^17 costs about 4,300 moves)
    hits = dict.fromkeys(range(6, min(17, width - 1)), 0)
    for k, _ in ((k, t) for k in hits for t in range(12)):
        if hits[k] == 2:                # two per k (of at most 12 tries)
            continue
        r = min(rng.uniform(2 ** k, 2 ** (k + 1)), rmax - 1)
        cw = rng.randint(0, 1)
        sense = -1 if cw else 1
        axis = rng.randrange(4) * math.pi / 2
        xs, ys = start_point(rng, r, axis - sense * math.acos((r - 70) / r), width)
        run = ArcRun(xs, ys, xs, ys, cw, width)
        q = run.q
        while run.q == q:
            run.move()
        xe, ye = run.x, run.y
        if run.u == abs(xe):
            xe += 1 if xe > 0 else -1
        else:
            ye += 1 if ye > 0 else -1
        if validate(xs, ys, xe, ye, width) == 0:
            cmds.append((cw, xs, ys, xe, ye))
            hits[k] += 1
    return cmds


@cocotb.test()
async def near_ends(dut):
    """Arcs ending within a few moves of their start on radii up to the
    width's limit, and arcs ending a few moves after an axis crossing.  Found
    by mutation testing: the start's end-comparison flags decide these stops
    before the look-ahead replaces them, and the flags of v against ue decide
    where an arc entering E's quadrant stops."""
    bind(dut)
    rng = random.Random(SEED * 31 + 13)
    bench = ArcBench(dut, W, seed=SEED + 97)
    await bench.start()
    cmds = near_end_commands(rng, W, 150) + crossing_end_commands(rng, W)
    await run_accepted(dut, bench, cmds, "near ends", en_idle=0.1)


def square_boundary_commands(rng: random.Random, width: int) -> list[tuple]:
    """Accepted commands whose R^2 and |E|^2 lie on the two sides of a
    boundary B = odd * 2^j, for every j up to the largest R^2: one with
    |E|^2 < B <= R^2 and one with R^2 < B <= |E|^2, so that the end check's
    carries run into bit j from either operand.  Start (a, y), y in 0..2, and
    an end one BLU away on an axis direction, turned about the centre by a
    random quarter turn; each arc stops within 8 moves."""
    from halfpoint.spec.arc import ArcRun

    lim = limits(width)[1]
    cmds = []
    for j in range(1, 2 * width - 2):
        if (1 << j) > lim:
            break
        top = max(0, (lim >> j) - 1) // 2
        b = (2 * rng.randint(0, top) + 1) << j
        found = {}
        root = math.isqrt(b)
        for a in range(max(1, root - 1), root + 2):
            for y in (0, 1, 2):
                for xe, ye in ((a - 1, y), (a + 1, y), (a, y - 1), (a, y + 1),
                               (a - 1, y + 1), (a + 1, y - 1)):
                    r2, e2 = a * a + y * y, xe * xe + ye * ye
                    if r2 > lim or validate(a, y, xe, ye, width):
                        continue
                    side = "inside" if e2 < b <= r2 else "outside" if r2 < b <= e2 else None
                    if side is None or side in found:
                        continue
                    for cw in (0, 1):
                        check = ArcRun(a, y, xe, ye, cw, width)
                        for _ in range(8):
                            if not check.done:
                                check.move()
                        if check.done:
                            found[side] = (cw, a, y, xe, ye)
                            break
        for cw, xs, ys, xe, ye in found.values():
            for _ in range(rng.randrange(4)):
                xs, ys, xe, ye = -ys, xs, -ye, xe
            cmds.append((cw, xs, ys, xe, ye))
    return cmds


def tolerance_family_commands(rng: random.Random, width: int) -> list[tuple]:
    """For a start magnitude a with its top bit at every position the width
    allows (the rest random), the five ends around (a, y) whose deviation is
    at the tolerance t = 2a or just beyond, on both sides of the circle:
    (a, 1) -> (a + 1, 0) at +t and (a, 1) -> (a - 1, 0) at -t (accepted),
    (a, 0) -> (a + 1, 0) at t + 1 and (a, 2) -> (a + 1, 2) at t + 1, and
    (a, 2) -> (a - 1, 1) at -(t + 2) (rejected: an end inside the circle;
    -(t + 1) has no lattice point there); and near the diagonal, (d, d + 1)
    and (d + 1, d) -> (d + 1, d + 1) at 2d + 1, within t = 2d + 2 only if
    the larger magnitude is taken (accepted).  Each turned about the centre by a
    random quarter turn; the accepted ones in the direction that stops
    within 8 moves.  Two more magnitudes per position, one even and one odd,
    with the four forms around the axis."""
    from halfpoint.spec.arc import ArcRun

    lim = limits(width)[1]
    cmds = []
    for k in range(1, width - 1):
        a = rng.randrange(1 << k, 1 << (k + 1))
        while a * a + 4 > lim:
            a -= 1
        d = min(a, math.isqrt(lim // 2) - 1)        # near the diagonal
        forms = [(a, 1, a + 1, 0), (a, 1, a - 1, 0), (a, 0, a + 1, 0), (a, 2, a + 1, 2),
                 (a, 2, a - 1, 1), (d, d + 1, d + 1, d + 1), (d + 1, d, d + 1, d + 1)]
        # two more magnitudes, one even and one odd (the parity of the squares
        # sets the checks' lowest carries), with the four forms around the axis
        for parity in (0, 1):
            b = rng.randrange(1 << k, 1 << (k + 1)) // 2 * 2 + parity
            while b * b + 4 > lim:
                b -= 2
            forms += [(b, 1, b + 1, 0), (b, 1, b - 1, 0), (b, 0, b + 1, 0), (b, 2, b - 1, 1)]
        for xs, ys, xe, ye in forms:
            first = rng.randint(0, 1)
            cw = first
            if validate(xs, ys, xe, ye, width) == 0:
                cw = None
                for sense in (first, 1 - first):
                    check = ArcRun(xs, ys, xe, ye, sense, width)
                    for _ in range(8):
                        if not check.done:
                            check.move()
                    if check.done:
                        cw = sense
                        break
                if cw is None:
                    continue
            for _ in range(rng.randrange(4)):
                xs, ys, xe, ye = -ys, xs, -ye, xe
            cmds.append((cw, xs, ys, xe, ye))
    return cmds


@cocotb.test()
async def long_quadrant(dut):
    """One arc across an axis on a radius above half the coordinate range (at
    W <= 16; 2^10 at wider widths, where such a radius takes too many moves),
    run on to 50 degrees past the axis: the new quadrant's first B moves come
    after its diagonal, some 0.7 R moves after the crossing, and use the -2u
    term set up at the crossing from v's high bits.  Found by mutation
    testing: the other tests' arcs on such radii are short."""
    bind(dut)
    rng = random.Random(SEED * 41 + 17)
    bench = ArcBench(dut, W, seed=SEED + 101)
    await bench.start()
    r = 0.52 * 2 ** (W - 1) if W <= 16 else 2.0 ** 10
    cw = rng.randint(0, 1)
    axis = rng.randrange(4) * math.pi / 2
    sense = -1 if cw else 1
    xs, ys = start_point(rng, r, axis - sense * 4 / r, W)
    xe, ye = nearest_on_circle(xs * xs + ys * ys, axis + sense * math.radians(50))
    cmds = [(cw, xs, ys, xe, ye)]
    results, stats = await bench.run(cmds)
    check_results(results, cmds)
    dut._log.info("long quadrant: %s, %d moves", cmds[0], stats.moves)


@cocotb.test()
async def wide_start_u(dut):
    """Arcs that start with u above a quarter of the coordinate range (above
    2^(W-2) + 1) where B moves come first, in both directions and every
    quadrant: the load computes Q1 = 2 - 2u, whose bit W - 1 is clear only
    there (and at u = 1, where a B move is a crossing that replaces it), so
    its B moves are the first to add a Q1 set up from u's high bits.  Found
    by mutation testing: bit 0 of the load's Q1 inverted while its bit W - 1
    is clear ran every other test."""
    bind(dut)
    rng = random.Random(SEED * 43 + 19)
    bench = ArcBench(dut, W, seed=SEED + 103)
    await bench.start()
    radius = 0.95 * 2 ** (W - 1)
    cmds = []
    for quadrant in range(4):
        for cw in (0, 1):
            # u = radius cos(a), v = radius sin(a), a the angle from u's axis:
            # a = 52 degrees puts u at 0.58 * 2^(W-1) with v > u (B moves)
            frame = math.radians(52 + rng.uniform(-2, 2))
            base = quadrant * math.pi / 2
            theta = base + (frame if not cw else math.pi / 2 - frame)
            xs, ys = start_point(rng, radius, theta, W)
            moves = 300
            span = moves / (math.sqrt(xs * xs + ys * ys) * 4 * math.sqrt(2) / (2 * math.pi))
            xe, ye = nearest_on_circle(xs * xs + ys * ys, theta - span if cw else theta + span)
            cmds.append((cw, xs, ys, xe, ye))
    await run_accepted(dut, bench, cmds, "wide start u", valid_idle=0.1, en_idle=0.1)


@cocotb.test()
async def start_past_end(dut):
    """A start in the end point's quadrant and octant that lies past the end
    in its progress order (v > ve, first octant): the arc is not armed and
    runs almost the full circle.  Here v = 300 has bit 8 set and v - 256 <
    ve = 50 (found by mutation testing: a mutant that clears bit 8 of v in
    the compare v < ve armed the arc and stopped it after one move)."""
    bind(dut)
    bench = ArcBench(dut, W, seed=SEED + 71)
    await bench.start()
    cmds = [(0, 400, 300, 497, 50), (1, 300, 400, 50, 497)]
    results, stats = await run_accepted(dut, bench, cmds, "start past end")
    for r in results:
        assert len(r.moves) > 2000, f"{r.cmd}: {len(r.moves)} moves, not the long way round"


@cocotb.test()
async def every_small_arc(dut):
    """Every command with its start and end coordinates in -2..2 that the
    validator accepts, in both directions (888 arcs): ends on and just off
    the circle on either side of the start, in every quadrant and octant
    relation, so that each of the pending slot's flags (v against ve, u
    against ue, v against ue: <, = and one apart) decides the arming or the
    stop somewhere (found by mutation testing: a mutant that took u < ue for
    u > ue in the start's progress order survived every other test)."""
    bind(dut)
    bench = ArcBench(dut, W, seed=SEED + 103)
    await bench.start()
    cmds = [(cw, xs, ys, xe, ye) for cw in (0, 1)
            for xs, ys, xe, ye in itertools.product(range(-2, 3), repeat=4)
            if validate(xs, ys, xe, ye, W) == 0]
    assert len(cmds) == 888
    await run_accepted(dut, bench, cmds, "every small arc", valid_idle=0.05)


@cocotb.test()
async def axis_starts(dut):
    """Short arcs (five moves) from starts on an axis at every power of two
    up to the width's limit, (±2^k, 0) and (0, ±2^k), both directions: the
    radius-zero check sees one coordinate zero and the other with a single
    bit set (found by mutation testing: a mutant that forced bit 3 of |ys| to
    0 in the check |ys| == 0 rejected the start (0, 8) with code 1)."""
    from halfpoint.spec.arc import ArcRun

    bind(dut)
    bench = ArcBench(dut, W, seed=SEED + 83)
    await bench.start()
    cmds = []
    for k in range(W - 2):
        r = 1 << k
        for xs, ys in ((r, 0), (-r, 0), (0, r), (0, -r)):
            for cw in (0, 1):
                run = ArcRun(xs, ys, xs, ys, cw, W)
                for _ in range(5):
                    if not run.done:        # radius 1: the full circle has 4 moves
                        run.advance()
                cmds.append((cw, xs, ys, run.x, run.y))
    await run_accepted(dut, bench, cmds, "axis starts")


@cocotb.test()
async def ends_at_the_origin(dut):
    """Ends at the centre, which the tolerance accepts on the smallest circles
    (R^2 <= 2 max(|xs|, |ys|)): the end's frame is u = v = 0, the only end
    with ue = 0 (found by mutation testing: a mutant computing ue == 0 as
    never true survived every other test)."""
    bind(dut)
    bench = ArcBench(dut, W, seed=SEED + 97)
    await bench.start()
    starts = [(xs, ys) for xs in range(-2, 3) for ys in range(-2, 3)
              if (xs, ys) != (0, 0) and xs * xs + ys * ys <= 2 * max(abs(xs), abs(ys))]
    assert len(starts) == 12         # (±1, 0), (0, ±1), (±1, ±1), (±2, 0), (0, ±2)
    cmds = [(cw, xs, ys, 0, 0) for xs, ys in starts for cw in (0, 1)]
    await run_accepted(dut, bench, cmds, "ends at the origin")



@cocotb.test()
async def octant_order_ends_every_bit(dut):
    """Short arcs to ends off the path next to the octant boundary, for each
    bit of ve and ue and each way a stuck bit would turn the compare ve <= ue
    that picks the end's progress order, where the other order stops at
    another move (``arcgen.octant_order_ends``; found by mutation testing: a
    mutant that cleared bit 10 of ve in that compare survived every other
    test, as no other test ends off the path where the order decides)."""
    bind(dut)
    bench = ArcBench(dut, W, seed=SEED + 101)
    await bench.start()
    cmds = octant_order_ends(random.Random(SEED + 101), W)
    await run_accepted(dut, bench, cmds, "octant order ends")
