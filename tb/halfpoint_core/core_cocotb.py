# SPDX-License-Identifier: Apache-2.0
"""cocotb tests of halfpoint_core: model equality on every clock (positions,
STEP/DIR pins, status), independent pin timing checks, and end results."""

from __future__ import annotations

import os
import random

import cocotb
from cocotb.triggers import FallingEdge

from halfpoint.spec import encoding as enc
from halfpoint.sim.corebench import CoreBench
from halfpoint.sim.design import read_parameters
from halfpoint.spec.rules import wrap
from halfpoint.spec.program import expect, random_arc, random_line
from halfpoint.spec.stepgen import StepCfg

NA = W = DEPTH = TW = 0     # the design's parameters: bind() reads them
SEED = int(os.environ.get("HP_SEED", "1"))


def bind(dut) -> None:
    """Take NA, W, DEPTH, TW from the design under test (its parameters)."""
    global NA, W, DEPTH, TW
    NA, W, DEPTH, TW = read_parameters(dut, "NA", "W", "DEPTH", "TW")


def rate(rng, lo=0.2, hi=2.0):
    return int(rng.uniform(lo, hi) * enc.RATE_ONE)


def random_cfg(rng):
    return [StepCfg(rng.randint(1, 3), rng.randint(0, 3), rng.randint(0, 3), rng.randint(0, 3),
                    rng.randint(0, 1), rng.randint(0, 1)) for _ in range(NA)]


def check_end(bench, cmds):
    """Positions, final position, error codes and pin-counted steps as the
    host expects them."""
    trace, final, errors = expect(cmds, NA, W)
    assert bench.trace == trace, "positions after the moves differ from the host's expectation"
    assert bench.last["pos"] == final
    assert [c for _, c in bench.errors] == errors
    for k, chk in enumerate(bench.checkers):
        assert wrap(chk.position, W) == final[k], f"axis {k}: pins say {chk.position}, pos {final[k]}"


@cocotb.test()
async def mixed_program(dut):
    """Hundreds of mixed arcs and lines at random rates, random gaps on the
    stream, random STEP/DIR timing and polarity, rejected and empty commands
    in the middle; every clock compared, every pin edge checked."""
    bind(dut)
    rng = random.Random(SEED)
    bench = CoreBench(dut, NA, W, DEPTH, TW, cfg=random_cfg(rng), seed=SEED)
    await bench.start(pause_prob=0.3)
    cmds = []
    for k in range(240):
        if rng.random() < 0.5:
            cmds.append(random_arc(rng, rate(rng)))
        else:
            cmds.append(random_line(rng, NA, rate(rng), scale=rng.choice((2, 30))))
        if k == 40:
            cmds.append(enc.encode_arc(0, -100, 0, 0, 103))           # end off the circle
        if k == 80:
            cmds.append(enc.pack([7, enc.RATE_ONE, 1, 2, 3, 0, 0, 0]))  # unknown opcode
        if k == 120:
            cmds.append(enc.encode_line([0] * NA))                    # empty: a no-op
        if k == 160:
            cmds.append(enc.encode_arc(1, 0, 0, 5, 5))                # radius zero
        if k == 200:
            cmds.append(enc.pack([enc.OP_LINE | 0x10, enc.RATE_ONE, 1, 0, 0, 0, 0, 0]))  # reserved bit
    if W < 32:
        cmds.append(enc.encode_line([1 << (W - 1)] + [0] * (NA - 1)))  # out of the width
    await bench.send(cmds)
    await bench.drain()
    check_end(bench, cmds)
    assert len(bench.errors) >= 4
    dut._log.info("mixed program: %d commands, %d moves, %d clocks", len(cmds), bench.moves, bench.cycle)


@cocotb.test()
async def queue_full_and_empty(dut):
    """A slow program fills the queue (tready low at DEPTH), then drains."""
    bind(dut)
    rng = random.Random(SEED + 1)
    bench = CoreBench(dut, NA, W, DEPTH, TW, seed=SEED + 1)
    await bench.start()
    cmds = [random_line(rng, NA, int(0.3 * enc.RATE_ONE), scale=6) for _ in range(3 * DEPTH)]
    cmds = [c for c in cmds if enc.decode(c)["deltas"][:NA] != [0] * NA]
    await bench.send(cmds)
    await bench.drain()
    check_end(bench, cmds)
    assert bench.max_level == DEPTH, f"queue reached {bench.max_level} of {DEPTH}"


@cocotb.test()
async def feed_override_and_hold(dut):
    """Live feed override: 100 %, 50 %, 0 % (hold: no move), 150 %, 200 %."""
    bind(dut)
    rng = random.Random(SEED + 2)
    bench = CoreBench(dut, NA, W, DEPTH, TW, cfg=[StepCfg(1, 0, 0, 0)] * NA, seed=SEED + 2)
    await bench.start()
    bench.override_schedule = {300: 50, 700: 0, 1100: 150, 1500: 200, 1800: 37}
    cmds = [random_arc(rng, int(0.4 * enc.RATE_ONE), rmin=20, rmax=40) for _ in range(6)]
    await bench.send(cmds)
    held = None
    while bench.cycle < 1100:
        await FallingEdge(dut.clk)
        if bench.cycle == 760:
            held = bench.moves
    assert bench.moves == held, "moves were made while the feed override was 0"
    await bench.drain()
    check_end(bench, cmds)


@cocotb.test()
async def underrun_flag(dut):
    """CONT segments with a gap in the stream set underrun; the last segment
    of a program (CONT clear) does not."""
    bind(dut)
    rng = random.Random(SEED + 3)
    bench = CoreBench(dut, NA, W, DEPTH, TW, seed=SEED + 3)
    await bench.start()
    await bench.send([random_line(rng, NA, enc.RATE_ONE, cont=False, scale=20)])
    await bench.drain()
    assert bench.last["underrun"] == 0
    cmds = [random_line(rng, NA, enc.RATE_ONE, cont=True, scale=20)]
    await bench.send(cmds)
    await bench.drain()
    assert bench.last["underrun"] == 1


@cocotb.test()
async def no_idle_clock_at_boundaries(dut):
    """With segments queued ahead, some segment is in a run stage on every
    clock from the first move to the last: a boundary between arcs and lines,
    in any order, costs no clock (read from the RTL's own run flags)."""
    bind(dut)
    rng = random.Random(SEED + 4)
    bench = CoreBench(dut, NA, W, DEPTH, TW, cfg=[StepCfg(1, 0, 0, 0)] * NA, seed=SEED + 4)
    await bench.start()
    cmds = []
    while len(cmds) < 24:
        c = random_arc(rng, 2 * enc.RATE_ONE, cont=True, rmin=12, rmax=30) if len(cmds) % 3 \
            else random_line(rng, NA, 2 * enc.RATE_ONE, cont=True, scale=60)
        n = len(expect([c], NA, W)[0])
        if n >= 50:
            cmds.append(c)
    cmds[-1] &= ~enc.FLAG_CONT          # the program's last segment
    running = []

    async def watch():
        while True:
            await FallingEdge(dut.clk)
            running.append((bench.moves, int(dut.arc_run.value) | int(dut.line_run.value)))

    cocotb.start_soon(watch())
    await bench.send(cmds)
    await bench.drain()
    check_end(bench, cmds)
    total = bench.moves
    active = [r for m, r in running if 0 < m < total]
    assert active and all(active), f"{active.count(0)} clocks without a running segment"
    assert bench.last["underrun"] == 0


@cocotb.test()
async def abort_then_new_program(dut):
    """Abort in the middle of a program (with segments queued, one in flight
    and one running): no further move, queue emptied, pulses in progress
    complete with full timing; then a new program runs from where the axes
    stopped."""
    bind(dut)
    rng = random.Random(SEED + 5)
    bench = CoreBench(dut, NA, W, DEPTH, TW, cfg=random_cfg(rng), seed=SEED + 5)
    await bench.start()
    first = [random_arc(rng, rate(rng, 0.5, 1.5), rmin=10, rmax=30) if k % 2
             else random_line(rng, NA, rate(rng, 0.5, 1.5), scale=40) for k in range(12)]
    cocotb.start_soon(bench.send(first))
    while bench.moves < 60:
        await FallingEdge(dut.clk)
    t = bench.cycle + 1
    bench.abort_schedule = {t, t + 1, t + 2}
    while bench.cycle < t + 3:
        await FallingEdge(dut.clk)
    # the source may still hold beats the core refused while aborting: let it finish
    await bench.source.wait()
    await bench.drain()
    stopped = bench.last["pos"]
    moved_before = bench.moves
    assert moved_before < len(expect(first, NA, W)[0]), "abort came too late to test anything"
    second = [random_line(rng, NA, enc.RATE_ONE, scale=20), random_arc(rng, enc.RATE_ONE)]
    bench.trace.clear()
    await bench.send(second)
    await bench.drain()
    trace, _, _ = expect(second, NA, W)
    shifted = [tuple(wrap(a + b, W) for a, b in zip(p, stopped)) for p in trace]
    assert bench.trace == shifted
    for k, chk in enumerate(bench.checkers):
        assert wrap(chk.position, W) == bench.last["pos"][k]
