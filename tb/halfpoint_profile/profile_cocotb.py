# SPDX-License-Identifier: Apache-2.0
"""cocotb tests of halfpoint_profile: the RTL against ``ProfileStage`` on every clock.

Run by ``test_profile_rtl.py``; W and DIV are read from the design.  The pieces are
kept apart: the stimulus (programs of segments and the events around them) decides
the inputs of a clock, the driver puts them on the pins, the monitor reads the
pins (and the registers), the model is ``halfpoint.spec.profile.ProfileStage``, and
the checker compares.  Every clock: the combinational view (pop, take, stopped,
holding) after the inputs settle, the registered outputs (speed, dry, busy) after
the edge and again before the next (still the same with the next clock's inputs
on), and every register of the model against its RTL counterpart (not with
HP_PROFILE_REGISTERS=0: the pins only; HP_PROFILE_SCOPE names the instance that
holds them when it is not the top, as in the mutation flow's wrapper).
"""

from __future__ import annotations

import copy
import os
import random
from dataclasses import dataclass, field

import cocotb
from cocotb.clock import Clock
from cocotb.triggers import FallingEdge, ReadOnly

from halfpoint.sim.design import read_parameters
from halfpoint.spec import profile as pf
from halfpoint.spec.profile import (CLASS_AXIS, CLASS_DIAG, CLASS_LINE, COST_AXIS,
                                    OVERRIDE_ONE, ProfileInputs, ProfileParams,
                                    ProfileStage)

W = DIV = 0         # the design's parameters: bind() reads them
SEED = int(os.environ.get("HP_SEED", "1"))
CLOCKS = int(os.environ.get("HP_PROFILE_CLOCKS", "15000"))    # per test, roughly
# 1: also run long_segment (about 2^(W - 1) clocks; the mutation flow sets it)
LONG = os.environ.get("HP_PROFILE_LONG", "0") == "1"
# rounds of the random corner programs: more with HP_PROFILE_LONG (the mutation run),
# where a kill should not hang on one draw
ROUNDS = 3 if LONG else 1
# 0: compare the pins only (the view and the registered outputs), not the internal
# registers (a measure of what the pins alone tell: the equivalence the mutation
# flow's --prove checks is at the ports)
REGISTERS = os.environ.get("HP_PROFILE_REGISTERS", "1") != "0"
# the instance below the top that holds the registers, "" for the top itself: the
# mutation flow (halfpoint.flows.mutate) sets u_mutants, its wrapper's instance of
# the mutated netlist, whose registers keep their names
SCOPE = os.environ.get("HP_PROFILE_SCOPE", "")


def bind(dut) -> None:
    """Take W and DIV from the design under test (its parameters)."""
    global W, DIV
    W, DIV = read_parameters(dut, "W", "DIV")


def ramp_left_width() -> int:
    """Width of the RTL's ramp_left register (see rtl/halfpoint_profile.v)."""
    return DIV + 42


# --- stimulus: programs and events ------------------------------------------------------------

@dataclass
class Program:
    """A chain of segments: profiles, the cost classes of their moves, and the clock
    (from the program's start) at which each profile and its moves are available."""

    kind: str
    profiles: list
    moves: list
    arrival: list


@dataclass
class Events:
    """What happens around a program, by clock from its start."""

    ready_stall: float = 0.0        # probability that ready is low on a clock
    head_gap: float = 0.0           # probability that the head move is not there yet
    holds: list = field(default_factory=list)       # (from, to) clocks
    overrides: list = field(default_factory=list)   # (from, value), ascending
    stop_at: int | None = None      # stop from this clock until the stage is stopped
    abort_at: int | None = None
    budget: int = 4000              # abort the program after this many clocks
    # abort on the first clock from this one on where the stage pops (the model
    # with the clock's other inputs says so): the pop must not happen
    abort_on_pop: int | None = None
    # ready low on every held clock: the credit fills while the stage slows down
    # under hold, so that at rest it covers the head move (not holding yet)
    stall_while_held: bool = False

    def hold(self, t: int) -> int:
        return int(any(a <= t < b for a, b in self.holds))

    def override(self, t: int) -> int:
        value = OVERRIDE_ONE
        for start, ov in self.overrides:
            if t >= start:
                value = ov
        return value


def moves_of(rng, line: bool, count: int) -> list:
    if line:
        return [CLASS_LINE] * count
    return [rng.choice((CLASS_AXIS, CLASS_DIAG)) for _ in range(count)]


def length_of(moves, line_cost: int) -> int:
    probe = ProfileParams(1, 0, 1, line_cost)
    return sum(pf.move_cost(c, probe) for c in moves)


def planned_program(rng) -> Program:
    """A chain from the host's integer pass: arcs (axis and diagonal moves) and lines
    with their line cost, random lengths, speeds and accelerations; ramps of 6 to 40
    speed steps."""
    count = rng.randint(1, 4)
    # round numbers (powers of two): the credit then lands exactly on a move's cost
    # often, which tells credit >= cost from credit > cost
    round_numbers = rng.random() < 0.3
    lengths, moves, cruise, exits, accels, costs = [], [], [], [], [], []
    for k in range(count):
        line = rng.random() < 0.5
        cost = rng.randint(COST_AXIS // 2, 3 * COST_AXIS) if line else 0
        if round_numbers:
            cost = COST_AXIS << rng.randint(0, 1) if line else 0
            cruise.append(1 << rng.randint(28, 31))
            exit_speed = cruise[-1] >> rng.randint(1, 3)
            accels.append((cruise[-1] << 6) >> rng.randint(4, 6))
        else:
            cruise.append(rng.randint(1 << 28, 1 << 31))
            exit_speed = rng.randint(0, 1 << 30)
            accels.append(min((cruise[-1] << 6) // rng.randint(6, 40), (1 << 34) - 1))
        m = moves_of(rng, line, rng.randint(3, 40))
        moves.append(m)
        costs.append(cost)
        lengths.append(length_of(m, cost))
        exits.append(0 if k == count - 1 else rng.choice((0, exit_speed)))
    profiles = pf.plan_integer(lengths, cruise, exits, accels, DIV, costs)
    arrival = [0] * count
    return Program("planned", profiles, moves, arrival)


TOP_SPEED = (1 << 32) - 1
TOP_ACCEL = (1 << 34) - 1


def raw_profile(rng, length: int, line_cost: int) -> ProfileParams:
    """Any legal ProfileParams (check() passes), extremes included."""
    v_cruise = rng.choice((TOP_SPEED, 0, rng.randint(1, 1 << 20), rng.randint(1 << 26, TOP_SPEED),
                           rng.randint(1 << 29, TOP_SPEED), rng.randint(1 << 29, TOP_SPEED)))
    v_exit = rng.choice((0, v_cruise, rng.randint(0, v_cruise)))
    accel = rng.choice((1, TOP_ACCEL, rng.randint(1, TOP_ACCEL), rng.randint(1 << 31, TOP_ACCEL),
                        rng.randint(1 << 31, TOP_ACCEL)))
    dist_top = (1 << pf.distance_bits(W)) - 1
    d_exit = rng.choice((0, dist_top, rng.randint(0, length + length // 4),
                         rng.randint(0, length)))
    d_stop = rng.choice((0, d_exit, rng.randint(0, d_exit)))
    p = ProfileParams(v_cruise, v_exit, accel, line_cost, d_exit, d_stop)
    p.check(W)
    return p


def ceiling_program(rng) -> Program:
    """One-move segments whose line cost is far below the speed: every take carries
    the credit (a take gains the speed without the segment's cap check), and it climbs
    to the ceiling, 2^41, where it gains nothing.  Before the ceiling it grew without
    bound and the 42-bit register wrapped.  Reaching the ceiling takes about
    sqrt(2^(DIV + 8)) one-move segments (the speed ramps from 0)."""
    dist_top = (1 << pf.distance_bits(W)) - 1
    count = 48 << max(0, (DIV - 1) // 2)
    profiles = [ProfileParams(TOP_SPEED, TOP_SPEED, TOP_ACCEL, rng.randint(1, 1 << 12),
                              dist_top, dist_top) for _ in range(count - 1)]
    profiles.append(ProfileParams(TOP_SPEED, 0, TOP_ACCEL, 1, 0, 0))
    return Program("raw", profiles, [[CLASS_LINE]] * count, [0] * count)


def raw_program(rng) -> Program:
    """Profiles straight from ProfileParams, not from the planner: d_exit 0 or past
    the end, v_exit = v_cruise, accel 1 and 2^34 - 1, line costs up to 2^18 - 1.
    Two corners on purpose: a segment of 2^18 - 1 line costs hands a large credit
    to one of tiny line costs (its credit far above the new cap: no gain until it is spent
    staircase), and a segment entered at full speed with a cruise speed far below
    it (the staircase's remainder falls by about v every clock, down to its floor)."""
    dist_top = (1 << pf.distance_bits(W)) - 1
    kind = rng.random()
    if kind < 0.2:
        big = ProfileParams(TOP_SPEED, TOP_SPEED, TOP_ACCEL, (1 << 18) - 1, dist_top, dist_top)
        cost = rng.randint(1, 100)
        small = ProfileParams(rng.randint(1 << 28, TOP_SPEED), 0, rng.randint(1, TOP_ACCEL),
                              cost, 0, 0)
        return Program("raw", [big, small],
                       [[CLASS_LINE] * rng.randint(2, 6), [CLASS_LINE] * rng.randint(5, 40)],
                       [0, 0])
    if kind < 0.4:
        fast = ProfileParams(TOP_SPEED, TOP_SPEED, TOP_ACCEL, 0, dist_top, dist_top)
        slow = ProfileParams(rng.randint(1, 1 << 24), 0, rng.randint(1 << 20, TOP_ACCEL), 0,
                             0, 0)
        return Program("raw", [fast, slow], [moves_of(rng, False, rng.randint(30, 60)),
                                             moves_of(rng, False, rng.randint(20, 300))], [0, 0])
    if kind < 0.55:
        # line iterations far below one BLU at full speed: the stage pops every
        # clock and the credit stays capped while the staircase steps
        count = rng.randint(1, 2)
        profiles, moves = [], []
        for _ in range(count):
            cost = rng.randint(1 << 10, 1 << 14)
            m = [CLASS_LINE] * rng.randint(100, 300)
            v_cruise = rng.randint(1 << 30, TOP_SPEED)
            d_exit = rng.randint(0, length_of(m, cost) // 3)
            profiles.append(ProfileParams(v_cruise, rng.randint(0, v_cruise),
                                          rng.randint(1 << 28, 1 << 32), cost, d_exit,
                                          rng.randint(0, d_exit)))
            moves.append(m)
        return Program("raw", profiles, moves, [0] * count)
    if kind < 0.7:
        # fine costs at low speeds: the credit often covers a move exactly (credit
        # >= cost and credit > cost differ)
        count = rng.randint(1, 3)
        profiles, moves = [], []
        for _ in range(count):
            cost = rng.randint(1, 64)
            m = [CLASS_LINE] * rng.randint(20, 80)
            v_cruise = rng.randint(1 << 16, 1 << 21)
            d_exit = rng.randint(0, length_of(m, cost))
            profiles.append(ProfileParams(v_cruise, rng.choice((0, v_cruise >> 1)),
                                          max(1, (v_cruise << 6) >> rng.randint(1, 4)), cost,
                                          d_exit, rng.randint(0, d_exit)))
            moves.append(m)
        return Program("raw", profiles, moves, [0] * count)
    count = rng.randint(1, 4)
    profiles, moves = [], []
    for _ in range(count):
        line = rng.random() < 0.5
        if line:
            cost = rng.choice((1, (1 << 18) - 1, rng.randint(1, (1 << 18) - 1),
                               rng.randint(COST_AXIS, 2 * COST_AXIS)))
        else:
            cost = 0
        m = moves_of(rng, line, rng.randint(1, 40))
        profiles.append(raw_profile(rng, length_of(m, cost), cost))
        moves.append(m)
    return Program("raw", profiles, moves, [0] * count)


def random_events(rng, program: Program, calm: bool) -> Events:
    """Ready stalls, late profiles (dry queue), hold pulses, override changes (0,
    above 128), stop and abort, each with some probability."""
    ev = Events(budget=rng.randint(1500, 3000))
    if calm:
        return ev
    horizon = 1500
    if rng.random() < 0.5:
        ev.ready_stall = rng.choice((0.1, 0.3, 0.6))
    if rng.random() < 0.3:
        ev.head_gap = rng.choice((0.05, 0.3))
    if rng.random() < 0.5:
        gaps = [0] + [rng.choice((0, 0, rng.randint(0, 600), rng.randint(0, 2000)))
                      for _ in program.profiles[1:]]
        program.arrival = [max(gaps[:k + 1]) for k in range(len(gaps))]
    for _ in range(rng.choice((0, 0, 1, 2, 3))):
        a = rng.randint(0, horizon)
        ev.holds.append((a, a + rng.choice((1, 5, rng.randint(10, 800)))))
    for _ in range(rng.choice((0, 0, 1, 3, 6))):
        ev.overrides.append((rng.randint(0, horizon),
                             rng.choice((128, 128, 127, 96, 64, 33, 1, 0, 129, 200, 255))))
    ev.overrides.sort()
    if rng.random() < 0.2:
        ev.stop_at = rng.randint(0, horizon)
    if rng.random() < 0.2:
        ev.abort_at = rng.randint(0, horizon)
    return ev


class Stimulus:
    """Runs programs as the core would: the head of the move queue is the current
    segment's next move, the next profile is there from its arrival on, and the
    events of the program set hold, stop, override, ready and abort.  It learns
    what happened from the view of the clock (``advance``), as the core does."""

    def __init__(self, rng: random.Random):
        self.rng = rng
        self.program: Program | None = None
        self.events = Events()
        self.programs = {"planned": 0, "raw": 0, "aligned": 0}
        self.ends = {"done": 0, "stopped": 0, "aborted": 0, "budget": 0}
        self.pops_aborted = 0       # aborts on a clock where the stage would pop

    def start(self, program: Program, events: Events) -> None:
        self.program, self.events = program, events
        self.seg_in, self.cur_seg, self.idx, self.t = 0, -1, 0, 0
        self.programs[program.kind] += 1

    def inputs(self, model: ProfileStage) -> ProfileInputs:
        rng, prog, ev, t = self.rng, self.program, self.events, self.t
        n = len(prog.profiles)
        next_ok = self.seg_in < n and t >= prog.arrival[self.seg_in]
        head = (self.cur_seg >= 0 and model.cur is not None
                and rng.random() >= ev.head_gap)
        inp = ProfileInputs(
            head_valid=int(head),
            head_class=rng.randint(0, 3), head_last=rng.randint(0, 1),
            ready=int(rng.random() >= ev.ready_stall),
            next_valid=int(next_ok),
            next_profile=prog.profiles[self.seg_in] if next_ok else None,
            hold=ev.hold(t),
            stop=int(ev.stop_at is not None and t >= ev.stop_at),
            override=ev.override(t),
            abort=int(t == ev.abort_at or t == ev.budget))
        if head:
            moves = prog.moves[self.cur_seg]
            inp.head_class = moves[self.idx]
            inp.head_last = int(self.idx == len(moves) - 1)
        if ev.stall_while_held and inp.hold:
            inp.ready = 0
        if ev.abort_on_pop is not None and t >= ev.abort_on_pop and model.view(inp).pop:
            inp.abort = 1
            self.pops_aborted += 1
        return inp

    def advance(self, inp: ProfileInputs, view, model: ProfileStage) -> bool:
        """Account for the clock that ended; True when the program is over."""
        self.t += 1
        if inp.abort:
            self.ends["budget" if self.t - 1 == self.events.budget else "aborted"] += 1
            return True
        if view.pop:
            self.idx += 1
            if inp.head_last:
                self.cur_seg, self.idx = -1, 0
        if view.stopped:
            self.ends["stopped"] += 1
            return True
        if view.take:
            self.cur_seg, self.idx = self.seg_in, 0
            self.seg_in += 1
        if self.seg_in == len(self.program.profiles) and model.cur is None and model.v == 0:
            self.ends["done"] += 1
            return True
        return False


# --- programs aimed at the staircase's returns and at near-exact speeds ---------------------

def aligned_speeds(rng, offset: int | None = None) -> tuple:
    """(v_cruise, v_exit, accel) fields whose register values lie a whole number of
    speed steps apart give or take a few LSB (or up to 2^20): the cruise speed k
    steps from 0, the exit speed m steps below it.  The speed's clamp at its target,
    the hold's last step to 0 and the staircase's way to its floor are then decided
    by a compare within a few LSB of its threshold, where a stuck low bit of its
    carry-save sum or a compare off by one changes the outcome."""
    k = rng.choice(range(3, 12, 2))                 # odd: invertible modulo 64
    if offset is None:
        offset = rng.choice((rng.randint(-6, 6), rng.randint(-(1 << 20), 1 << 20)))
    top = min(((1 << 38) - (1 << 21)) // k, (1 << 34) - 64) >> 6
    accel = (rng.randint(1 << 16, top) << 6) + (-offset * pow(k, -1, 64)) % 64
    peak = k * accel + offset                       # a multiple of 64
    m = rng.randint(1, k - 1)
    below = peak - m * accel - rng.choice((rng.randint(-6, 6), rng.randint(0, 1 << 20)))
    v_exit = min(max(below, 0) >> pf.SPEED_SHIFT, peak >> pf.SPEED_SHIFT)
    return peak >> pf.SPEED_SHIFT, rng.choice((v_exit, v_exit, 0)), accel


def aligned_program(rng, dry_exit: bool = False, offset: int | None = None) -> Program:
    """Two planned segments (axis and diagonal moves) with ``aligned_speeds``, the
    first long enough to reach its cruise speed, the second of 3 to 10 moves;
    ``dry_exit``: the first with an exit speed above 0, so that it has a dry
    staircase (d_stop before d_exit)."""
    speeds = [aligned_speeds(rng, offset), aligned_speeds(rng)]
    cruise, v_exit, accel = speeds[0]
    if dry_exit:
        v_exit = min(v_exit, cruise - 1) or cruise >> rng.randint(1, 3)
    run_up = pf.accel_distance(0, cruise << pf.SPEED_SHIFT, accel, DIV) >> pf.COST_SHIFT
    moves = [moves_of(rng, False, 2 * run_up // COST_AXIS + rng.randint(4, 20)),
             moves_of(rng, False, rng.randint(3, 10))]
    profiles = pf.plan_integer([length_of(m, 0) for m in moves], [cruise, speeds[1][0]],
                               [v_exit, 0], [accel, speeds[1][2]], DIV, [0, 0])
    return Program("aligned", profiles, moves, [0, 0])


def model_states(start: ProfileStage, program: Program, events: Events,
                 clocks: int) -> list:
    """The model's registers before each clock of ``program`` run from the state
    ``start`` (a copy is run: the stimulus is decided by the model's state and the
    events, so a run on the bench follows the same clocks until an input
    differs), up to ``clocks`` clocks or the first segment's end."""
    model, stim = copy.deepcopy(start), Stimulus(random.Random(0))
    stim.start(program, events)
    states = []
    for _ in range(clocks):
        states.append((model.ramp_on, model.ramp_dry, model.past_exit, model.ramp_v, model.v))
        inp = stim.inputs(model)
        w = model.clock(inp)
        if stim.advance(inp, w, model) or (stim.seg_in == 1 and model.cur is None):
            break
    return states


DRY_RETURNS = ("before_exit", "above_exit_plus_accel", "above_exit", "below_exit")


def dry_return_program(rng, wanted: str, model: ProfileStage) -> tuple:
    """An ``aligned_program`` whose second profile comes while the first segment's
    dry staircase runs (``wanted``, one of DRY_RETURNS: before d_exit, where the
    staircase stops, or after it, with the staircase's speed at or above the exit
    speed plus a step, at or above the exit speed, or below it, where it returns to
    the exit speed), found by running the model from its state ``model``;
    (program, events), or (None, None) after 30 draws without one."""
    for _ in range(30):
        program = aligned_program(rng, dry_exit=True)
        first = program.profiles[0]
        if not first.v_exit or first.d_stop >= first.d_exit:
            continue
        events = Events(budget=5000)
        program.arrival = [0, 1 << 30]
        exit_speed = first.v_exit << pf.SPEED_SHIFT
        found = {k: [] for k in DRY_RETURNS}
        for t, (on, dry, past_exit, ramp_v, _) in enumerate(model_states(model, program,
                                                                         events, 4000)):
            if not (on and dry):
                continue
            if not past_exit:
                found["before_exit"].append(t)
            elif ramp_v >= exit_speed + first.accel:
                found["above_exit_plus_accel"].append(t)
            elif ramp_v >= exit_speed:
                found["above_exit"].append(t)
            else:
                found["below_exit"].append(t)
        if found[wanted]:
            program.arrival = [0, rng.choice(found[wanted])]
            return program, events
    return None, None


def hold_from_cruise_program(rng, model: ProfileStage) -> tuple:
    """An ``aligned_program`` whose first cruise speed is 1 to 4 LSB off a whole
    number of steps, held from a clock at that speed until rest: the last step down
    lands 1 to 4 LSB above 0 (found by running the model from its state ``model``);
    (program, events), or (None, None) after 30 draws without one."""
    for _ in range(30):
        program = aligned_program(rng, offset=rng.choice((-1, 1)) * rng.randint(1, 4))
        events = Events(budget=5000)
        peak = program.profiles[0].v_cruise << pf.SPEED_SHIFT
        at_peak = [t for t, state in enumerate(model_states(model, program, events, 4000))
                   if state[4] == peak]
        if at_peak:
            start = at_peak[0] + rng.randint(0, 8)
            events.holds.append((start, start + (13 << DIV)))
            return program, events
    return None, None


def override_staircase_program(rng) -> tuple:
    """A segment under an override below 128 whose exit staircase starts at once
    (d_exit 0) and whose first step lands 1 to 4 LSB above or below the override's
    product: the speed step is the cruise speed less that product less the offset.
    The target's choice between the staircase and the product is then a compare
    at its threshold; (program, events)."""
    ov = rng.randint(72, 127)
    while True:
        peak = rng.randint(1 << 24, (1 << 32) - 1) << pf.SPEED_SHIFT
        offset = rng.choice((-1, 1)) * rng.randint(1, 4)
        accel = peak - ((peak * ov) >> 7) - offset
        if 0 < accel < 1 << 34:
            break
    level = ((peak << DIV) >> pf.SPEED_FRAC) + 1            # BLU of the first level
    profile = ProfileParams(peak >> pf.SPEED_SHIFT, 0, accel, 0, 0, 0)
    events = Events(budget=5000)
    events.overrides.append((0, ov))
    return Program("aligned", [profile], [moves_of(rng, False, 2 * level + 2)], [0]), events


FLOORS_NEAR_CRUISE = ("creep_above", "creep_below", "exit_below")


def floor_near_cruise_program(rng, kind: str, offset: int = 0) -> Program:
    """One segment (axis and diagonal moves) whose exit staircase starts at once
    (d_exit 0) and whose floor lies just off its cruise speed: the creep speed
    (v_exit 0: the floor is the speed step) 1 to 4 LSB above the cruise speed
    (``creep_above``: the staircase's speed passes the cruise speed, which stays the
    target), up to 2^15 LSB below it (``creep_below``), or an exit speed 1 to 511
    field LSB (64 to 32,704 LSB) below it (``exit_below``, the planner's exit a hair
    under the cruise speed).  The target's choice between the staircase and the
    cruise speed is then decided this close to its threshold.  Speed steps near the
    cruise speed keep the cruise speed below 2^28 field LSB (1/16 BLU per clock).
    ``offset`` (1 to 4) fixes ``creep_above``'s distance, else it is random."""
    v_cruise = rng.randint(1 << 25, (1 << 28) - 1)
    cruise = v_cruise << pf.SPEED_SHIFT
    v_exit = 0
    if kind == "creep_above":
        accel = min(cruise + (offset or rng.randint(1, 4)), TOP_ACCEL)
    elif kind == "creep_below":
        accel = cruise - rng.choice((rng.randint(1, 4), rng.randint(1, (1 << 15) - 1)))
    else:
        v_exit = v_cruise - rng.randint(1, 511)
        accel = rng.choice((rng.randint(64, 1 << 12), rng.randint(1 << 12, cruise)))
    moves = moves_of(rng, False, rng.randint(3, 6))
    profile = ProfileParams(v_cruise, v_exit, accel, 0, 0, 0)
    profile.check(W)
    return Program("raw", [profile], [moves], [0])


def dry_floor_program(rng) -> Program:
    """One segment with an exit speed and no next profile, its dry staircase started
    at once (d_stop 0) and stepping straight to its floor, the creep speed ``accel``
    (larger than half the cruise speed), a tick later, with moves left to run at the
    floor: the level kept for the next step down is then 4 accel, every bit of a
    random accel with bit 17 set (the bits of a speed step below 2^18 that the
    planned chains rarely have)."""
    v_cruise = rng.randint(1 << 27, (1 << 28) - 1)
    cruise = v_cruise << pf.SPEED_SHIFT
    accel = rng.randint(cruise // 2 + 1, cruise - 1) | (1 << 17)
    profile = ProfileParams(v_cruise, rng.randint(1, v_cruise), accel, 0,
                            rng.randint(1 << 16, 1 << 20), 0)
    profile.check(W)
    return Program("raw", [profile], [moves_of(rng, False, rng.randint(40, 60))], [0])


BELOW_TERMS = ("accel_floor", "accel_speed", "floor_speed")


def below_term_program(rng, bit: int, term: str) -> Program | None:
    """One segment whose exit staircase starts at once (d_exit 0) and whose first
    step from the cruise speed lands at most 2^(bit + 1) LSB under floor + accel,
    with one carry term of that compare's carry-save level live at ``bit``: the
    RTL decides "below" as accel + (floor + accel) + ~ramp_v >= 0, and ``term``
    names the pair of its three operands that are 1 at ``bit`` (the third 0), so
    that a lost carry there turns the outcome.  Speeds and steps large enough that
    the first step comes within about a hundred clocks.  None when no draw has it
    (below bit 6 the speeds' bits are 0, which rules out some terms)."""
    tick = 1 << DIV
    for _ in range(2000):
        accel = rng.randint(1 << 30, TOP_ACCEL)
        floor = rng.randint(accel, 3 * accel) >> pf.SPEED_SHIFT << pf.SPEED_SHIFT
        # ramp_v = floor + 2 accel - 1 - s with s in [0, 2^(bit + 1)) such that
        # ramp_v is a multiple of 64 (a field speed)
        s_low = (2 * accel - 1) % 64
        span = 1 << (bit + 1)
        if s_low >= span:
            continue
        s = s_low + 64 * rng.randint(0, max(0, (span - 1 - s_low) // 64))
        cruise = floor + 2 * accel - 1 - s
        if cruise >= 1 << 38 or cruise <= floor + accel:
            continue
        a, b, c = accel >> bit & 1, (floor + accel) >> bit & 1, ~cruise >> bit & 1
        if (a, b, c) == {"accel_floor": (1, 1, 0), "accel_speed": (1, 0, 1),
                         "floor_speed": (0, 1, 1)}[term]:
            break
    else:
        return None
    level = ((cruise * tick) >> pf.SPEED_FRAC) + 1         # BLU of the first level
    profile = ProfileParams(cruise >> pf.SPEED_SHIFT, floor >> pf.SPEED_SHIFT, accel, 0, 0, 0)
    profile.check(W)
    return Program("raw", [profile], [moves_of(rng, False, 2 * level + 4)], [0])


# --- driver, monitor, checker ---------------------------------------------------------------

class Driver:
    """Puts a clock's inputs on the pins; fields that are not valid get noise."""

    def __init__(self, dut, rng: random.Random):
        self.dut, self.rng = dut, rng
        self.dist_top = (1 << pf.distance_bits(W)) - 1

    def drive(self, inp: ProfileInputs, rst: int = 0) -> None:
        d, rng = self.dut, self.rng
        d.rst.value = rst
        d.abort_now.value = inp.abort
        d.head_valid.value = inp.head_valid
        d.head_class.value = inp.head_class
        d.head_last.value = inp.head_last
        d.ready.value = inp.ready
        d.next_valid.value = inp.next_valid
        p = inp.next_profile
        if p is None:
            p = ProfileParams(rng.getrandbits(32), rng.getrandbits(32), rng.getrandbits(34),
                              rng.getrandbits(18), rng.randint(0, self.dist_top),
                              rng.randint(0, self.dist_top))
        d.next_v_cruise.value = p.v_cruise
        d.next_v_exit.value = p.v_exit
        d.next_accel.value = p.accel
        d.next_line_cost.value = p.line_cost
        d.next_d_exit.value = p.d_exit
        d.next_d_stop.value = p.d_stop
        d.hold.value = inp.hold
        d.stop.value = inp.stop
        d.feed_override.value = inp.override


VIEW = ("pop", "take", "stopped", "holding")
OUTPUTS = ("speed", "dry", "busy")


class Monitor:
    """Reads the pins, and the registers that mirror the model's."""

    def __init__(self, dut):
        self.dut = dut
        self.inner = dut
        for name in filter(None, SCOPE.split(".")):
            self.inner = getattr(self.inner, name)

    def view(self) -> dict:
        return {k: int(getattr(self.dut, k).value) for k in VIEW}

    def outputs(self) -> dict:
        return {k: int(getattr(self.dut, k).value) for k in OUTPUTS}

    def registers(self, fresh: bool = False) -> dict:
        d = self.inner
        got = {k: int(getattr(d, k + "_q").value) for k in (
            "cur_valid", "accel", "v_cruise", "v", "target", "credit", "gain", "s", "since",
            "last_up", "last_down", "dry", "ov", "ov_acc", "ov_count", "ov_target",
            "past_exit", "past_stop", "ramp_on", "ramp_dry", "ramp_v", "tick_done",
            "ramp_changed")}
        # the credit's compares with the axis and diagonal costs (always) and the
        # whole part of the credit less the line cost (with a segment), whose sign
        # is the third compare the pop uses
        got["covers_axis"] = int(d.covers_axis_q.value)
        got["covers_diagonal"] = int(d.covers_diagonal_q.value)
        if got["cur_valid"]:
            got["over_line"] = signed(int(d.over_line_q.value), 21)
        rw = ramp_left_width()
        if got["ramp_on"]:
            # meaningful only while the staircase runs (the RTL does not clear it)
            got["ramp_left"] = signed(int(d.ramp_left_q.value), rw)
        if got["ramp_on"] and not got["ramp_changed"]:
            # the next level, for either way of the next step, made from the
            # staircase of the clock before: read when it has not moved since
            for k in ("ramp_down_level", "ramp_floor_level"):
                got[k] = signed(int(getattr(d, k + "_q").value), rw)
            got["ramp_below"] = int(d.ramp_below_q.value)
        if got["cur_valid"]:
            for k in ("line_cost", "d_exit", "d_stop", "cap", "v_exit"):
                got[k] = int(getattr(d, k + "_q").value)
        if got["cur_valid"] and not fresh:
            # derived from the fields on a segment's first clock
            for k in ("exit_speed", "exit_plus_accel", "cruise_level"):
                got[k] = int(getattr(d, k + "_q").value)
            for k in ("accel_level", "exit_level"):
                got[k] = signed(int(getattr(d, k + "_q").value), rw)
        return got


def signed(raw: int, width: int) -> int:
    return raw - (1 << width) if raw >> (width - 1) else raw


def model_outputs(model: ProfileStage) -> dict:
    o = model.outputs()
    return {"speed": o.v, "dry": o.dry, "busy": o.busy}


def model_view(view) -> dict:
    return {k: int(bool(getattr(view, k))) for k in VIEW}


def model_registers(model: ProfileStage, fresh: bool = False) -> dict:
    """The model's registers as the RTL holds them; ``fresh``: the clock after a take
    (the RTL derives the staircase's products from the fields on that clock)."""
    want = {"tick_done": int(model.since >= model.tick),
            "cur_valid": int(model.cur is not None), "accel": model.accel,
            "v_cruise": model.v_cruise, "v": model.v, "target": model.target,
            "credit": model.credit, "gain": 0 if model.full else model.v, "s": model.s,
            "since": model.since - 1,
            "last_up": int(model.last_dir == 1), "last_down": int(model.last_dir == -1),
            "dry": model.dry, "ov": model.ov_q, "ov_acc": model.ov_acc,
            "ov_count": model.ov_count, "ov_target": model.ov_target,
            "past_exit": int(model.past_exit), "past_stop": int(model.past_stop),
            "ramp_on": int(model.ramp_on),
            "ramp_dry": int(model.ramp_dry), "ramp_v": model.ramp_v,
            "ramp_changed": int(model.ramp_changed)}
    want["covers_axis"] = int(model.credit >= pf.COST_AXIS << pf.COST_SHIFT)
    want["covers_diagonal"] = int(model.credit >= pf.COST_DIAG << pf.COST_SHIFT)
    if model.cur is not None:
        want["over_line"] = (model.credit >> pf.COST_SHIFT) - model.cur.line_cost
    if model.ramp_on:
        want["ramp_left"] = model.ramp_left
    if model.ramp_on and not model.ramp_changed:
        # the RTL keeps the level of the staircase's next step ready both ways:
        # a step down by accel ((ramp_v << DIV) - accel (2^DIV - 4)) and a step to
        # the floor (floor (2^DIV - 4) + 4 ramp_v), and which one it is
        c, tick = model.cur, 1 << DIV
        floor = model.accel if model.ramp_dry or not c.v_exit else c.v_exit << pf.SPEED_SHIFT
        want.update(ramp_down_level=(model.ramp_v << DIV) - model.accel * (tick - pf.RAMP_LAG),
                    ramp_floor_level=floor * (tick - pf.RAMP_LAG) + pf.RAMP_LAG * model.ramp_v,
                    ramp_below=int(model.ramp_v < floor + model.accel))
    if model.cur is not None:
        c = model.cur
        want.update(line_cost=c.line_cost, d_exit=c.d_exit, d_stop=c.d_stop,
                    v_exit=c.v_exit, cap=c.largest_cost())
    if model.cur is not None and not fresh:
        # the RTL keeps v_exit as the staircase's exit speed (the creep speed for 0)
        # and the products of the levels, derived on the segment's first clock
        exit_speed = c.v_exit << pf.SPEED_SHIFT if c.v_exit else c.accel
        tick = 1 << DIV
        want.update(exit_speed=exit_speed, exit_plus_accel=exit_speed + c.accel,
                    cruise_level=(c.v_cruise << pf.SPEED_SHIFT) * (tick - 1),
                    accel_level=c.accel * (tick - pf.RAMP_LAG),
                    exit_level=exit_speed * (tick - pf.RAMP_LAG))
    return want


class Checker:
    """Compares what the monitor saw with what the model says; counts what it saw."""

    def __init__(self):
        self.clocks = 0
        self.seen = {"pop": 0, "take": 0, "stopped": 0, "holding": 0, "ramp_step": 0,
                     "dry_start": 0, "left_negative": 0, "changed_negative": 0,
                     "capped": 0,
                     "exact_cover": 0, "capped_pop_step": 0, "left_floor": 0,
                     "ceiling": 0, "ceiling_wait": 0, "near_up": 0, "near_down": 0,
                     "held_covered": 0,
                     "floor_above_cruise": 0, "floor_near_cruise": 0}
        self.returns = {k: 0 for k in DRY_RETURNS}
        self.v_before = 0
        self.ceiling_before = False

    @staticmethod
    def _diff(what: str, clock: int, got: dict, want: dict, context: str) -> None:
        bad = [k for k in want if got.get(k) != want[k]]
        assert not bad, f"clock {clock} ({context}) {what}: " + ", ".join(
            f"{k}: rtl={got.get(k)} model={want[k]}" for k in bad)

    def registered(self, clock, got_out, want_out, got_reg, want_reg, context) -> None:
        self._diff("outputs", clock, got_out, want_out, context)
        self._diff("registers", clock, got_reg, want_reg, context)
        if want_reg.get("ramp_left", 0) < 0:
            self.seen["left_negative"] += 1
            # a level ran out on the clock right after the staircase moved: the
            # step waits a clock (the level registers are not the staircase's yet)
            self.seen["changed_negative"] += want_reg["ramp_changed"]
        if want_reg.get("ramp_left") == -pf.ramp_left_floor(DIV):
            self.seen["left_floor"] += 1

    def held(self, clock, got: dict, want: dict, context) -> None:
        self._diff("outputs before the edge", clock, got, want, context)

    def view(self, clock, got: dict, want: dict, w, context) -> None:
        self._diff("view", clock, got, want, context)
        self.clocks += 1
        for k in VIEW:
            self.seen[k] += want[k]
        self.seen["ramp_step"] += int(w.ramp_step)
        self.seen["dry_start"] += int(w.ramp_dry)
        self.seen["capped"] += int(w.gain < self.v_before)
        # a pop with the credit capped, on a clock the staircase steps
        self.seen["capped_pop_step"] += int(w.pop and w.ramp_step and w.gain < self.v_before)
        # at or above the credit's ceiling with a segment, and no pop
        self.seen["ceiling_wait"] += int(self.ceiling_before and not w.pop)
        self.ceiling_before = False

    def credit(self, model: ProfileStage, inp: ProfileInputs) -> None:
        """Before the clock: does the credit cover the head move exactly?"""
        self.v_before = model.v
        self.seen["ceiling"] += int(model.credit >= pf.CREDIT_CEILING)
        self.ceiling_before = model.credit >= pf.CREDIT_CEILING and model.cur is not None
        if model.cur is not None and inp.head_valid:
            cost = pf.move_cost(inp.head_class, model.cur)
            self.seen["exact_cover"] += int(model.credit >> pf.COST_SHIFT == cost)
            # held at rest with the head move covered: it waits for the release
            # (holding, no pop), though the credit has it due (the test
            # owed_move_waits_for_release below has its axes ready too)
            self.seen["held_covered"] += int(bool(inp.hold) and model.v == 0
                                             and model.covers(cost))
        # a step that lands within 4 LSB of its target, not on it
        v, t, a = model.v, model.target, model.accel
        self.seen["near_up"] += int(t > v and 0 < abs(v + a - t) <= 4)
        self.seen["near_down"] += int(t < v and 0 < abs(v - a - t) <= 4)
        if model.cur is not None and model.ramp_on:
            # the staircase's speed above the cruise speed (a creep speed above it)
            # or within 2^15 LSB below it
            cruise = model.cur.v_cruise << pf.SPEED_SHIFT
            self.seen["floor_above_cruise"] += int(model.ramp_v > cruise)
            self.seen["floor_near_cruise"] += int(cruise - (1 << 15) <= model.ramp_v < cruise)
        if model.cur is not None and model.ramp_on and model.ramp_dry and inp.next_valid:
            # the next profile came while the dry staircase runs: where it returns
            exit_speed = model.cur.v_exit << pf.SPEED_SHIFT
            if not model.past_exit:
                self.returns["before_exit"] += 1
            elif model.ramp_v >= exit_speed + model.accel:
                self.returns["above_exit_plus_accel"] += 1
            elif model.ramp_v >= exit_speed:
                self.returns["above_exit"] += 1
            else:
                self.returns["below_exit"] += 1


# --- the loop -------------------------------------------------------------------------------

class Bench:
    def __init__(self, dut, seed: int):
        self.dut = dut
        self.rng = random.Random(seed)
        self.model = ProfileStage(DIV, W)
        self.stim = Stimulus(self.rng)
        self.driver = Driver(dut, random.Random(seed + 1))
        self.monitor = Monitor(dut)
        self.checker = Checker()
        self.clock = 0

    async def start(self) -> None:
        cocotb.start_soon(Clock(self.dut.clk, 10, unit="ns").start())
        await self.reset()

    async def reset(self) -> None:
        """rst for two clocks with noise on every other input."""
        for _ in range(2):
            self.driver.drive(ProfileInputs(head_valid=1, next_valid=1, hold=1,
                                            override=self.rng.randint(0, 255),
                                            head_class=3), rst=1)
            await FallingEdge(self.dut.clk)
            self.model.reset()
        await self.compare_registered("reset")

    async def compare_registered(self, context: str, fresh: bool = False) -> None:
        want = model_registers(self.model, fresh)
        got = self.monitor.registers(fresh) if REGISTERS else want
        self.checker.registered(self.clock, self.monitor.outputs(), model_outputs(self.model),
                                got, want, context)

    async def run_program(self, program: Program, events: Events) -> None:
        self.stim.start(program, events)
        context = f"{program.kind} program {sum(self.stim.programs.values())}"
        while True:
            inp = self.stim.inputs(self.model)
            w = await self.step(inp, context)
            if self.stim.advance(inp, w, self.model):     # reads the model only
                return

    async def step(self, inp: ProfileInputs, context: str):
        """One clock of the given inputs, compared as every other; returns the
        model's view of the clock."""
        self.driver.drive(inp)
        await ReadOnly()
        got = self.monitor.view()
        # the registered outputs still hold the last edge's values with this
        # clock's inputs on (a register clocked on the falling edge shows here)
        self.checker.held(self.clock, self.monitor.outputs(), model_outputs(self.model),
                          context)
        self.checker.credit(self.model, inp)
        w = self.model.clock(inp)
        self.checker.view(self.clock, got, model_view(w), w, context)
        await FallingEdge(self.dut.clk)
        self.clock += 1
        await self.compare_registered(context, fresh=w.take)
        return w

    async def idle(self, clocks: int) -> None:
        """Clocks with nothing queued: noise on the profile fields, random override."""
        for _ in range(clocks):
            inp = ProfileInputs(override=self.rng.randint(0, 255),
                                hold=self.rng.randint(0, 1), head_class=3)
            self.driver.drive(inp)
            await ReadOnly()
            got = self.monitor.view()
            w = self.model.clock(inp)
            self.checker.view(self.clock, got, model_view(w), w, "idle")
            await FallingEdge(self.dut.clk)
            self.clock += 1
            await self.compare_registered("idle")

    def report(self, name: str) -> None:
        self.dut._log.info("%s: W=%d DIV=%d, %d clocks, programs %s, ends %s, seen %s", name,
                           W, DIV, self.checker.clocks, self.stim.programs, self.stim.ends,
                           self.checker.seen)


@cocotb.test()
async def planned_chains(dut):
    """Chains from plan_integer with random stalls of ready, late profiles, hold
    pulses, override changes (0 and above 128), stop with a following program and
    abort; every clock compared."""
    bind(dut)
    bench = Bench(dut, SEED)
    await bench.start()
    k = 0
    wanted = ("pop", "take", "stopped", "holding", "ramp_step", "dry_start")
    ends = ("done", "stopped", "aborted")

    def covered():
        return (all(bench.checker.seen[k] for k in wanted)
                and all(bench.stim.ends[k] for k in ends))
    # at least CLOCKS clocks, and on until every case was seen (at most 4 x CLOCKS)
    least = ROUNDS * CLOCKS
    while bench.checker.clocks < least or (not covered() and bench.checker.clocks < 4 * least):
        program = planned_program(bench.rng)
        events = random_events(bench.rng, program, calm=k % 4 == 0)
        await bench.run_program(program, events)
        if bench.rng.random() < 0.3:
            await bench.idle(bench.rng.randint(1, 20))
        k += 1
    bench.report("planned chains")
    seen = bench.checker.seen
    assert all(seen[k] for k in wanted)
    assert all(bench.stim.ends[k] for k in ends)


@cocotb.test()
async def raw_profiles(dut):
    """Profiles straight from ProfileParams (not planned), the same events, and a
    reset in the middle; every clock compared."""
    bind(dut)
    bench = Bench(dut, SEED + 100)
    await bench.start()
    k = 0
    while bench.checker.clocks < CLOCKS:
        program = raw_program(bench.rng)
        events = random_events(bench.rng, program, calm=k % 5 == 0)
        events.budget = min(events.budget, 1200)
        await bench.run_program(program, events)
        if k == 10:
            await bench.reset()
        k += 1
    if DIV <= 5:
        # last, so that the programs above are the same draws as before it
        program = ceiling_program(bench.rng)
        await bench.run_program(program, random_events(bench.rng, program, calm=True))
    bench.report("raw profiles")
    seen = bench.checker.seen
    assert all(seen[k] for k in ("pop", "take", "ramp_step", "left_negative",
                                 "changed_negative", "capped", "exact_cover",
                                 "capped_pop_step"))
    assert seen["ceiling"] or DIV > 5
    # the remainder's floor, 2^(DIV + 40), is 2^(DIV + 2) clocks of full speed
    # beyond a level: these programs reach it at DIV 3
    assert seen["left_floor"] or DIV > 3


@cocotb.test()
async def dry_returns_and_aligned_speeds(dut):
    """The next profile arriving while the dry staircase runs, once or more in each
    of its four cases (DRY_RETURNS), chains of ``aligned_speeds``: steps that land
    within a few LSB of the cruise speed, the exit speed, the floor and 0 (a hold
    from the cruise speed), and staircases that step to within a few LSB of the
    override's product; every clock compared.  (Written for the mutation run of
    issue 17: its survivors of this kind were bits of these compares and of the
    return from the dry queue.)"""
    bind(dut)
    bench = Bench(dut, SEED + 200)
    await bench.start()
    for wanted in DRY_RETURNS:
        program, events = dry_return_program(bench.rng, wanted, bench.model)
        assert program is not None, f"no chain with a dry return {wanted}"
        await bench.run_program(program, events)
    for k in range(4 * ROUNDS):
        if k % 2:
            program, events = hold_from_cruise_program(bench.rng, bench.model)
            assert program is not None, "no chain held from its cruise speed"
        else:
            # the cruise speed 1 to 4 LSB off a whole number of steps from 0
            offset = bench.rng.choice((-1, 1)) * bench.rng.randint(1, 4)
            program, events = aligned_program(bench.rng, offset=offset), Events(budget=5000)
        await bench.run_program(program, events)
    for k in range(5):
        await bench.run_program(*override_staircase_program(bench.rng))
    # more returns at or above the exit speed, on other speeds: the level such a
    # return keeps (exit_level + 4 ramp_v) over more bit patterns
    for wanted in DRY_RETURNS[1:3] * 3:
        program, events = dry_return_program(bench.rng, wanted, bench.model)
        assert program is not None, f"no chain with a dry return {wanted}"
        await bench.run_program(program, events)
    bench.report("dry returns and aligned speeds")
    assert all(bench.checker.returns.values()), bench.checker.returns
    assert bench.checker.seen["near_up"] and bench.checker.seen["near_down"]


@cocotb.test()
async def override_products(dut):
    """The override's product with many cruise speeds: a profile is taken under hold
    (the speed stays 0), the override changes on 0 to 3 of the next clocks (each
    change restarts the bit-by-bit product), then stays long enough for the product
    to finish (most often values below 128 with most bits set, whose steps carry
    far), and a stop at rest drops the segment; the product's registers and the
    target compared every clock.  (Written for the mutation run of issue 17: a
    carry of the product needs such overrides and cruise speeds.)"""
    bind(dut)
    bench = Bench(dut, SEED + 300)
    await bench.start()
    rng = bench.rng

    def override() -> int:
        return rng.choice((127, 126, 124, 123, 119, 111, 95, 63, rng.randint(0, 255)))
    for _ in range(150):
        cruise = rng.choice((rng.getrandbits(32), TOP_SPEED, rng.randint(1 << 28, TOP_SPEED)))
        profile = ProfileParams(cruise, rng.randint(0, cruise), rng.randint(1, TOP_ACCEL))
        await bench.step(ProfileInputs(next_valid=1, next_profile=profile, hold=1,
                                       override=override()), "override products")
        for _ in range(rng.randint(0, 3)):
            await bench.step(ProfileInputs(hold=1, override=override()), "override products")
        last = override()
        for _ in range(pf.OVERRIDE_STEPS + 1):
            await bench.step(ProfileInputs(hold=1, override=last), "override products")
        assert bench.model.override_settled()
        await bench.step(ProfileInputs(hold=1, stop=1, override=last), "override products")
    bench.report("override products")
    assert bench.checker.seen["take"] == 150 and bench.checker.seen["stopped"] == 150


@cocotb.test()
async def one_step_approaches(dut):
    """Speed steps that land within a few LSB of their target: a profile whose speed
    step is its cruise speed less 1 to 4 LSB (or more, or less, up to 2^12 either
    way) is taken under hold, released (the first step up from rest lands that far
    from the cruise speed, where the clamp's carry-save compare decides), held back
    to rest and dropped by a stop at rest; 10 clocks each, every clock compared.
    (Written for the mutation run of issue 17: bits of the clamp's sum whose
    change flips it only this close to its threshold.)"""
    bind(dut)
    bench = Bench(dut, SEED + 500)
    await bench.start()
    rng = bench.rng
    dist_top = (1 << pf.distance_bits(W)) - 1
    samples = 120
    for _ in range(samples):
        peak = rng.randint(1 << 10, (1 << 28) - 1) << pf.SPEED_SHIFT
        offset = rng.choice((rng.randint(1, 4), rng.randint(-4, -1),
                             rng.randint(-(1 << 12), 1 << 12)))
        profile = ProfileParams(peak >> pf.SPEED_SHIFT, 0, peak - offset, 0, dist_top, dist_top)
        context = "one-step approaches"
        await bench.step(ProfileInputs(next_valid=1, next_profile=profile, hold=1), context)
        for hold in (1, 1, 0, 0, 0, 1, 1, 1):
            await bench.step(ProfileInputs(hold=hold), context)
        await bench.step(ProfileInputs(hold=1, stop=1), context)
    bench.report("one-step approaches")
    seen = bench.checker.seen
    assert seen["take"] == samples and seen["stopped"] == samples
    assert seen["near_up"] >= samples // 2


@cocotb.test()
async def aborts_holds_and_floors(dut):
    """Corners of the pop, the hold, the staircase's floor and the dry flag: an
    abort on a clock where the stage would pop (it must not pop), holds with ready
    low while held (the credit fills as the speed falls, so at rest it covers the
    head move and the stage is not holding), programs with override changes,
    staircases whose floor lies just off the cruise speed
    (``floor_near_cruise_program``), and dry staircases, each followed by a reset
    (the dry flag set and cleared again).  (Written for the mutation run of the
    stable sample: a pop left ungated by the abort, holding without the covered
    move, bits of the compare of the staircase's speed with the cruise speed, and
    the dry flag's register clocked on the falling edge, which the outputs' check
    before each edge sees.)"""
    bind(dut)
    bench = Bench(dut, SEED + 600)
    await bench.start()
    rng = bench.rng
    for _ in range(10 * ROUNDS):
        events = Events(budget=3000, abort_on_pop=rng.randint(0, 300))
        await bench.run_program(planned_program(rng), events)
    for _ in range(8 * ROUNDS):
        start = rng.randint(20, 300)
        events = Events(budget=4000, holds=[(start, start + rng.randint(50, 500))],
                        stall_while_held=True)
        await bench.run_program(planned_program(rng), events)
    for _ in range(6 * ROUNDS):
        program = planned_program(rng)
        events = random_events(rng, program, calm=False)
        events.overrides.append((rng.randint(0, 50), rng.choice((96, 127, 64))))
        events.overrides.sort()
        await bench.run_program(program, events)
    for k, kind in enumerate(FLOORS_NEAR_CRUISE * 4):
        # creep_above at each distance 1 .. 4 (at 1 the floor is the one speed a bit
        # of the compare with the cruise speed decides)
        program = floor_near_cruise_program(rng, kind, offset=k // 3 + 1)
        await bench.run_program(program, Events(budget=5000))
    # dry staircases straight to the floor (dry_floor_program)
    for _ in range(2):
        await bench.run_program(dry_floor_program(rng), Events(budget=5000))
    # the dry flag set on a rising edge (a dry staircase's step), then cleared by a reset
    for _ in range(2):
        program, events = dry_return_program(rng, "below_exit", bench.model)
        assert program is not None, "no chain with a dry return below the exit speed"
        await bench.run_program(program, events)
        await bench.reset()
    bench.report("aborts, holds and floors")
    seen = bench.checker.seen
    assert seen["dry_start"] >= 2, seen
    assert bench.stim.pops_aborted >= 5, bench.stim.pops_aborted
    assert seen["held_covered"] >= 4, seen
    assert seen["floor_above_cruise"] and seen["floor_near_cruise"], seen


@cocotb.test()
async def below_compare_terms(dut):
    """The staircase's compare of its next speed with floor + accel, one step under
    its threshold for every bit of the carry-save sum from 6 to 33 (below 6 where a
    draw has one: the speeds' low six bits are 0) (``below_term_program``), each
    bit with a random one of its three carry terms live; every clock compared.
    (Written for the mutation run of the stable sample: a carry term of that sum
    dropped at bit 25 survived every other test.)"""
    bind(dut)
    bench = Bench(dut, SEED + 700)
    await bench.start()
    rng = bench.rng
    runs = 0
    for bit in range(34):
        for term in rng.sample(BELOW_TERMS, len(BELOW_TERMS)):
            program = below_term_program(rng, bit, term)
            if program is not None:
                break
        assert program is not None or bit < 6, f"no staircase for bit {bit}"
        if program is not None:
            await bench.run_program(program, Events(budget=5000))
            runs += 1
    bench.report("below compare terms")
    assert bench.stim.ends["done"] == runs, bench.stim.ends
    assert bench.checker.seen["ramp_step"] >= runs


@cocotb.test()
async def owed_move_waits_for_release(dut):
    """A hold brings the speed to 0 while no move is queued and the credit already
    covers one; the move that then arrives must not pop while held at rest, and pops
    at the release (the composed core proof found it popping under hold); every
    clock compared."""
    bind(dut)
    bench = Bench(dut, SEED + 500)
    await bench.start()
    model = bench.model
    profile = ProfileParams(1 << 30, 0, 1 << 30, 0, 1 << 20, 1 << 20)

    async def clock(head_valid: int, hold: int):
        inp = ProfileInputs(head_valid=head_valid, head_class=CLASS_AXIS, ready=1,
                            next_valid=int(model.cur is None), next_profile=profile,
                            hold=hold, override=pf.OVERRIDE_ONE)
        return await bench.step(inp, "owed move")

    for _ in range(1 << 12):                # speed and credit grow, no move queued
        await clock(0, 0)
        if model.v and model.credit >> pf.COST_SHIFT >= COST_AXIS:
            break
    assert model.credit >> pf.COST_SHIFT >= COST_AXIS
    for _ in range(1 << 16):                # held down to rest, still no move
        await clock(0, 1)
        if model.v == 0:
            break
    assert model.v == 0 and model.credit >> pf.COST_SHIFT >= COST_AXIS
    for _ in range(20):                     # the owed move arrives: it waits
        w = await clock(1, 1)
        assert w.holding and not w.pop
    w = await clock(1, 0)                   # released: it pops
    assert w.pop
    bench.report("owed move")


@cocotb.test()
async def no_pop_without_a_segment(dut):
    """A segment ends on a diagonal move popped with the credit at its cap, so the
    remainder it leaves covers an axis move; with no next profile there is no segment,
    and a head move then presented must not pop (mutation #199 of 2026-11-25: the pop
    without cur_valid_q survived every other test); every clock compared."""
    bind(dut)
    bench = Bench(dut, SEED + 600)
    await bench.start()
    model = bench.model
    length = 3 * pf.COST_DIAG
    profile = ProfileParams(1 << 30, 0, 1 << 30, 0, length, length)
    cap = (pf.COST_DIAG << pf.COST_SHIFT) << 1

    async def clock(**kw):
        inp = ProfileInputs(override=pf.OVERRIDE_ONE, **kw)
        return await bench.step(inp, "no segment")

    await clock(next_valid=1, next_profile=profile)             # taken idle
    popped = 0
    for _ in range(1 << 16):
        last = int(popped == 2)
        # the last move waits (axes not ready) until the credit is at its cap
        ready = int(not last or model.credit >= cap)
        w = await clock(head_valid=1, head_class=CLASS_DIAG, head_last=last, ready=ready)
        popped += int(w.pop)
        if popped == 3:
            break
    assert popped == 3 and model.cur is None
    assert model.credit >> pf.COST_SHIFT >= COST_AXIS, model.credit
    for _ in range(8):                  # a move with no segment: nothing pops
        w = await clock(head_valid=1, head_class=CLASS_AXIS, ready=1)
        assert not w.pop
    bench.report("no segment")


@cocotb.test()
async def diagonal_covered_just_above_its_cost(dut):
    """The diagonal cost's compare is registered from the credit after a pop: an axis
    move pops at the clock that leaves the credit's whole part in 92688 .. 92697, a few
    units above the diagonal cost, where bit 4 of the compared value is set and the
    constant's is clear, and the diagonal behind it must pop on the next clock
    (mutation #107 of 2026-11-27, that bit forced to 0, survived every other test).
    At 10 whole units (2^-16 BLU) per clock the credit counts up from 0 in steps of 10,
    so it passes through the window (about 16,000 clocks); every clock compared."""
    bind(dut)
    bench = Bench(dut, SEED + 700)
    await bench.start()
    model = bench.model
    units = 10
    length = COST_AXIS + 2 * pf.COST_DIAG
    profile = ProfileParams(units << 16, 0, 1 << 30, 0, length, length)

    async def clock(**kw):
        inp = ProfileInputs(override=pf.OVERRIDE_ONE, **kw)
        return await bench.step(inp, "diagonal remainder")

    await clock(next_valid=1, next_profile=profile)            # taken idle
    for _ in range(20000):
        gain = 0 if model.full else model.v
        after = (model.credit + gain - (COST_AXIS << pf.COST_SHIFT)) >> pf.COST_SHIFT
        if 92688 <= after <= 92697:
            break
        await clock(head_valid=1, head_class=CLASS_AXIS, ready=0)
    else:
        assert False, "the credit never came to leave 92688 .. 92697 after an axis move"
    w = await clock(head_valid=1, head_class=CLASS_AXIS, ready=1)
    assert w.pop and 92688 <= model.credit >> pf.COST_SHIFT <= 92697, model.credit
    w = await clock(head_valid=1, head_class=CLASS_DIAG, ready=1)
    assert w.pop
    for _ in range(1 << 16):
        w = await clock(head_valid=1, head_class=CLASS_DIAG, head_last=1, ready=1)
        if w.pop:
            break
    assert model.cur is None
    bench.report("diagonal remainder")


@cocotb.test()
async def credit_waits_at_cap_and_ceiling(dut):
    """The credit held where it stops growing, every clock compared.  (1) A line
    segment at a slow speed (2^-13 BLU per clock) whose move waits (axes not ready)
    until the credit reaches its cap, twice the line cost: a line cost with bit 13 set
    and bit 4 clear, so that a cap compare off by 16 units there stops the credit four
    clocks late (mutation #183 of 2026-11-28, bit 4 of the cap inverted while bit 13 is
    set, survived every other test).  (2) At DIV <= 5, the ceiling program (one-move
    segments that carry the credit up to 2^41) with the head's axes not ready on
    about half the clocks, so that the credit waits at the ceiling with a segment
    current (mutation #87 of 2026-11-28, bit 31 of the kept credit inverted while its
    bit 41 is set, survived every other test)."""
    bind(dut)
    bench = Bench(dut, SEED + 800)
    await bench.start()
    model, rng = bench.model, bench.rng

    async def clock(**kw):
        inp = ProfileInputs(override=pf.OVERRIDE_ONE, **kw)
        return await bench.step(inp, "credit at its cap")

    for _ in range(3):
        line_cost = ((1 << 13) | rng.randrange(1 << 18)) & ~(1 << 4)
        length = 4 * line_cost
        profile = ProfileParams(1 << 19, 0, 1 << 25, line_cost, length, length)
        await clock(next_valid=1, next_profile=profile)             # taken idle
        for waited in range(1 << 16):
            if model.full:
                break
            await clock(head_valid=1, head_class=CLASS_LINE, ready=0)
        assert model.full and waited > 64, (model.credit, waited)
        cap = (line_cost << pf.COST_SHIFT) << 1
        assert cap <= model.credit < cap + 2 * model.v, model.credit
        for _ in range(16):                 # held there while the move waits
            await clock(head_valid=1, head_class=CLASS_LINE, ready=0)
        w = await clock(head_valid=1, head_class=CLASS_LINE, head_last=1, ready=1)
        assert w.pop and model.cur is None
        await bench.idle(8)
    if DIV <= 5:
        program = ceiling_program(rng)
        events = random_events(rng, program, calm=True)
        events.ready_stall = 0.5
        await bench.run_program(program, events)
        assert bench.checker.seen["ceiling_wait"], bench.checker.seen
    bench.report("credit at its cap")


@cocotb.test(skip=not LONG)
async def long_segment(dut):
    """One line segment of 2^(W - 1) BLU and a little more at the top speed and
    acceleration (line iterations of 4 BLU less 2^-16), its staircase from d_exit
    just beyond 2^(W - 1) BLU: the popped distance s fills its bit W + 15, which a
    shorter segment leaves 0.  About 2^(W - 1) clocks (33,000 at W 16), so only with
    HP_PROFILE_LONG=1 (the mutation flow sets it: #55 of its run, s_plus bit 31 stuck
    at 0, survived every shorter test); every clock compared."""
    bind(dut)
    assert W <= 20, f"long_segment runs 2^(W - 1) clocks: W = {W} is too wide"
    bench = Bench(dut, SEED + 400)
    await bench.start()
    cost = (1 << 18) - 1
    count = ((1 << (W - 1 + pf.COST_FRAC)) + (256 << pf.COST_FRAC)) // cost
    d_exit = (1 << (W - 1 + pf.COST_FRAC)) + (64 << pf.COST_FRAC)
    profile = ProfileParams(TOP_SPEED, 0, TOP_ACCEL, cost, d_exit, d_exit)
    program = Program("raw", [profile], [[CLASS_LINE] * count], [0])
    events = Events(budget=1 << (W + 2))
    await bench.run_program(program, events)
    bench.report("long segment")
    assert bench.stim.ends["done"] == 1 and bench.checker.seen["ramp_step"]
