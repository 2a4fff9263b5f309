# SPDX-License-Identifier: Apache-2.0
"""cocotb tests of halfpoint_arc: the RTL against the model on every clock.

Run by ``test_arc_rtl.py`` (pytest) through cocotb's Python runner; the
coordinate width is read from the design (its parameter W).
"""

from __future__ import annotations

import math
import os
import random

import cocotb

from arcgen import arc_for_quadrants, full_circle, short_arc
from halfpoint.spec.arc import (
    ERR_END_OFF, ERR_RADIUS_ZERO, ERR_RANGE, arc_points, limits, validate, validate_latency,
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


@cocotb.test()
async def full_circles(dut):
    """Every full circle of radius 1..64, both directions, on and off an axis."""
    bind(dut)
    bench = ArcBench(dut, W, seed=SEED)
    await bench.start()
    cmds = []
    for r in range(1, 65):
        for cw in (0, 1):
            cmds.append(full_circle(r, 0.0, cw))
            cmds.append(full_circle(r, 0.7 + r * 0.37, cw))
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
    results, stats = await bench.run(cmds, valid_idle=0.3, en_idle=0.25)
    check_results(results, cmds)
    assert not any(r.rejected for r in results)
    dut._log.info("quadrant pairs: %d arcs, %d moves, %d cycles", len(cmds), stats.moves, stats.cycles)


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
    """Each reject case makes no move, reports its code, and the next runs."""
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
        ((0, 100, 0, 0, 103), ERR_END_OFF),                 # 3 BLU outside
        ((1, 100, 0, 0, 98), ERR_END_OFF),                  # 2 BLU inside
        ((0, 5, 0, -5, 5), ERR_END_OFF),
        ((0, 1, 0, 2, 2), ERR_END_OFF),
    ]
    good = (0, 7, 3, -3, 7)
    cmds = []
    for cmd, _ in bad:
        cmds += [cmd, good]
    results, _ = await bench.run(cmds, valid_idle=0.1)
    check_results(results, cmds)
    for k, (cmd, code) in enumerate(bad):
        r_bad, r_good = results[2 * k], results[2 * k + 1]
        assert r_bad.rejected == code, f"{cmd}: code {r_bad.rejected}, expected {code}"
        assert r_bad.moves == [], f"{cmd} moved"
        assert not r_good.rejected and r_good.finished


@cocotb.test()
async def back_to_back(dut):
    """Commands queued ahead run with no idle clock between them."""
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
    assert stats.moves == span, f"{span - stats.moves} idle clocks between the first and last move"
    dut._log.info("back to back: %d arcs, %d moves in %d clocks", len(cmds), stats.moves, span)


def tolerance_edge_commands(width: int) -> list[tuple[int, int, int, int, int]]:
    """End points whose deviation |xe^2 + ye^2 - R^2| is exactly the tolerance
    2 max(|xs|, |ys|) (accepted) or one more (rejected), on both sides of the
    circle: every such end around a few small starts, and, near the largest
    coordinates, starts (a, 1) and (a, 0) with clockwise ends one step away
    (deviations +2a, -2a and 2a + 1), where the checks' carries run through
    every bit."""
    cmds = []
    for xs, ys in ((5, 0), (7, 3), (-4, 6), (2, -9), (-11, -11)):
        r2, tol = xs * xs + ys * ys, 2 * max(abs(xs), abs(ys))
        span = abs(xs) + abs(ys) + 2
        for xe in range(-span, span + 1):
            for ye in range(-span, span + 1):
                if abs(xe * xe + ye * ye - r2) in (tol, tol + 1):
                    cmds.append((1, xs, ys, xe, ye))
    a = (1 << (width - 2)) + 12345 % (1 << (width - 3))
    for sign in (1, -1):
        cmds.append((1, sign * a, sign, sign * (a + 1), 0))    # +tol: accepted
        cmds.append((1, sign * a, sign, sign * (a - 1), 0))    # -tol: accepted
        cmds.append((1, sign * a, 0, sign * (a + 1), 0))       # tol + 1: rejected
    return cmds


@cocotb.test()
async def tolerance_edges(dut):
    """End points exactly at the tolerance of reject code 3 and one beyond."""
    bind(dut)
    bench = ArcBench(dut, W, seed=SEED + 53)
    await bench.start()
    cmds = tolerance_edge_commands(W)
    results, _ = await bench.run(cmds, valid_idle=0.1)
    check_results(results, cmds)
    codes = [r.rejected for r in results]
    expected = [validate(*c[1:], W) for c in cmds]
    assert codes == expected
    assert ERR_END_OFF in codes and 0 in codes, "both sides of the edge"
    dut._log.info("tolerance edges: %d commands, %d rejected", len(cmds), codes.count(ERR_END_OFF))
