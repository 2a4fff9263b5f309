# SPDX-License-Identifier: Apache-2.0
"""cocotb test of halfpoint_outputs: every pin and every register against
``halfpoint.spec.outputs.OutputStage`` on every clock, under random inputs.

Run by ``test_outputs_rtl.py``; PWM_BITS is read from the design.  Stimulus: random
loads (power 0, 65536, above 65536, random; every mix of the flags), cruise speeds
taken at random clocks (0, tiny, random; half of them with a segment's power, the
same choice of values as a load's), a speed that ramps and jumps (to 0, to just
below, at and above the cruise speed, to the top of its range), ``off`` levels of a
few clocks (with a load at the same edge half of the time) and one reset.  Where the
unit is idle (counter 2P + 2 .. 2^P - 3, every flag clear) the counter is set
forward in both the RTL and the model (a deposit on ``counter_q``), to just before,
at or after the duty or to the period's end, so PWM_BITS 16 runs many periods in a
few thousand clocks; nothing else is touched.  The test counts what it saw (each
kind of result, the pin's edges, offs) and fails if a kind never happened.
"""

from __future__ import annotations

import os
import random
from collections import Counter

import cocotb
from cocotb.clock import Clock
from cocotb.triggers import FallingEdge

from halfpoint.sim.design import read_parameters
from halfpoint.spec.outputs import REGISTERS, OutputInputs, OutputStage

PWM_BITS = 0        # the design's parameter: bind() reads it
SEED = int(os.environ.get("HP_SEED", "1"))
CLOCKS = int(os.environ.get("HP_OUTPUTS_CLOCKS", "8000"))
PINS = ("spindle_enable", "spindle_reverse", "coolant_mist", "coolant_flood", "pwm", "duty")
TOP_SPEED = (1 << 38) - 1


def bind(dut) -> None:
    """Take PWM_BITS from the design under test (its parameters)."""
    global PWM_BITS
    (PWM_BITS,) = read_parameters(dut, "PWM_BITS")


class Stimulus:
    """The inputs of each clock, from a seeded generator and the model's state."""

    def __init__(self, rng: random.Random, model: OutputStage):
        self.rng = rng
        self.model = model
        self.speed = 0
        self.target = 0
        self.step = 0
        self.off_left = 0
        # per-clock rates, scaled so that P = 4 (16-clock periods) and the larger
        # PWM_BITS (periods shortened by the jumps) see a few events per period
        self.rate = 0.02 if model.pwm_bits == 4 else 0.01

    def new_speed_target(self) -> None:
        rng = self.rng
        full = self.model.cruise << 6
        target = rng.choice([0, 0, max(full - 1, 0), full, full + 1, rng.randrange(full + 1),
                             rng.randrange(full + 1), rng.randrange(full, 4 * full + 2),
                             TOP_SPEED, rng.randrange(1, 64)])
        self.target = min(target, TOP_SPEED)
        if rng.random() < 0.4:
            self.speed = self.target                # a jump
        else:
            self.step = max(1, abs(self.target - self.speed) // rng.randint(3, 300))

    def next_inputs(self) -> OutputInputs:
        rng = self.rng
        i = OutputInputs()
        if rng.random() < self.rate * 2:
            self.new_speed_target()
        if self.speed < self.target:
            self.speed = min(self.speed + self.step, self.target)
        elif self.speed > self.target:
            self.speed = max(self.speed - self.step, self.target)
        i.speed = self.speed
        if rng.random() < self.rate / 2:
            i.take = 1
            i.take_v_cruise = rng.choice([0, 1, rng.randrange(1 << 32), rng.randrange(1 << 32),
                                          rng.randrange(1, 1 << rng.randint(1, 32))])
        elif rng.random() < 0.02:
            i.take_v_cruise = rng.randrange(1 << 32)         # not taken
        # a segment's power with the take (half of them), or offered without one
        if (i.take and rng.random() < 0.5) or rng.random() < 0.01:
            i.take_set_power = 1
            i.take_power = rng.choice([0, 65536, 65537, (1 << 17) - 1, rng.randrange(65537),
                                       rng.randrange(65537), rng.randrange(1 << 17)])
        elif rng.random() < 0.02:
            i.take_power = rng.randrange(1 << 17)            # without set_power: ignored
        if self.off_left == 0 and rng.random() < self.rate / 4:
            self.off_left = rng.randint(1, 5)
        if self.off_left:
            self.off_left -= 1
            i.off = 1
        if rng.random() < self.rate or (i.off and rng.random() < 0.5):
            i.load = 1
            i.load_power = rng.choice([0, 65536, 65537, (1 << 17) - 1, rng.randrange(65537),
                                       rng.randrange(65537), rng.randrange(1 << 17)])
            i.load_enable = int(rng.random() < 0.85)
            i.load_laser = int(rng.random() < 0.7)
            i.load_dynamic = int(rng.random() < 0.7)
            i.load_reverse, i.load_mist, i.load_flood = (rng.randint(0, 1) for _ in range(3))
        elif rng.random() < 0.05:
            # load_* change without a load: nothing may follow them
            i.load_power = rng.randrange(1 << 17)
            i.load_enable = i.load_laser = i.load_dynamic = 1
        return i

    def jump(self) -> int | None:
        """A counter value to set forward to, or None: only from and to the unit's idle
        clocks (2P + 2 .. 2^P - 3), where every schedule flag is clear."""
        m = self.model
        p = m.pwm_bits
        low, high = 2 * p + 2, m.period - 3
        if not low <= m.counter < high or self.rng.random() < 0.3:
            return None
        duty = m.duty
        candidates = [high, duty - 2, duty - 1, duty, duty + 1,
                      self.rng.randrange(m.counter, high + 1)]
        value = self.rng.choice(candidates)
        return value if m.counter < value <= high else None


def drive(dut, i: OutputInputs) -> None:
    for name, value in vars(i).items():
        getattr(dut, name).value = value


def read_registers(dut) -> dict:
    return {name: int(getattr(dut, name + "_q").value) for name in REGISTERS}


@cocotb.test()
async def pins_and_registers_match_the_model(dut):
    """Every clock: the six outputs and every register equal the model's."""
    bind(dut)
    rng = random.Random(SEED * 1000 + PWM_BITS)
    model = OutputStage(PWM_BITS)
    stimulus = Stimulus(rng, model)
    seen = Counter()
    cocotb.start_soon(Clock(dut.clk, 10, unit="ns").start())
    drive(dut, OutputInputs(rst=1))
    await FallingEdge(dut.clk)
    model.clock(OutputInputs(rst=1))
    reset_at = CLOCKS // 2
    last_pwm = 0
    for cycle in range(CLOCKS):
        await FallingEdge(dut.clk)
        got = {name: int(getattr(dut, name).value) for name in PINS}
        want = vars(model.outputs())
        bad = [k for k in PINS if got[k] != want[k]]
        assert not bad, f"clock {cycle}: " + ", ".join(
            f"{k}: rtl={got[k]} model={want[k]}" for k in bad)
        got = read_registers(dut)
        want = model.registers()
        # the RTL's copy of the sign (for fanout) is always the accumulator's top bit
        assert int(dut.sign_copy_q.value) == got["accumulator"] >> 32, f"clock {cycle}"
        bad = [k for k in REGISTERS if got[k] != want[k]]
        assert not bad, f"clock {cycle}: " + ", ".join(
            f"{k}: rtl={got[k]} model={want[k]}" for k in bad)
        # what this clock covers
        seen["pwm rising"] += int(want["pwm"] and not last_pwm)
        seen["pwm falling"] += int(last_pwm and not want["pwm"])
        last_pwm = want["pwm"]
        if model.at_end:
            seen[result_kind(model)] += 1
        inputs = stimulus.next_inputs()
        if cycle == reset_at:
            inputs = OutputInputs(rst=1, speed=inputs.speed)
        seen["off"] += inputs.off
        seen["off with load"] += int(inputs.off and inputs.load)
        seen["load"] += inputs.load
        seen["power taken"] += int(inputs.take and inputs.take_set_power and not inputs.off)
        seen["power taken, load wins"] += int(inputs.take and inputs.take_set_power
                                              and inputs.load and not inputs.off)
        target = stimulus.jump() if not inputs.rst else None
        if target is not None:
            dut.counter_q.value = target
            model.counter = target
            seen["jump"] += 1
        drive(dut, inputs)
        model.clock(inputs)
    dut._log.info("PWM_BITS %d, %d clocks: %s", PWM_BITS, CLOCKS, dict(sorted(seen.items())))
    wanted = ["dynamic, part", "dynamic, full", "laser at rest", "laser, constant",
              "spindle", "disabled", "pwm rising", "pwm falling", "off", "off with load",
              "power taken"]
    missing = [k for k in wanted if seen[k] < 2]
    assert not missing, f"never (or once) seen: {missing}; seen {dict(seen)}"


def result_kind(model: OutputStage) -> str:
    """Which rule gives the duty the register takes at this clock's end."""
    if not model.sample_enable:
        return "disabled"
    if not model.sample_laser:
        return "spindle"
    if not model.sample_moving:
        return "laser at rest"
    if not model.sample_dynamic:
        return "laser, constant"
    return "dynamic, full" if model.sample_full else "dynamic, part"
