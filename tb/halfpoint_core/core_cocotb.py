# SPDX-License-Identifier: Apache-2.0
"""cocotb tests of halfpoint_core: model equality on every clock (positions,
STEP/DIR pins, status), independent pin timing checks, and end results."""

from __future__ import annotations

import copy
import os
import random

import cocotb
from cocotb.triggers import FallingEdge

from halfpoint.spec import encoding as enc
from halfpoint.spec import profile as pf
from halfpoint.spec.core import CoreInputs, decode_for_core
from halfpoint.sim.corebench import CoreBench
from halfpoint.sim.design import read_parameters
from halfpoint.spec.rules import wrap
from halfpoint.spec.program import (expect, line_cost, move_count, profiled, random_arc,
                                    random_helix, random_line)
from halfpoint.spec.stepgen import StepCfg

NA = W = DEPTH = TW = DIV = MOVE_DEPTH = PROFILE_DEPTH = PWM_BITS = 0   # bind() reads them
SEED = int(os.environ.get("HP_SEED", "1"))
# the long variants (the mutation flow's core target sets it): profile_distance_bits
# until every bit of both profile distances has decided a crossing
LONG = os.environ.get("HP_CORE_LONG", "0") == "1"
# far_distance (a segment of 65,000 clocks, about a minute): run only when set
FAR = os.environ.get("HP_CORE_FAR", "0") == "1"
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
            # axis 0 twice: a mutant that read u = 0 as 4 in u != v survived
            cmds.append(enc.encode_arc(0, -5, 0, 0, 5, plane=(0, 0)))
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
async def owed_move_waits_under_hold(dut):
    """Slow STEP/DIR timing (a step at most every 60 clocks) under fast lines, so the
    credit reaches its cap while the head move waits for its axes, and holds that
    bring the speed to 0 meanwhile: the head move is then owed (its axes become ready
    at rest, the credit covers it).  At rest under hold no move is made until the
    release (before 2026-11-25 the owed move popped at rest); every clock as the
    model, which counts the owed clocks."""
    bind(dut)
    rng = random.Random(SEED + 11)
    bench = new_bench(dut, cfg=[StepCfg(20, 40, 2, 2)] * NA, seed=SEED + 11)
    await bench.start()
    owed = []
    model_clock = bench.model.clock

    def clock(inp):
        m = bench.model
        st, si = m.stage, m.stage_inputs(inp)
        if inp.hold and st.v == 0 and st.cur is not None and si.head_valid and si.ready \
                and st.covers(pf.move_cost(si.head_class, st.cur)):
            owed.append(bench.cycle)
        return model_clock(inp)
    bench.model.clock = clock
    cmds = [random_line(rng, NA, True, 12) for _ in range(4)]
    prog = profiled(cmds, NA, W, DIV, v_cruise=int(0.4 * ONE), accel=(1 << 34) - 1,
                    junction=int(0.2 * ONE))
    holds = set()
    for start in range(300, 4000, 450):
        holds.update(range(start, start + 250))
    bench.hold_schedule = holds
    await bench.send(prog)
    await bench.drain()
    check_end(bench, prog)
    # no move seen in the clock after an edge at rest under hold (hold on that clock
    # and the one before, the speed register 0)
    for c in bench.move_cycles:
        e = c - 1
        assert not (e in holds and e - 1 in holds and bench.speeds[e] == 0), \
            f"a move at rest under hold (edge of cycle {e})"
    assert owed, "no clock held at rest with an owed move"


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


@cocotb.test()
async def power_with_the_motion(dut):
    """Laser power carried by the PROFILEs (set_power): an OUTPUT switches the laser on
    (laser mode, constant power) at rest, then lines run through junctions above 0,
    each with its own power (0, 100 %, random; some PROFILEs without set_power keep
    the one before): the speed never falls to 0 between the first and the last move
    (no stop at a power change) and in every PWM period inside a segment (two
    periods after its first move) the PWM is high for that segment's power.  Every
    clock compared with the model besides."""
    bind(dut)
    rng = random.Random(SEED + 11)
    bench = new_bench(dut, cfg=[StepCfg(1, 0, 0, 0)] * NA, seed=SEED + 11)
    await bench.start()
    full = enc.OUTPUT_POWER_FULL
    period = 1 << PWM_BITS
    lines = [random_line(rng, NA, scale=600) for _ in range(14)]
    lines = [c for c in lines if move_count(c, NA, W) > 150][:10]
    powers = [full // 2, 0, full, None, rng.randrange(full + 1), None, full // 8, 17,
              rng.randrange(full + 1), 0][:len(lines)]
    prog = [enc.encode_output(full // 4, 1, 0, 1, 0)] + profiled(
        lines, NA, W, DIV, v_cruise=lambda k: speed(rng, 0.2, 0.45),
        accel=lambda k: accel(rng), junction=ONE, power=lambda k: powers[k])
    await bench.send(prog)
    await bench.drain()
    check_end(bench, prog)
    assert not bench.errors
    # the power in force for each segment, and the cycle of its first move
    expected, power = [], full // 4
    for p in powers:
        power = power if p is None else p
        expected.append(power >> (16 - PWM_BITS))
    firsts, total = [], 0
    for c in lines:
        firsts.append(total)
        total += move_count(c, NA, W)
    moves_at = [pins[0] for pins in bench.output_pins]      # moves made before each cycle
    starts = [moves_at.index(m + 1) for m in firsts] + [moves_at.index(total)]
    for t in range(starts[0], starts[-1]):
        assert bench.speeds[t] > 0, f"the motion stopped at cycle {t}"
    # a period's duty comes from the power sampled a period or two before it
    for k, want in enumerate(expected):
        first = -(-(starts[k] + 2 * period) // period) * period
        periods = range(first, starts[k + 1] - 2 * period + 1, period)
        assert len(periods) >= 2, f"segment {k} too short to measure"
        for p0 in periods:
            high = sum(bench.output_pins[t][5] for t in range(p0, p0 + period))
            assert high == want, f"segment {k}, period at {p0}: {high} high, not {want}"


def decode_cases():
    """Commands that reach every decode check bit by bit (for the core's own
    mutants): each reserved bit of each opcode alone, each bit of the deltas of
    the axes and helix slots this core lacks, each bit of a field's top beyond
    the width (both signs), each PROFILE rule broken alone, and the OUTPUT power
    around 100 %; valid commands between them keep the dispatcher moving."""
    bases = [enc.encode_line([1] + [0] * (NA - 1)), enc.encode_arc(1, 0, -3, 0, 0),
             enc.encode_profile(ONE // 8, 0, 1 << 30), enc.encode_output(100, 1)]
    cmds = [enc.pack([op, 0, 1, 2, 3, 4, 5, 6]) for op in (0, 6, 7, 8, 12, 15)]
    # every bit whose flip alone is a reserved bit set (E_OPCODE) in the model: the
    # reserved bits of each opcode, the deltas of the axes and helix slots the core
    # lacks, the opcodes that do not exist
    for base in bases:
        cmds += [base ^ (1 << b) for b in range(enc.CMD_BITS)
                 if decode_for_core(base ^ (1 << b), NA, W) == ("err", enc.E_OPCODE)]
    # each bit of the top (bits W-1 and up) of a field, alone and cleared in -1
    tops = [enc._s32(1 << b) for b in range(W - 1, 32)] + \
           [enc._s32(((1 << 32) - 1) ^ (1 << b)) for b in range(W - 1, 32)]
    for v in tops:
        for axis in range(NA):
            cmds.append(enc.encode_line([0] * axis + [v] + [0] * (NA - 1 - axis)))
        cmds += [enc.encode_arc(0, *ijxy) for ijxy in
                 ((v, 0, 0, 0), (0, v, 0, 0), (0, 0, v, 0), (0, 0, 0, v), (v, 0, v, 0),
                  (0, v, 0, v))]
        for slot in range(enc.helix_slots(NA)):
            cmds.append(enc.encode_arc(1, 0, -3, 0, 3, count=6, helix=[0] * slot + [v]))
    # a helix delta of either sign at its count and one beyond (E_HELIX), the
    # largest magnitude against the counts around it
    half = 1 << (W - 1)
    pairs = [(n, d) for n in (1, 6, half - 2) for d in (n, -n, n + 1, -n - 1)]
    pairs += [(half - 1, -half), (half, -half), (half + 1, half - 1), (half - 2, half - 1)]
    for slot in range(enc.helix_slots(NA)):
        cmds += [enc.encode_arc(1, 0, -3, 0, 3, count=n, helix=[0] * slot + [d])
                 for n, d in pairs]
    # each arc field alone out of the width (i, x and the derived xs = -i, xe = x -
    # i; j, y, ys, ye the same), and alone at its limits
    for i, x in ((half, 0), (1, half), (-1, -half - 1), (-half, 0), (-1, half - 1),
                 (1, -half), (-half + 1, half - 1), (half - 1, -half + 1), (0, half - 1),
                 (0, -half)):
        if max(i, x) < 1 << 31 and min(i, x) >= -(1 << 31):     # a 32-bit field
            cmds += [enc.encode_arc(0, i, 0, x, 0), enc.encode_arc(1, 0, i, 0, x)]
    # PROFILE rules, each broken alone, and each bit of d_exit beyond its width
    dw = W + enc.PROFILE_DISTANCE_EXTRA
    cmds += [enc.encode_profile(ONE // 8, 0, 0), enc.encode_profile(100, 101, 1),
             enc.encode_profile(ONE // 8, 0, 1, 0, 5, 6),
             enc.encode_profile(ONE // 8, 0, 1, 0, (1 << dw) - 1, (1 << dw) - 1)]
    for b in range(dw, 54):
        cmds.append(enc.encode_profile(ONE // 8, 0, 1, 0, 1 << b, 0))
        cmds.append(enc.encode_profile(ONE // 8, 0, 1, 0, 1, 1 << b))
    for b in range(34):
        cmds.append(enc.encode_profile(ONE // 8, 0, 1 << b))
    for b in range(32):
        cmds.append(enc.encode_profile((1 << b) - 1, 1 << b, 1))
        cmds.append(enc.encode_profile(1 << b, 1 << b, 1))
    for b in range(min(dw, 54)):
        cmds.append(enc.encode_profile(ONE // 8, 0, 1, 0, (1 << b) - 1, 1 << b))
        cmds.append(enc.encode_profile(ONE // 8, 0, 1, 0, 1 << b, 1 << b))
    full = enc.OUTPUT_POWER_FULL
    cmds += [enc.encode_output(p, 1) for p in (full, full + 1, full - 1)]
    cmds += [enc.encode_output(full | (1 << b), 1) for b in range(16)]
    # a PROFILE's power: around 100 %, each bit alone with and without set_power, each
    # bit above 100 %
    cmds += [enc.encode_profile(ONE // 8, 0, 1, 0, 0, 0, 1, p)
             for p in (full, full + 1, full - 1, (1 << 17) - 1)]
    for b in range(17):
        cmds += [enc.encode_profile(ONE // 8, 0, 1, 0, 0, 0, s, 1 << b) for s in (0, 1)]
    cmds += [enc.encode_profile(ONE // 8, 0, 1, 0, 0, 0, 1, full | (1 << b))
             for b in range(16)]
    return cmds


@cocotb.test()
async def decode_every_field_bit(dut):
    """Every decode check reached bit by bit (``decode_cases``): rejects with their
    codes, the accepted commands run, every clock compared with the model; then a
    short program with the arc unit's rejects."""
    bind(dut)
    bench = new_bench(dut, seed=SEED + 9)
    await bench.start()
    rng = random.Random(SEED + 9)
    cmds = decode_cases()
    # a line; an arc ending off its circle (E_ARC_END) and one whose circle leaves
    # the width (E_ARC_RANGE), the arc unit's rejects
    far = 3 << (W - 3)
    runs = plan(rng, [enc.encode_line([2] + [0] * (NA - 1)), enc.encode_arc(1, 0, -3, 0, 3),
                      enc.encode_arc(1, -far, -far, 0, 0)])
    await bench.send(cmds + runs)
    await bench.drain()
    check_end(bench, cmds + runs)
    dut._log.info("decode: %d commands, %d clocks, %d rejects", len(cmds), bench.cycle,
                  len(bench.errors))


def simulate(model, cmds, override, clocks, reference=None, accel_field=None):
    """A copy of ``model`` fed ``cmds`` back to back for ``clocks`` clocks (or until
    it is idle): (speed, dry) per clock, and the stage's earned distance E in the
    segment whose profile has ``accel_field`` (None on other clocks).  With a
    ``reference`` trace: whether the trace differs from it (stopping at the first
    difference)."""
    m = copy.deepcopy(model)
    trace, distances, idx, idle = [], [], 0, 0
    while idle < 4 and len(trace) < clocks:
        o = m.outputs()
        st = m.stage
        trace.append((o.speed, o.dry))
        if reference is not None and (len(trace) > len(reference)
                                      or trace[-1] != reference[len(trace) - 1]):
            return True
        current = st.cur is not None and st.cur.accel == accel_field
        distances.append(st.s + (st.credit >> pf.COST_SHIFT) if current else None)
        feed = idx < len(cmds)
        m.clock(CoreInputs(tvalid=int(feed), tdata=cmds[idx] if feed else 0,
                           override=override))
        idx += int(feed and o.tready)
        idle = 0 if (o.busy or idx < len(cmds)) else idle + 1
    if reference is not None:
        return len(trace) != len(reference)
    return trace, distances


class DistanceCases:
    """Segments whose earned distance E crosses a profile distance (``field``:
    d_exit or d_stop) exactly, so that each bit of the distance, set or clear,
    decides the clock of the crossing: d = E(n-1) + 1 (clearing any set bit moves
    the crossing earlier; setting a clear bit at or above the clock's gain moves it
    later) or d = E(n) (setting any clear bit moves it later).  Each bit's flip is
    checked on a copy of the bench's model to change the speed or dry trace; the
    bits a segment cannot reach (2^k beyond its distances) get d = 2^k, one
    short segment each, never crossed, and crossed at once with the bit cleared
    (``LONG`` only).  d_exit cases set d_stop = d_exit (a later exit
    crossing is a dry one); d_stop cases have d_exit at its largest and a nonzero
    exit speed, the queue dry behind them.

    Each case is a chain: a short line A, the segment B under test, and a PROFILE
    C whose fields are B's inverted (B's distance among them), loaded as the
    profile in force while B's profile still waits in the profile queue for A's
    end: the queue must hand B's profile over as it was written."""

    def __init__(self, field, rng):
        self.field, self.rng = field, rng
        self.bits = W + enc.PROFILE_DISTANCE_EXTRA
        self.top = (1 << self.bits) - 1
        self.needed = {(kind, k) for kind in ("set", "clear") for k in range(self.bits)}
        self.reach = self.bits

    def distances(self, d):
        return (d, d) if self.field == "d_exit" else (self.top, d)

    def segment(self, params, d):
        (v_cruise, v_exit, accel_field, deltas), (a_cruise, a_accel, a_deltas) = params
        inverted = self.distances(~d & self.top)
        cruise_c = ~v_cruise & 0xFFFFFFFF
        pad = [0] * (NA - 2)
        tested = [enc.encode_profile(v_cruise, v_exit, accel_field, line_cost(deltas),
                                     *self.distances(d)),
                  enc.encode_line(list(deltas) + pad)]
        if a_deltas is None:
            return tested
        return [enc.encode_profile(a_cruise, a_cruise, a_accel, line_cost(a_deltas),
                                   self.top, self.top),
                enc.encode_line(list(a_deltas) + pad)] + tested + \
            [enc.encode_profile(cruise_c, ~v_exit & cruise_c, ~accel_field & ((1 << 34) - 1),
                                ~line_cost(deltas) & ((1 << 18) - 1), *inverted)]

    def params(self, length=30, chain=True):
        rng = self.rng
        v_cruise = speed(rng, 0.3, 0.45)
        deltas = (rng.randint(length, length + 10) * rng.choice((1, -1)),
                  rng.randint(-length // 2, length // 2))
        return ((v_cruise, rng.randint(v_cruise // 4, v_cruise // 2),
                 rng.randint(1 << 33, (1 << 34) - 1), deltas),
                (speed(rng, 0.05, 0.1), rng.randint(1 << 31, (1 << 32) - 1),
                 (rng.randint(4, 8), rng.randint(-3, 3)) if chain else None))

    def differs(self, model, params, d, k, reference, clocks):
        return simulate(model, self.segment(params, d ^ (1 << k)), 128, clocks + 1, reference,
                        params[0][2])

    def next(self, model):
        """The next case for the bench's model in its present (idle) state, or
        None when every bit is covered."""
        params = self.params()
        accel_b = params[0][2]
        _, distances = simulate(model, self.segment(params, self.top), 128, 20_000, None,
                                accel_b)
        during = [n for n, e in enumerate(distances) if e is not None]
        # a set bit within the middle of the segment's distances
        reach = distances[during[-1]].bit_length() - 2
        self.reach = min(self.reach, reach)
        want = {(kind, k) for kind, k in self.needed if k < reach or kind == "clear"}
        if not want:
            if not self.needed or not LONG:
                return None
            # a bit beyond the segment: d = 2^k is never reached, d = 0 at once
            k = min(k for _, k in self.needed)
            d = 1 << k
            kinds = {"set"}
            params = self.params(length=16, chain=False)
        else:
            steps = [n for n in during[len(during) // 4:3 * len(during) // 4]
                     if distances[n - 1] is not None and distances[n] > distances[n - 1]]

            def covers(d, gain):
                return sum(1 for kind, k in want if (d >> k & 1) == (kind == "set")
                           and (kind == "set" or d == gain[1] or (1 << k) >= gain[1] - gain[0]))

            candidates = [(distances[n - 1] + 1, (distances[n - 1], distances[n]))
                          for n in steps] + [(distances[n], (distances[n - 1], distances[n]))
                                             for n in steps]
            d = max(self.rng.sample(candidates, min(40, len(candidates))),
                    key=lambda c: covers(*c))[0]
            kinds = {"set", "clear"}
        reference, _ = simulate(model, self.segment(params, d), 128, 20_000)
        clocks = len(reference)
        for kind, k in sorted(self.needed):
            if kind in kinds and (d >> k & 1) == (kind == "set") and \
                    self.differs(model, params, d, k, reference, clocks):
                self.needed.discard((kind, k))
        return self.segment(params, d)


@cocotb.test()
async def profile_distance_bits(dut):
    """Every bit of d_exit and d_stop decides a crossing (``DistanceCases``): the
    distances pass the queue, the profile register and the profile queue bit for
    bit; every clock compared with the model.  Without HP_CORE_LONG two cases
    per distance (the bits they happen to decide); with it, cases until every bit
    of both distances, set and clear, has decided one (about 50 segments at W 16),
    which the test asserts."""
    bind(dut)
    rng = random.Random(SEED + 10)
    bench = new_bench(dut, cfg=[StepCfg(1, 0, 0, 0)] * NA, seed=SEED + 10)
    await bench.start()
    segments = 0
    for field in ("d_exit", "d_stop"):
        cases = DistanceCases(field, rng)
        for _ in range(80 if LONG else 2):
            for _ in range((1 << DIV) + 8):       # the stage's step cadence settles
                await FallingEdge(dut.clk)
            case = cases.next(bench.model)
            if case is None:
                break
            await bench.send(case)
            await bench.drain()
            segments += 1
        if LONG:
            assert not cases.needed, f"{field}: bits no case decided: {sorted(cases.needed)}"
    dut._log.info("profile distances: %d cases, %d clocks", segments, bench.cycle)


@cocotb.test()
async def output_meets_stop(dut):
    """An OUTPUT reaching the head of an idle core in the clock the registered stop
    rises does not load (that clock is a stop at rest; the flush after it drops the
    OUTPUT); stop is raised at several offsets around the beat, with the settings
    changing each time; every clock compared with the model, and the case is
    checked to have happened."""
    bind(dut)
    bench = new_bench(dut, seed=SEED + 11)
    await bench.start()
    full = enc.OUTPUT_POWER_FULL
    met = 0
    for offset in range(-3, 3):
        await bench.send([enc.encode_output(full // 4, 1, 0, 0, 0, 1, 0)])
        await bench.drain()
        t = bench.cycle
        bench.stop_schedule = set(range(t + offset + 2, t + offset + 8))
        await bench.send([enc.encode_output(full // 2, 1, 1, 0, 0, 0, 1)])
        for _ in range(16):
            await FallingEdge(dut.clk)
            m = bench.model
            head = m.queue and enc.decode(m.queue[0])["opcode"] == enc.OP_OUTPUT
            met += int(bool(head and m.stop_pin and m.inflight is None
                            and m.downstream_idle()))
        await bench.source.wait()
        await bench.drain()
    assert met, "no OUTPUT met the registered stop at the head"


@cocotb.test()
async def cont_waits_at_head(dut):
    """A CONT line that waits at the queue head (the line before it in flight) keeps
    its CONT: with nothing behind it, its end is an underrun.  Every clock compared
    with the model."""
    bind(dut)
    bench = new_bench(dut, seed=SEED + 12)
    await bench.start()
    first = enc.encode_line([40, 13] + [0] * (NA - 2), cont=True)
    prog = profiled([first], NA, W, DIV, v_cruise=ONE // 4, accel=1 << 31, junction=ONE // 4)
    # the second line under the same profile: at the head while the first is in flight
    prog.append(enc.encode_line([-9, 4] + [0] * (NA - 2), cont=True))
    changes = []

    async def watch():
        while True:
            await FallingEdge(dut.clk)
            changes.append((bench.moves, bench.last["underrun"]))

    cocotb.start_soon(watch())
    await bench.send(prog)
    await bench.drain()
    check_end(bench, prog)
    first_moves = len(expect(prog[:2], NA, W)[0])
    assert all(u == 0 for moves, u in changes if moves <= first_moves), \
        "the first segment underran: the second is not the one tested"
    assert bench.last["underrun"] == 1, "the last CONT segment ended without an underrun"


@cocotb.test()
async def profile_speeds_reached(dut):
    """Segments under profiles with random bits in every field whose speed reaches
    the cruise speed and then, from a d_exit early in the segment, the exit speed,
    and stays there: each speed field's bits, the speed steps (accel) and the line
    cost appear on the speed register and the move timing, passed through the queue,
    the profile register and the profile queue.  Every clock compared with the
    model; the test checks both plateaus were reached."""
    bind(dut)
    rng = random.Random(SEED + 13)
    bench = new_bench(dut, cfg=[StepCfg(1, 0, 0, 0)] * NA, seed=SEED + 13)
    await bench.start()
    top = (1 << (W + enc.PROFILE_DISTANCE_EXTRA)) - 1
    for _ in range(4):
        for _ in range((1 << DIV) + 8):
            await FallingEdge(dut.clk)
        v_cruise = rng.randint(ONE // 4, ONE // 2)
        v_exit = rng.randint(ONE // 16, ONE // 5)
        accel_field = rng.randint(1 << 33, (1 << 34) - 1)
        deltas = [rng.randint(70, 80) * rng.choice((1, -1)), rng.randint(-30, 30)] + \
            [0] * (NA - 2)

        def segment(d):
            return [enc.encode_profile(v_cruise, v_exit, accel_field, line_cost(deltas), d, d),
                    enc.encode_line(deltas)]

        trace, distances = simulate(bench.model, segment(top), 128, 20_000, None, accel_field)
        # d_exit: the distance two ticks after the cruise speed is reached
        cruise = next(n for n, (v, _) in enumerate(trace) if v == v_cruise << pf.SPEED_SHIFT)
        start = len(bench.speeds)
        await bench.send(segment(distances[cruise + (2 << DIV)]))
        await bench.drain()
        seen = set(bench.speeds[start:])
        assert {v_cruise << pf.SPEED_SHIFT, v_exit << pf.SPEED_SHIFT} <= seen, \
            "a plateau was not reached"


@cocotb.test()
async def arc_count_bits(dut):
    """A quarter arc with its exact move count, and with each bit of the count
    flipped in turn (E_HELIX_COUNT at its last move, the arc run in full; a count
    flipped to 0 is no count): every bit
    of the count the queue carries to the helix mapper decides the error.  Every
    clock compared with the model."""
    bind(dut)
    bench = new_bench(dut, cfg=[StepCfg(1, 0, 0, 0)] * NA, seed=SEED + 14)
    await bench.start()
    arc = enc.encode_arc(1, 0, -3, 3, -3)
    count = move_count(arc, NA, W)
    arcs = [enc.encode_arc(1, 0, -3, 3, -3, count=count ^ (1 << k)) for k in range(32)]
    prog = profiled([enc.encode_arc(1, 0, -3, 3, -3, count=count)] + arcs, NA, W, DIV,
                    v_cruise=ONE // 2 - 1, accel=(1 << 34) - 1, junction=ONE // 2 - 1)
    await bench.send(prog)
    await bench.drain()
    check_end(bench, prog)
    # a count of 0 is no count (not checked)
    flipped = sum(1 for k in range(32) if count ^ (1 << k))
    assert [c for _, c in bench.errors] == [enc.E_HELIX_COUNT] * flipped


@cocotb.test()
async def dispatch_and_burst(dut):
    """Two cases the other tests miss, every clock compared with the model.  An arc
    with a reserved bit set (E_OPCODE) reaches the queue head while an arc profile is
    in force and the arc unit and the profile queue are free: it is rejected and
    must not reach the arc unit.  And two moves pop on consecutive clocks across a
    segment boundary: the X generator is slow (steplen 12, stepspace 8), so the credit
    reaches its cap while the first line waits on it; the last X move pops, and the
    next line's first move, on Y (idle, ready), pops on the next clock, when the move
    queue holds one move and the line unit makes one at the same edge (the head after
    that pop is the move made, not the memory's stale entry)."""
    bind(dut)
    slow = [StepCfg(12, 8, 0, 0)] + [StepCfg(1, 0, 0, 0)] * (NA - 1)
    bench = new_bench(dut, cfg=slow, seed=SEED + 16)
    await bench.start()
    base = enc.encode_arc(1, 0, -3, 3, -3)
    bad = next(base ^ (1 << b) for b in range(4, enc.CMD_BITS)
               if decode_for_core(base ^ (1 << b), NA, W) == ("err", enc.E_OPCODE))
    fast = (ONE * 7) // 8
    prog = profiled([base, bad, base,
                     enc.encode_line([5] + [0] * (NA - 1)),
                     enc.encode_line([0, 5] + [0] * (NA - 2))],
                    NA, W, DIV, v_cruise=fast, accel=(1 << 34) - 1, junction=fast)
    # the arc profile again just before the bad arc: the profile queue, which the
    # first arc's profile filled as its run started, has room again when it arrives
    prog.insert(prog.index(bad), prog[0])
    await bench.send(prog)
    await bench.drain()
    check_end(bench, prog)
    assert [c for _, c in bench.errors] == [enc.E_OPCODE]
    # the arcs end at (3, -3) and (6, -6), the lines at (11, -6) and (11, -1): the
    # last X move and the first Y move seen on consecutive clocks
    plane = [tuple(p[:2]) for p in bench.trace]
    first_y = plane.index((11, -5))
    assert plane[first_y - 1] == (11, -6)
    assert bench.move_cycles[first_y] == bench.move_cycles[first_y - 1] + 1, \
        "no pop burst across the boundary"


@cocotb.test()
async def reversals_wait_for_dirhold(dut):
    """Every axis with a DIR hold time longer than its step space (steplen 1,
    stepspace 0, dirhold 5): a step in the same direction is ready two clocks after
    the last, a reversal only after the hold, so the generators' two lookaheads
    (next_ready_same, next_ready_reverse) differ and the registered readiness must
    take the one for the head's direction, after a pop and while the head waits.
    Lines back and forth on each axis and zig-zags at 7/8 BLU per clock (moves pop
    on consecutive clocks) and a full circle (Y reverses twice); every clock compared
    with the model, every pin edge checked.  The other tests' timings never tell
    the lookaheads apart (a mutant that took one for the other survived them); this
    one checks that a reversal came as soon as the DIR timing allowed, later than
    the quickest step in the same direction."""
    bind(dut)
    bench = new_bench(dut, cfg=[StepCfg(1, 0, 1, 5)] * NA, seed=SEED + 18)
    await bench.start()
    cmds = []
    for k in range(NA):
        for sign in (1, -1, 1):
            cmds.append(enc.encode_line([3 * sign if a == k else 0 for a in range(NA)]))
    for sign in (1, -1, 1, -1):
        cmds.append(enc.encode_line([2, 2 * sign] + [0] * (NA - 2)))
    cmds.append(enc.encode_arc(0, 0, -4, 0, 0))                   # a full circle
    fast = (ONE * 7) // 8
    prog = profiled(cmds, NA, W, DIV, v_cruise=fast, accel=(1 << 34) - 1, junction=fast)
    await bench.send(prog)
    await bench.drain()
    check_end(bench, prog)
    # per axis, the clocks between consecutive steps, split by whether the second
    # one reversed the first
    same, reverse = [], []
    for k in range(NA):
        last = None                               # (cycle, direction) of the last step
        for n in range(1, len(bench.trace)):
            delta = bench.trace[n][k] - bench.trace[n - 1][k]
            if delta == 0:
                continue
            if last is not None:
                (reverse if delta != last[1] else same).append(bench.move_cycles[n] - last[0])
            last = (bench.move_cycles[n], delta)
    assert same and reverse
    dut._log.info("step gaps: same direction %d..%d clocks, reversals %d..%d",
                  min(same), max(same), min(reverse), max(reverse))
    # the earliest reversal: STEP high 1 clock, DIR held 5, set up 1 before the next
    earliest = 1 + 5 + 1
    assert earliest <= min(reverse) <= earliest + 2, "no reversal came as soon as DIR allowed"
    assert min(same) < min(reverse), "the same-direction steps were as slow as the reversals"


@cocotb.test(skip=not FAR)
async def far_arc_count(dut):
    """A full circle of more than 2^15 moves with its exact count: bit 15 of the
    count set, so each lower bit must be carried exactly for the count check to pass
    (no E_HELIX_COUNT).  Every clock compared with the model.  Only with HP_CORE_FAR=1
    (about 70,000 clocks at W 16); W >= 14 (radius 6,000)."""
    bind(dut)
    assert W >= 14, "far_arc_count needs a radius of 6,000: W >= 14"
    bench = new_bench(dut, cfg=[StepCfg(1, 0, 0, 0)] * NA, seed=SEED + 17)
    await bench.start()
    circle = enc.encode_arc(1, 0, -6000, 0, 0)
    count = move_count(circle, NA, W)
    assert count >= 1 << 15
    prog = profiled([enc.encode_arc(1, 0, -6000, 0, 0, count=count)], NA, W, DIV,
                    v_cruise=ONE - 1, accel=(1 << 34) - 1)
    await bench.send(prog)
    await bench.drain()
    check_end(bench, prog)
    assert not bench.errors


@cocotb.test(skip=not FAR)
async def far_distance(dut):
    """A distance beyond 2^32 (BLU x 2^16) crossed: one line whose iterations cost
    the largest line cost (4 BLU), at the largest cruise speed (1 BLU per clock), with
    d_stop = 2^32 and d_exit 4 BLU beyond it (bit 18 set): its exit staircase starts
    4 BLU after 2^32, about 65,600 clocks into the segment (E gains at most 2^16 a
    clock), and each bit of both distances up there is carried to the stage.  The
    exit speed 0 keeps the queue from being dry.  Every clock compared with the
    model.  Only with HP_CORE_FAR=1 (about a minute at W 16); W <= 20 (a line of
    16,400 iterations)."""
    bind(dut)
    assert W <= 20, "far_distance needs a line of 16,400 iterations: W <= 20"
    bench = new_bench(dut, cfg=[StepCfg(1, 0, 0, 0)] * NA, seed=SEED + 15)
    await bench.start()
    cost = (1 << 18) - 1
    d_stop = 1 << 32
    d_exit = d_stop + (1 << 18)
    iterations = -(-d_exit // cost) + 8
    prog = [enc.encode_profile((1 << 32) - 1, 0, (1 << 34) - 1, cost, d_exit, d_stop),
            enc.encode_line([iterations] + [0] * (NA - 1))]
    await bench.send(prog)
    await bench.drain()
    check_end(bench, prog)
