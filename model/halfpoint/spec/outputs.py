# SPDX-License-Identifier: Apache-2.0
"""Executable specification of the spindle / laser / coolant output stage
(``rtl/halfpoint_outputs.v``, issue 14 item 3).

The core drives it in program order between moves: a ``load`` pulse takes the settings
of an OUTPUT command (M3 / M4 / M5 with S, M7 / M8 / M9, the machine file's laser
mode), ``take`` takes each new segment's cruise speed from the profile stage and,
when the segment's PROFILE sets one (``take_set_power``: laser mode's S words and
G0s, carried with the motion), its power, and ``speed`` is the profile stage's speed
register.  A ``load`` at the same edge as a take's power wins (the core never makes
both at one edge: an OUTPUT loads only with the profile queue empty).  ``off`` (a
level) clears every setting and the duty at once (abort, a controlled stop at rest).
The RTL is held to ``OutputStage`` clock by clock; ``effective_duty`` is the closed form
of the duty the sequential unit computes (for the tests and the host).

Parameter P = ``pwm_bits`` (4..16): a PWM period is 2^P clocks (48.8 kHz at 50 MHz for
P = 10); the duty is 0..2^P clocks of it (2^P: always on).

Registers (names as in the RTL, which adds ``_q``):

=================  ======  ===========================================================
register           bits    meaning
=================  ======  ===========================================================
enable, reverse    1 each  the settings: spindle / laser on, counter-clockwise (M4 out
laser, dynamic             of laser mode), laser mode (off at rest), duty follows
mist, flood                speed / cruise (M4 in laser mode), coolant mist, flood
power              P+1     the power in 1/2^P of full, 0..2^P: load_power >> (16 - P),
                           a load_power above 65536 taken as 65536 (the "base"); a
                           take with take_set_power loads take_power the same way
cruise             32      the current segment's cruise speed, BLU per clock x 2^32
counter            P       the PWM counter: +1 every clock, wraps; cleared by rst only
duty               P+1     this period's duty, 0..2^P; takes the unit's result at the
                           wrap (counter 2^P - 1 -> 0): one duty per period
pwm                1       the pin, registered (see below)
at_start .. at_end 1 each  the unit's schedule, decoded from the counter a clock
                           early (registered): at_start 0, dividing 1..P, clearing
                           P+1, multiplying P+2..2P+1, shifting 2..2P, at_end 2^P - 1
sample_*           1 each  the settings and the speed's tests at the sample (below)
sample_power       P+1     the power register at the sample
accumulator        33      the adder's register: remainder (two's complement), then
                           product
dividend           P       the dividend's low bits, fed to the division from the top
signs              P       the remainder's sign after each division step: the quotient's
                           bits inverted (shift register, taking the accumulator's sign
                           on the clock after each step; the multiplication reads it)
addend             32      the divisor (the cruise speed), then the base
multiply_add       1       the next multiplication step adds the addend (an inverted
                           sign bit, registered a clock early)
=================  ======  ===========================================================

Effective duty (``effective_duty``) from a speed s (2^-38 BLU per clock), a cruise
speed c (2^-32) and the settings, with base = the power register (0..2^P):

* not enabled: 0;
* not laser (spindle speed control): base;
* laser, not dynamic (M3 in laser mode): base if s != 0, else 0 (off at rest, where
  grbl's M3 stays on);
* laser and dynamic (M4 in laser mode): base * q / 2^P rounded down, where q = 0 if
  s = 0, else 2^P if s >= c << 6 (also when c = 0), else floor(s * 2^P / (c << 6)):
  the power per length stays that of the cruise speed through accelerations and
  corners, and is the full power at or above the cruise speed.

The unit: one 33-bit adder / subtractor, used once per clock, and shifts (no
multiplier).  Its operands come straight from registers through one level of logic
(the operand's select and sign, and the sample's load, are each a function of at
most four register bits) and its sum goes straight into the accumulator (and the
RTL's copy of its sign), so the adder's carry chain is the only thing between two
registers
(a 33-bit add / subtract whose operand its own sign bit selects, as the reference
loop ``refloop_fold``).  Schedule, by the counter's value during the clock (the
registers take the new value at the clock's end):

* 0 (``at_start``), the sample: the settings registers, the speed input and the cruise
  register as they are during this clock (a ``load``, ``take`` or ``off`` at this edge
  acts from the next sample; ``off`` still clears ``sample_enable``): accumulator =
  s >> 6 (through the adder, adding 0), dividend = the low P bits of M = floor(s * 2^P
  / 2^6) (M >> P is s >> 6), addend = c, and the flags: enable, laser, dynamic, moving
  (s != 0), full (s >> 6 >= c, i.e. s >= c << 6 since c << 6 has six zero low bits;
  true for c = 0).
* 1..P (``dividing``), non-restoring division of M by c, one quotient bit a clock
  (floor(M / c) = floor(s * 2^P / (c << 6)) when not full: then s >> 6 < c and the
  quotient has P bits): the shifted remainder with the next dividend bit (the
  dividend register's top bit; the register shifts up) gets c subtracted when the
  remainder is not negative, c added when it is; the result's sign is the quotient
  bit inverted, shifted into ``signs`` from below on the next clock (2..P + 1, from
  the accumulator's top bit, so the sum feeds nothing but the accumulator; the RTL
  keeps a copy of that bit, ``sign_copy``, to halve its fanout).  The remainder
  stays in [-c, c), so 33 bits hold it (the shifted value's 34th bit is not needed:
  the sum is exact modulo 2^33).  With the full flag set the steps run on and their
  result is unused.
* P + 1 (``clearing``): accumulator = 0, addend = sample_power; multiply_add = the
  quotient's top bit.
* P + 2..2P + 1 (``multiplying``): shift-and-add, the quotient's bits from the top:
  accumulator = 2 accumulator + (multiply_add ? addend : 0) (plus the dividend's top
  bit, 0 by now), ``signs`` shifts up (P + 2..2P, taking the accumulator's top bit,
  unused) and multiply_add takes the next quotient bit; at the end the accumulator is
  base * q < 2^33.
* 2^P - 1 (``at_end``): the duty register takes the effective duty, selected from the
  flags, sample_power (for q = 2^P) and accumulator >> P.  The unit needs 2P + 2 clocks
  (0..2P + 1) <= 2^P - 1 for P >= 4.

So a duty is computed from the sample at the period's start and shown through the
next period: the duty lags the speed (and a new setting) by at least one and at most
two PWM periods, 2^(P+1) clocks (41 us at 50 MHz, P = 10).  The enable pin acts at
once: a load that clears ``enable`` silences ``pwm`` from the next clock.

``pwm``, registered: at each edge it takes ``enable`` as it is after the edge and
(counter < duty) of the clock before the edge.  So during the clock in which the
counter is k + 1 the pin shows enable and k < duty: high for exactly ``duty`` clocks
per period (from the clock with counter 1), one clock after the counter, never a
glitch.  ``off``, ``rst`` and a load without enable clear it at the edge.

``off`` (a level) at an edge: every setting (enable, reverse, laser, dynamic, mist,
flood, power), the duty, ``pwm`` and ``sample_enable`` (so the computation under way
delivers 0) are cleared; it wins over a ``load`` and a take's power at the same edge.
The cruise register and the counter keep running.  ``rst`` (synchronous) clears every register.
"""

from __future__ import annotations

from dataclasses import dataclass

PWM_BITS_RANGE = (4, 16)
POWER_BITS = 17                     # load_power: 0..65536, 65536 = 100 %
POWER_ONE = 1 << 16
SPEED_BITS = 38                     # the profile stage's speed register, 2^-38 BLU / clock
CRUISE_BITS = 32                    # a cruise speed field, 2^-32 BLU / clock
SPEED_SHIFT = SPEED_BITS - CRUISE_BITS      # 6: cruise field -> speed units
ACCUMULATOR_BITS = 33               # remainder in [-c, c), c < 2^32; product < 2^33


def check_pwm_bits(pwm_bits: int) -> None:
    low, high = PWM_BITS_RANGE
    if not low <= pwm_bits <= high:
        raise ValueError(f"PWM_BITS must be {low}..{high}, not {pwm_bits}")


def clamp_power(power: int) -> int:
    """The power as the register holds it: above 65536 counts as 65536."""
    if power < 0:
        raise ValueError(f"power must not be negative, not {power}")
    return min(power, POWER_ONE)


def base_duty(power: int, pwm_bits: int) -> int:
    """power >> (16 - P): 0..2^P."""
    return clamp_power(power) >> (16 - pwm_bits)


def speed_ratio(s: int, c: int, pwm_bits: int) -> int:
    """q: the speed s (2^-38) over the cruise speed c (2^-32) in 1/2^P, 0..2^P."""
    if s == 0:
        return 0
    if s >= c << SPEED_SHIFT:
        return 1 << pwm_bits
    return (s << pwm_bits) // (c << SPEED_SHIFT)


def effective_duty(power: int, enable: int, laser: int, dynamic: int, s: int, c: int,
                   pwm_bits: int) -> int:
    """The duty (0..2^P clocks of a period) the output stage computes from a sample of
    the settings, the speed s and the cruise speed c (see the module's docstring)."""
    check_pwm_bits(pwm_bits)
    if not 0 <= s < 1 << SPEED_BITS or not 0 <= c < 1 << CRUISE_BITS:
        raise ValueError(f"speed {s} or cruise speed {c} out of range")
    base = base_duty(power, pwm_bits)
    if not enable:
        return 0
    if not laser:
        return base
    if not dynamic:
        return base if s else 0
    return (base * speed_ratio(s, c, pwm_bits)) >> pwm_bits


@dataclass
class OutputInputs:
    rst: int = 0
    load: int = 0                   # pulse: the settings registers take the load_* below
    load_power: int = 0             # 0..2^17 - 1 (above 65536 acts as 65536)
    load_enable: int = 0
    load_reverse: int = 0
    load_laser: int = 0
    load_dynamic: int = 0
    load_mist: int = 0
    load_flood: int = 0
    off: int = 0                    # level: clears the settings and the duty; wins over load
    speed: int = 0                  # the profile stage's speed, 2^-38 BLU per clock
    take: int = 0                   # pulse: the cruise register takes take_v_cruise
    take_v_cruise: int = 0          # 2^-32 BLU per clock
    take_set_power: int = 0         # with take: the power register takes take_power
    take_power: int = 0             # 0..2^17 - 1 (above 65536 acts as 65536), as load_power


@dataclass
class OutputPins:
    """The outputs during a clock (all registers)."""

    spindle_enable: int
    spindle_reverse: int
    coolant_mist: int
    coolant_flood: int
    pwm: int
    duty: int


# the registers, in the order the tests report them (the RTL's names without _q)
REGISTERS = ("counter", "duty", "pwm", "enable", "reverse", "laser", "dynamic", "mist",
             "flood", "power", "cruise", "at_start", "dividing", "clearing", "multiplying",
             "shifting", "at_end", "sample_enable", "sample_laser", "sample_dynamic",
             "sample_moving", "sample_full", "sample_power", "accumulator", "dividend", "signs",
             "addend", "multiply_add")


class OutputStage:
    """Clock-by-clock model of ``halfpoint_outputs`` (``pwm_bits`` = PWM_BITS)."""

    def __init__(self, pwm_bits: int = 10):
        check_pwm_bits(pwm_bits)
        self.pwm_bits = pwm_bits
        self.period = 1 << pwm_bits
        self.reset()

    def reset(self) -> None:
        self.counter = 0
        self.duty = 0
        self.pwm = 0
        self.enable = self.reverse = self.laser = self.dynamic = 0
        self.mist = self.flood = 0
        self.power = 0
        self.cruise = 0
        self._decode(0)
        self.sample_enable = self.sample_laser = self.sample_dynamic = 0
        self.sample_moving = self.sample_full = 0
        self.sample_power = 0
        self.accumulator = 0
        self.dividend = 0
        self.signs = 0
        self.addend = 0
        self.multiply_add = 0

    def _decode(self, counter: int) -> None:
        """The schedule's flags for a clock with this counter value (the RTL registers
        them a clock early, from the counter before its increment)."""
        p = self.pwm_bits
        self.at_start = int(counter == 0)
        self.dividing = int(1 <= counter <= p)
        self.clearing = int(counter == p + 1)
        self.multiplying = int(p + 2 <= counter <= 2 * p + 1)
        self.shifting = int(2 <= counter <= 2 * p)
        self.at_end = int(counter == self.period - 1)

    def registers(self) -> dict:
        return {name: getattr(self, name) for name in REGISTERS}

    def outputs(self) -> OutputPins:
        return OutputPins(spindle_enable=self.enable, spindle_reverse=self.reverse,
                          coolant_mist=self.mist, coolant_flood=self.flood,
                          pwm=self.pwm, duty=self.duty)

    def result(self) -> int:
        """The effective duty from the unit's registers (what the duty register takes
        at the wrap; meaningful from counter 2P + 2 on)."""
        if not self.sample_enable:
            return 0
        if not self.sample_laser:
            return self.sample_power
        if not self.sample_moving:
            return 0
        if not self.sample_dynamic or self.sample_full:
            return self.sample_power
        return self.accumulator >> self.pwm_bits

    def step(self, i: OutputInputs) -> OutputPins:
        """The outputs during this clock, then the edge with inputs ``i``."""
        pins = self.outputs()
        self.clock(i)
        return pins

    def clock(self, i: OutputInputs) -> None:
        if i.rst:
            self.reset()
            return
        p = self.pwm_bits
        mask = (1 << ACCUMULATOR_BITS) - 1
        top = ACCUMULATOR_BITS - 1
        # the pin's comparison and the duty's result, from this clock's registers
        below = int(self.counter < self.duty)
        if self.at_end:
            self.duty = self.result()
        # the unit: the adder's operands, all from this clock's registers
        dividend_top = self.dividend >> (p - 1)
        if self.at_start:
            s, c = i.speed, self.cruise
            if not 0 <= s < 1 << SPEED_BITS:
                raise ValueError(f"speed {s} out of range")
            shifted = s >> SPEED_SHIFT
        else:
            shifted = ((self.accumulator << 1) | dividend_top) & mask
        subtract = int(self.dividing and not self.accumulator >> top)
        if self.dividing:
            operand = self.addend ^ mask if subtract else self.addend
        else:
            operand = self.addend if self.multiply_add else 0
        total = (shifted + operand + subtract) & mask
        if self.shifting:
            # a clock after each step: its sign, from the accumulator register
            self.signs = ((self.signs << 1) & (self.period - 1)) | (self.accumulator >> top)
        if self.at_start:
            self.accumulator = total
            self.dividend = ((s << p) >> SPEED_SHIFT) & (self.period - 1)
            self.addend = c
            self.sample_power = self.power
            self.sample_enable = self.enable
            self.sample_laser = self.laser
            self.sample_dynamic = self.dynamic
            self.sample_moving = int(s != 0)
            self.sample_full = int(s >> SPEED_SHIFT >= c)
        elif self.clearing:
            self.accumulator = 0
            self.addend = self.sample_power
        elif self.dividing or self.multiplying:
            self.accumulator = total
        if self.dividing:
            self.dividend = (self.dividend << 1) & (self.period - 1)
        # the next step adds the addend: a multiplication step follows and the
        # quotient's next bit (the inverted sign now on top) is 1
        next_counter = (self.counter + 1) & (self.period - 1)
        self.multiply_add = int(p + 2 <= next_counter <= 2 * p + 1
                                and not self.signs >> (p - 1))
        if i.take:
            if not 0 <= i.take_v_cruise < 1 << CRUISE_BITS:
                raise ValueError(f"cruise speed {i.take_v_cruise} out of range")
            self.cruise = i.take_v_cruise
            if i.take_set_power:
                if not 0 <= i.take_power < 1 << POWER_BITS:
                    raise ValueError(f"power {i.take_power} out of range")
                self.power = base_duty(i.take_power, self.pwm_bits)
        if i.off:
            self.enable = self.reverse = self.laser = self.dynamic = 0
            self.mist = self.flood = 0
            self.power = 0
            self.duty = 0
            self.sample_enable = 0
        elif i.load:
            if not 0 <= i.load_power < 1 << POWER_BITS:
                raise ValueError(f"power {i.load_power} out of range")
            self.power = base_duty(i.load_power, self.pwm_bits)
            self.enable, self.reverse = int(bool(i.load_enable)), int(bool(i.load_reverse))
            self.laser, self.dynamic = int(bool(i.load_laser)), int(bool(i.load_dynamic))
            self.mist, self.flood = int(bool(i.load_mist)), int(bool(i.load_flood))
        # the pin: enable after this edge and the comparison of this clock
        self.pwm = int(bool(self.enable and below))
        self.counter = (self.counter + 1) & (self.period - 1)
        self._decode(self.counter)
