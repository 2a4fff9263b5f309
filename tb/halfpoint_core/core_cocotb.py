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
from halfpoint.spec.program import (expect, move_count, profiled, random_arc,
                                    random_helix, random_line)
from halfpoint.spec.stepgen import StepCfg

NA = W = DEPTH = TW = DIV = MOVE_DEPTH = PROFILE_DEPTH = PWM_BITS = 0   # bind() reads them
SEED = int(os.environ.get("HP_SEED", "1"))
ONE = 1 << 32               # a speed field of 1 BLU per clock


def bind(dut) -> None:
    """Take the parameters from the design under test."""
    global NA, W, DEPTH, TW, DIV, MOVE_DEPTH, PROFILE_DEPTH, PWM_BITS
    NA, W, DEPTH, TW, DIV, MOVE_DEPTH, PROFILE_DEPTH, PWM_BITS = read_parameters(
        dut, "NA", "W", "DEPTH", "TW", "DIV", "MOVE_DEPTH", "PROFILE_DEPTH", "PWM_BITS")


def new_bench(dut, cfg=None, seed=SEED):
    return CoreBench(dut, NA, W, DEPTH, TW, cfg=cfg, seed=seed, div=DIV,
                     move_depth=MOVE_DEPTH, profile_depth=PROFILE_DEPTH, pwm_bits=PWM_BITS)


def speed(rng, lo=0.05, hi=0.45):
    """A random path speed field (BLU per clock x 2^32)."""
    return int(rng.uniform(lo, hi) * ONE)


def accel(rng):
    """A random speed step per tick: 0 to 0.3 BLU per clock in 20..200 ticks."""
    return int(rng.uniform(0.3 / 200, 0.3 / 20) * (1 << 38))


def plan(rng, cmds, lo=0.05, hi=0.45):
    """``cmds`` with planned PROFILEs: random cruise speeds, accelerations, junctions."""
    return profiled(cmds, NA, W, DIV, v_cruise=lambda k: speed(rng, lo, hi),
                    accel=lambda k: accel(rng), rng=rng)


def random_cfg(rng):
    return [StepCfg(rng.randint(1, 3), rng.randint(0, 3), rng.randint(0, 3), rng.randint(0, 3),
                    rng.randint(0, 1), rng.randint(0, 1)) for _ in range(NA)]


def random_pulses(rng, start, end, count, longest):
    """Cycles covered by ``count`` random pulses of up to ``longest`` cycles."""
    out = set()
    for _ in range(count):
        t = rng.randint(start, end)
        out.update(range(t, t + rng.randint(1, longest)))
    return out


def check_end(bench, cmds):
    """Positions, final position, error codes and pin-counted steps as the
    host expects them."""
    trace, final, errors = expect(cmds, NA, W)
    assert bench.trace == trace, "positions after the moves differ from the host's expectation"
    assert bench.last["pos"] == final
    # an arc's move count error comes at its last move, after the rejects of the
    # commands the dispatcher decoded meanwhile: the rejects in program order, the
    # count errors counted
    got = [c for _, c in bench.errors]
    assert [c for c in got if c != enc.E_HELIX_COUNT] == \
        [c for c in errors if c != enc.E_HELIX_COUNT]
    assert got.count(enc.E_HELIX_COUNT) == errors.count(enc.E_HELIX_COUNT)
    for k, chk in enumerate(bench.checkers):
        assert wrap(chk.position, W) == final[k], f"axis {k}: pins say {chk.position}, pos {final[k]}"


@cocotb.test()
async def mixed_program(dut):
    """Mixed arcs (XY, and helices and G18/G19 arcs where the core has the axes, two
    with a wrong move count) and lines with planned profiles (accelerations, junction
    speeds), random gaps on the stream, random STEP/DIR timing and polarity, random
    holds and override changes, rejected commands and empty ones in the middle; every
    clock compared, every pin edge checked."""
    bind(dut)
    rng = random.Random(SEED)
    bench = new_bench(dut, cfg=random_cfg(rng))
    await bench.start(pause_prob=0.3)
    cmds = []
    for k in range(80):
        choice = rng.random()
        if choice < 0.25:
            cmds.append(random_arc(rng, rmax=30))
        elif choice < 0.5 or k in (15, 45):
            cmds.append(random_helix(rng, NA, rmax=30,
                                     count_error=(-1 if k == 15 else 1 if k == 45 else 0)))
        else:
            cmds.append(random_line(rng, NA, scale=rng.choice((2, 30))))
        if k == 10:
            cmds.append(enc.encode_arc(0, -100, 0, 0, 103))           # end off the circle
        if k == 20:
            cmds.append(enc.pack([7, 0, 1, 2, 3, 0, 0, 0]))          # unknown opcode
        if k == 30:
            cmds.append(enc.encode_line([0] * NA))                    # empty: a no-op
        if k == 40:
            cmds.append(enc.encode_arc(1, 0, 0, 5, 5))                # radius zero
        if k == 50:
            cmds.append(enc.pack([enc.OP_LINE | 0x10, 0, 1, 0, 0, 0, 0, 0]))  # reserved bit
        if k == 55:         # a helix delta beyond the count (E_HELIX; E_OPCODE without slots)
            cmds.append(enc.encode_arc(0, -5, 0, 0, 5, count=3, helix=(4,)))
        if k == 60:         # an axis pair out of range, and one axis twice (E_FIELD)
            cmds.append(enc.encode_arc(0, -5, 0, 0, 5, plane=(0, NA)))
            cmds.append(enc.encode_arc(0, -5, 0, 0, 5, plane=(1, 1)))
    if W < 32:
        cmds.append(enc.encode_line([1 << (W - 1)] + [0] * (NA - 1)))  # out of the width
    prog = plan(rng, cmds)
    # a line under an arc's profile, a bad profile and the line after it
    arc_profile = next(c for c in prog if enc.decode(c)["opcode"] == enc.OP_PROFILE
                       and enc.decode(c)["line_cost"] == 0)
    prog[30:30] = [arc_profile, enc.encode_line([3] + [0] * (NA - 1)),
                   enc.encode_profile(100, 200, 1), enc.encode_line([0, 3] + [0] * (NA - 2))]
    bench.hold_schedule = random_pulses(rng, 500, 20_000, 6, 600)
    bench.override_schedule = {rng.randint(500, 20_000): rng.choice((0, 40, 100, 128, 200))
                               for _ in range(8)}
    await bench.send(prog)
    await bench.drain()
    check_end(bench, prog)
    assert {enc.E_PROFILE, enc.E_PROFILE_FIELD, enc.E_HELIX_COUNT} <= \
        {c for _, c in bench.errors}
    assert len(bench.errors) >= 7
    dut._log.info("mixed program: %d commands, %d moves, %d clocks", len(prog), bench.moves,
                  bench.cycle)


@cocotb.test()
async def queue_full_and_empty(dut):
    """A slow program fills the queue (tready low at DEPTH), then drains."""
    bind(dut)
    rng = random.Random(SEED + 1)
    bench = new_bench(dut, seed=SEED + 1)
    await bench.start()
    cmds = [random_line(rng, NA, scale=6) for _ in range(2 * DEPTH)]
    cmds = [c for c in cmds if enc.decode(c)["deltas"][:NA] != [0] * NA]
    prog = plan(rng, cmds, 0.02, 0.05)
    await bench.send(prog)
    await bench.drain()
    check_end(bench, prog)
    assert bench.max_level == DEPTH, f"queue reached {bench.max_level} of {DEPTH}"


@cocotb.test()
async def hold_resume_and_override(dut):
    """Feed hold decelerates to rest and stays there (no move while held at rest),
    resumes; override changes (0 holds the motion too); the moves are those of the
    program, every clock as the model."""
    bind(dut)
    rng = random.Random(SEED + 2)
    bench = new_bench(dut, cfg=[StepCfg(1, 0, 0, 0)] * NA, seed=SEED + 2)
    await bench.start()
    bench.hold_schedule = set(range(800, 2500))
    bench.override_schedule = {3000: 64, 3600: 0, 4600: 128, 5000: 200, 5600: 37}
    cmds = [random_arc(rng, rmin=20, rmax=40) for _ in range(6)]
    prog = plan(rng, cmds, 0.3, 0.45)
    await bench.send(prog)
    held = None
    while bench.cycle < 2500:
        await FallingEdge(dut.clk)
        if bench.last["speed"] == 0 and bench.cycle > 800 and held is None:
            held = (bench.cycle, bench.moves)
    assert held is not None and held[0] < 2000, "hold did not reach rest"
    assert bench.moves == held[1], "moves were made while held at rest"
    await bench.drain()
    check_end(bench, prog)


@cocotb.test()
async def underrun_and_dry_queue(dut):
    """A CONT segment with nothing behind it sets underrun; the last segment of a
    program (CONT clear) does not.  A segment planned to leave at speed whose
    successor comes late decelerates (dry)."""
    bind(dut)
    rng = random.Random(SEED + 3)
    bench = new_bench(dut, seed=SEED + 3)
    await bench.start()
    await bench.send(plan(rng, [random_line(rng, NA, cont=False, scale=20)]))
    await bench.drain()
    assert bench.last["underrun"] == 0 and bench.last["dry"] == 0
    first = random_line(rng, NA, cont=True, scale=300)
    second = random_line(rng, NA, scale=300)
    prog = profiled([first, second], NA, W, DIV, v_cruise=ONE // 4, accel=1 << 30,
                    junction=ONE // 4)
    await bench.send(prog[:2])
    for _ in range(3000):
        await FallingEdge(dut.clk)
    await bench.send(prog[2:])
    await bench.drain()
    assert bench.last["underrun"] == 1 and bench.last["dry"] == 1


@cocotb.test()
async def interpolators_run_ahead(dut):
    """While the move queue has room and segments are queued, the interpolators make
    a move on every clock (read from the RTL's own signals), arcs and lines in any
    order; the pins never wait for them at a feed the STEP timing allows."""
    bind(dut)
    rng = random.Random(SEED + 4)
    bench = new_bench(dut, cfg=[StepCfg(1, 0, 0, 0)] * NA, seed=SEED + 4)
    await bench.start()
    cmds = []
    while len(cmds) < 16:
        c = random_arc(rng, cont=True, rmin=12, rmax=30) if len(cmds) % 3 \
            else random_line(rng, NA, cont=True, scale=60)
        if move_count(c, NA, W) >= 50:
            cmds.append(c)
    cmds[-1] &= ~enc.FLAG_CONT          # the program's last segment
    prog = profiled(cmds, NA, W, DIV, v_cruise=ONE // 2 - 1, accel=1 << 33,
                    junction=ONE // 2 - 1)
    samples = []

    async def watch():
        while True:
            await FallingEdge(dut.clk)
            inner = bench.inner
            samples.append((bench.moves, int(inner.move_room.value), int(inner.produce.value),
                            int(inner.move_valid.value)))

    cocotb.start_soon(watch())
    await bench.send(prog)
    await bench.drain()
    check_end(bench, prog)
    total = bench.moves
    inner = [s for s in samples if 0 < s[0] < total - MOVE_DEPTH]
    room = [s for s in inner if s[1]]
    made = sum(s[2] for s in room)
    dut._log.info("moves per clock with room: %d / %d", made, len(room))
    if PROFILE_DEPTH >= 2:
        assert room and made >= 0.99 * len(room), f"{made} moves in {len(room)} clocks"
    assert all(s[3] for s in inner), "the move queue ran empty in the middle of the program"
    assert bench.last["underrun"] == 0
    # with one profile queued the look-ahead is one segment: shorter than the
    # stopping distance, the next one is not validated in time (dry, as planned)
    if PROFILE_DEPTH >= 2:
        assert bench.last["dry"] == 0


async def start_interrupted_program(bench, rng):
    """Send a 12-segment program in the background and return once 60 moves are
    made (for the stop and abort tests)."""
    first = plan(rng, [random_arc(rng, rmin=10, rmax=30) if k % 2
                       else random_line(rng, NA, scale=40) for k in range(12)], 0.2, 0.4)
    cocotb.start_soon(bench.send(first))
    while bench.moves < 60:
        await FallingEdge(bench.dut.clk)
    return first


def expected_from(cmds, start):
    """The positions the host expects after every move of ``cmds`` run from ``start``."""
    trace, _, _ = expect(cmds, NA, W)
    return [tuple(wrap(a + b, W) for a, b in zip(p, start)) for p in trace]


@cocotb.test()
async def stop_then_new_program(dut):
    """stop decelerates to rest, then drops the rest of the program; a new program
    (with its profile: the one in force is forgotten) runs from where the axes
    stopped."""
    bind(dut)
    rng = random.Random(SEED + 6)
    bench = new_bench(dut, cfg=random_cfg(rng), seed=SEED + 6)
    await bench.start()
    first = await start_interrupted_program(bench, rng)
    t = bench.cycle + 1
    bench.stop_schedule = set(range(t, t + 4000))
    while bench.cycle < t + 4000:
        await FallingEdge(dut.clk)
    await bench.source.wait()
    await bench.drain()
    stopped = bench.last["pos"]
    assert bench.moves < len(expect(first, NA, W)[0]), "stop came too late to test anything"
    second = plan(rng, [random_line(rng, NA, scale=20), random_arc(rng)])
    bench.trace.clear()
    before = len(bench.errors)
    await bench.send([enc.encode_line([1] + [0] * (NA - 1))] + second)
    await bench.drain()
    assert [c for _, c in bench.errors[before:]] == [enc.E_PROFILE]
    assert bench.trace == expected_from(second, stopped)


class StopUntilRest:
    """A stop schedule (``CoreBench.stop_schedule``) high from cycle ``start`` until
    the first cycle in which the core is at rest with its registered stop high: stop
    falls in that very cycle, so the edge ending it is the last stop at rest and the
    flush at the next edge sees the registered stop low.  ``profiles``: the model's
    profile queue then (segments the flush must drop, not take)."""

    def __init__(self, model, start):
        self.model, self.start = model, start
        self.done = False
        self.profiles = 0

    def __contains__(self, cycle):
        if self.done or cycle < self.start:
            return False
        if self.model.stop_pin and self.model.stage.v == 0:
            self.done, self.profiles = True, len(self.model.profiles)
            return False
        return True


@cocotb.test()
async def stop_released_at_rest(dut):
    """stop released in the clock the machine comes to rest: the flush still comes
    at the next edge and drops everything, the queued profiles included (the stage
    takes none of them), and a new program runs from where the axes stopped."""
    bind(dut)
    rng = random.Random(SEED + 8)
    bench = new_bench(dut, cfg=random_cfg(rng), seed=SEED + 8)
    await bench.start()
    first = await start_interrupted_program(bench, rng)
    stopper = StopUntilRest(bench.model, bench.cycle + 1)
    bench.stop_schedule = stopper
    while not stopper.done:
        await FallingEdge(dut.clk)
    await bench.source.wait()
    await bench.drain()
    stopped = bench.last["pos"]
    assert bench.moves < len(expect(first, NA, W)[0]), "stop came too late to test anything"
    assert stopper.profiles > 0, "no profile queued at the stop: nothing to drop"
    second = plan(rng, [random_line(rng, NA, scale=20), random_arc(rng)])
    bench.trace.clear()
    await bench.send(second)
    await bench.drain()
    assert bench.trace == expected_from(second, stopped)


@cocotb.test()
async def abort_then_new_program(dut):
    """Abort in the middle of a program (with segments queued, one in flight
    and one running): no further move, queue emptied, pulses in progress
    complete with full timing; then a new program runs from where the axes
    stopped."""
    bind(dut)
    rng = random.Random(SEED + 5)
    bench = new_bench(dut, cfg=random_cfg(rng), seed=SEED + 5)
    await bench.start()
    first = await start_interrupted_program(bench, rng)
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
    second = plan(rng, [random_line(rng, NA, scale=20), random_arc(rng)])
    bench.trace.clear()
    await bench.send(second)
    await bench.drain()
    assert bench.trace == expected_from(second, stopped)
    for k, chk in enumerate(bench.checkers):
        assert wrap(chk.position, W) == bench.last["pos"][k]


@cocotb.test()
async def outputs_in_program_order(dut):
    """OUTPUT commands between motion: each takes effect after every move before it and
    before any move after it; the spindle PWM's duty per period is its power (outside
    laser mode), 0 at rest in laser mode; bad OUTPUTs are rejected and change nothing;
    a stop at rest switches every output off.  Every clock is compared with the model
    besides."""
    bind(dut)
    rng = random.Random(SEED + 7)
    bench = new_bench(dut)
    await bench.start(pause_prob=0.2)
    full = enc.OUTPUT_POWER_FULL
    period = 1 << PWM_BITS
    # (command, the pins (enable, reverse, mist, flood) after it, or None: rejected)
    outputs = [
        (enc.encode_output(full // 3, 1, mist=1), (1, 0, 1, 0)),
        (enc.encode_output(full, 1, 1, flood=1), (1, 1, 0, 1)),
        (enc.encode_output(full + 1, 1), None),                 # above 100 %: E_FIELD
        (enc.encode_output(0, 1) | (1 << 100), None),           # a reserved bit: E_OPCODE
        (enc.encode_output(full // 2, 1, 0, 1, 0), (1, 0, 0, 0)),   # laser, constant
        (enc.encode_output(full, 1, 0, 1, 1, 1, 1), (1, 0, 1, 1)),  # laser, dynamic
        (enc.encode_output(), (0, 0, 0, 0)),
    ]
    cmds = []
    for command, _ in outputs:
        for _ in range(3):
            cmds.append(random_arc(rng, rmax=20) if rng.random() < 0.5
                        else random_line(rng, NA, scale=20))
        cmds.append(command)
    cmds.append(random_line(rng, NA, scale=20))
    prog = plan(rng, cmds)
    await bench.send(prog)
    await bench.drain()
    check_end(bench, prog)
    assert [c for _, c in bench.errors] == [enc.E_FIELD, enc.E_OPCODE]

    # the moves the host expects before each OUTPUT, and the pin changes seen
    changes = [(i, pins[0], pins[1:5]) for i, pins in enumerate(bench.output_pins)
               if i == 0 or pins[1:5] != bench.output_pins[i - 1][1:5]]
    assert changes[0][2] == (0, 0, 0, 0)
    expected = []
    for k, c in enumerate(prog):
        if enc.decode(c)["opcode"] == enc.OP_OUTPUT:
            after = dict(outputs)[c]
            if after is not None:
                expected.append((len(expect(prog[:k], NA, W)[0]), after))
    got = [(moves, pins) for _, moves, pins in changes[1:]]
    assert got == expected, f"output changes {got}, expected {expected}"

    # duty per PWM period: the power outside laser mode, nothing at rest in laser mode
    spans = [(start, changes[n + 1][0] if n + 1 < len(changes) else len(bench.output_pins))
             for n, (start, _, _) in enumerate(changes)]
    constant = [(spans[1], full // 3), (spans[2], full)]
    for (start, end), power in constant:
        first = -(-(start + 2 * period) // period) * period
        for p0 in range(first, end - period + 1, period):
            high = sum(bench.output_pins[t][5] for t in range(p0, p0 + period))
            assert high == power >> (16 - PWM_BITS), f"period at {p0}: {high} high"
    for start, end in spans[3:5]:
        for t in range(start + 2 * period, end):
            if all(v == 0 for v in bench.speeds[t - 2 * period:t + 1]):
                assert bench.output_pins[t][5] == 0, f"laser on at rest, cycle {t}"
    assert any(bench.output_pins[t][5] for t in range(*spans[4]))

    # a stop at rest switches everything off
    await bench.send([enc.encode_output(full, 1, 0, 0, 0, 1, 1)])
    await bench.drain()
    assert bench.output_pins[-1][1:5] == (1, 0, 1, 1)
    bench.stop_schedule = set(range(bench.cycle + 2, bench.cycle + 10))
    for _ in range(20):
        await FallingEdge(dut.clk)
    assert bench.output_pins[-1][1:6] == (0, 0, 0, 0, 0)
