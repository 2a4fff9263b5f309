# SPDX-License-Identifier: Apache-2.0
"""Executable specification of the motion-profile stage (issue 13, items 2 and 5).

``rtl/halfpoint_profile.v`` is held to this model clock by clock.  Every decision
that is not the pop itself is taken from registers (compares registered a clock
early, the target registered, the override's product pipelined), so that each
register's next value is at most one carry chain away from registers.  It is
integer-only: per clock it uses adders, comparators, constant shifts and muxes;
the one product, the feed override applied to the cruise speed, is a shift-add of
an 8-bit override (see ``ProfileStage.view``).  The host-side functions below
(``ramp_distance``, ``exit_distance``, ``speed_field`` ...) use exact integer and
rational arithmetic and are not part of the hardware.

Place in the pipeline: the arc / line interpolators run ahead into a short move
queue; each queued move carries its cost class (axis move, diagonal arc move, line
iteration) and whether it is its segment's last move.  This stage pops the head
move when its credit covers the move's cost and every axis the move steps is ready
(``ready``, from the STEP/DIR generators); the STEP/DIR generators follow.

Per segment a profile (a PROFILE command ahead of each motion command,
``ProfileParams``) gives the cruise and exit speeds, the speed step per tick, the
line cost and two distances from the segment's start: ``d_exit`` (from there on,
decelerate towards the exit speed) and ``d_stop`` (from there on, decelerate to the
creep speed if the next segment is not available yet: the dry queue).

Fixed point (path unit = one BLU of X, shared with Y; a diagonal arc move is
sqrt(2) of it, a line iteration its Euclidean length / iteration count).  The
bounds come from the issue's ranges (clocks 10-200 MHz, BLU 0.1-10 um, speeds
0.1-500 mm/s, accelerations 10-50,000 mm/s^2, arcs ramp at half of it): path speed
2^-24.3 .. 2^-1 BLU per clock, acceleration 2^-46.2 .. 2^-17.6 BLU per clock^2.

===============  =====  ==================  =========================================
quantity         bits   unit (LSB)          bound and error
===============  =====  ==================  =========================================
v_cruise, v_exit  32    2^-32 BLU/clock     < 1 BLU/clock (>= 2^-1 needed); floor,
  (fields)                                  error < 2^-32 / 2^-24.3 = 0.5 %
accel (field)     34    2^-38 BLU/clock     speed step per tick, < 2^-4 (2^-17.6 *
                        per tick            2^DIV <= 2^-6.7 with choose_div); nearest,
                                            error <= 0.9 % (>= 56 LSB at 2^-46.2, 200 MHz)
line_cost         18    2^-16 BLU           one line iteration, < 4 (sqrt(6) for 6
                                            axes of one BLU); 0 marks an arc
d_exit, d_stop  W+19    2^-16 BLU           < 2^(W+3): a segment's cost length, W the
                                            core's position width (51 bits at W = 32)
speed register v  38    2^-38 BLU/clock     < 1 BLU/clock (the fields shifted by 6)
ramp_v            38    2^-38 BLU/clock     the exit staircase's speed, <= v_cruise
ramp_left     DIV+42    2^-38 BLU           signed; a level is < 2^(DIV+38) + 2^40;
                                            saturates at -2^(DIV+40) (see below)
target            38    2^-38 BLU/clock     <= v_cruise x 2^6, registered a clock ahead
ov_acc            38    2^-32 BLU/clock     the override's product, bit by bit: after
                                            k < 8 steps v_cruise x (ov_q's top k of 8
                                            bits) <= v_cruise x 2^6 (ov_q <= 128)
ov_target         38    2^-38 BLU/clock     (v_cruise << 6) * ov_q >> 7 = ov_acc >> 1
                                            <= v_cruise x 2^6
ov_count           4    steps               8 .. 1 while the product runs, 0 when done
credit            42    2^-38 BLU           < cap + 2 v (v is added on the clock after
                                            it reached the cap, cap = 2 * largest
                                            cost <= 2^41 - 2^23), and < 2^41 + 2^39
                                            whatever the segments (CREDIT_CEILING)
distance s      W+19    2^-16 BLU           as d_exit (sum of the popped costs)
tick counter     DIV    clocks              1 .. 2^DIV, saturating
===============  =====  ==================  =========================================

ramp_left: a level (2^DIV clocks of the staircase's speed) ends with the remainder
at most one clock's gain below 0 when every level is longer than a clock's gain
(planned profiles).  With profiles not from the planner (a segment entered at a
speed above 2^DIV times its staircase's speed) the remainder falls by about v on
every clock for as long as the segment lasts: unbounded, it needed max(W + 43,
DIV + 40) bits (found by the RTL's first version: minus the popped costs of a
whole segment, plus a negative gain when a carried credit was above the new cap).
Only its sign decides, and the credit's gain is never negative now, so it
saturates at -2^(DIV+40): DIV + 42 bits signed whatever W.

A profile command therefore needs 32 + 32 + 34 + 18 + 2 (W + 19) = 218 bits at
W = 32: it fits the 224 bits of a 256-bit beat after the 32-bit opcode word.

Per clock (``ProfileStage.clock``); "registered" means computed from the registers
of this clock and used on the next one:

* credit += v while a segment is current, unless the credit was at or above its
  cap (twice the segment's largest cost: arcs the diagonal cost, lines the line
  cost) on the clock before (``full``, registered), so credit cannot pile up
  while nothing can move.  A segment's end clears ``full`` (it belongs to its
  segment), but a credit at or above CREDIT_CEILING = 2^41 (above every cap) sets
  it whatever the segment: a take would otherwise gain v unchecked, and a chain of
  one-move segments whose line cost is below the speed (a Z line when Z's BLU is
  finer than X's) grew the credit without bound (found by the profile stage's
  formal proof; the 42-bit register wrapped).  So credit < 2^41 + 2^39.  A move pops when the head is valid, credit >= its cost,
  ``ready``, and not ``stop`` at rest; credit -= cost, s += cost; on the segment's
  last move the next profile becomes current (if available), s restarts at 0 and
  the credit's remainder is carried.  The pop is the one decision taken in the
  clock (from the credit register and the inputs).  E = s + credit (the distance
  earned, exact to one clock, not only the distance popped) drives everything
  below; its gain is v or 0, never negative.
* ``past_exit`` / ``past_stop``: E >= d_exit / E >= d_stop, registered (false on a
  segment's first clock).
* the exit staircase (``_ramp``): a speed limit that starts at the segment's peak
  on a clock with ``past_exit`` (or ``past_stop`` while the next profile is not
  available and the exit speed is not 0: the dry queue; its first step sets the
  sticky flag ``dry``) and
  steps down by ``accel`` on each clock that starts with its remainder
  ``ramp_left`` negative (the sign of a register), down to the exit speed (to the
  creep speed, one speed step, when the exit speed is 0 or the queue is dry, so
  the segment finishes), except on the clock right after it started, stepped or
  returned from the dry queue (``ramp_changed``): the level of its next step is
  made from its speed and floor as they are after such an edge, and registered, so
  it is ready a clock later.  With planned profiles and DIV >= 2 a level outlasts
  two clocks (the speed is at most the staircase's level above), so this delays
  no step but one whose level ran out at a return from the dry queue (by a clock);
  it halves the rate of the catch-up steps of a staircase that a profile not from
  the planner left far behind.  The remainder falls by E's gain each clock; the
  first level is (2^DIV - 1) clocks of the peak, each further one 2^DIV clocks of
  its speed plus RAMP_LAG = 4 times the step that started it (the speed follows a
  step three clocks late, spending them at the level above).  So at full speed its
  steps come exactly a tick apart, the first a tick after its start, and the speed
  is exactly the time staircase of ``exit_ramp_distance``; slower
  (override, hold, stalls) it keeps the same distances, so the stage rejoins it
  instead of finishing the ramp early and creeping the rest.  If the next profile
  arrives while it heads for the creep speed, it returns to the plan (off before
  d_exit, else floor back to the exit speed).
* the override's product ``(v_cruise << 6) * ov >> 7`` = ``v_cruise * ov >> 1`` (ov in
  1/128, 0..128, registered as ``ov_q``) is computed bit by bit from the ``v_cruise``
  register (the last current segment's, kept after it ends), one add a clock:
  ``ov_acc`` becomes twice itself plus ``v_cruise`` where the override's bit is set,
  its 8 bits from the top (``OVERRIDE_STEPS``), and the eighth sum, halved, goes to
  ``ov_target``.  An edge that changes ``ov_q``, or takes a segment while the
  override is below 128, restarts it (``ov_count`` = 8), so ``ov_target`` is the new
  product 8 clocks after the edge that changed an operand and the old one until
  then.  At 128 the product is not read (below), so a take leaves it as it is.  The
  override changes rarely and the speed steps once a tick: one adder replaces the
  eight-term shift-add.
* the target, registered: 0 under ``hold`` or ``stop`` or with no segment; else the
  least of the cruise speed, ``ov_target`` unless the override is 128 (100 %: the
  product would be the cruise speed, so a take needs no product), and the
  staircase while it runs.  The cruise speed also bounds the stale product of a
  segment's first clocks.
* the speed steps by ``accel`` towards the registered target (never past it); two
  steps in the same direction are at least 2^DIV clocks apart, a step in the
  other direction may come at once.  So in any window of 2^DIV clocks the speed
  changes by at most ``accel``: the acceleration limit, measured over a tick.

Peers: the speed changes once per period as in LinuxCNC's trajectory planner
(``tp.c``, ``tpCalculateTrapezoidalAccel``, once per servo period; it limits the
speed by the distance to go, v_f^2 + 2 a dx, with a square root the stage avoids
by taking d_exit from the host) and Smoothieware's acceleration ticks
(``StepTicker``, ``set_acceleration_ticks_per_second``, 1000 per second); the
distance where deceleration starts is Marlin's / Smoothieware's ``decelerate_after``
and grbl's ``st_prep_t.decelerate_after`` (from the planner's ``accelerate_until``
/ ``decelerate_after`` arithmetic), here in path cost units and compared with the
earned distance every clock; the host's backward and forward passes are grbl's
``planner_recalculate`` on the stage's own integers (``plan_integer``).

Why not the lead's free-running tick with a fixed d_exit: a decision once per tick
starts the deceleration up to a tick of cruise distance late, so the ramp runs out
of segment with the speed still about sqrt(2 v accel) above the exit speed (14 steps
for a ramp of 100 steps), or, planned a tick early, ends early and creeps the rest
at the exit speed (at the creep speed that doubles the ramp's time).  And a fixed
d_exit with a time staircase finishes a slowed ramp (override 50 %: a quarter of
the planned distance) early and creeps the rest: 2.95 times the full-speed time
for the 1500-BLU segment of the tests, 1.79 times with the distance-driven one.

Feed hold, stop, override (issue 13, item 5): hold decelerates at ``accel`` per tick
along the path, across segment boundaries, to rest, and stays (``holding``: hold and
v = 0; then no move pops, not even one the credit already covers: such a move, owed
by the deceleration, pops at the release); releasing it accelerates back to the
target.  Stop does the same and, at rest, drops the current segment and credit
(``stopped``; the core flushes its queues while stop is high at rest).  The override
acts on the target, so its changes ramp at ``accel`` like any change of target.
Moves are only delayed, never reordered, merged or dropped (except by stop).

Dry queue: from ``d_stop`` on, with no next profile, the stage decelerates to the
creep speed, so the segment ends at that speed and the stage then stops (one step
of ``accel``).  Where the segment is too short for that (``d_stop`` = 0 and the
entry speed too high) the deceleration starts at the segment's start, the segment
ends above the creep speed and the speed falls to 0 at once when it ends: the one
case where the acceleration limit is not kept; ``dry`` flags it.

Bounds (proved where said, else measured by the tests):

* no events, profiles from ``plan_integer``: every segment's last move is made at
  exactly its exit speed (creep speed for 0); the speed never exceeds the peak and
  stays within ``accel`` of the planned curve v_plan(s) = min(v_cruise,
  sqrt(v_exit^2 + 2 (accel / 2^DIV) (L - s))): the staircase is above the linear
  ramp by less than a step.  Exact for DIV >= 2 (a level must outlast the three
  clocks of lag).
* any pattern of hold, override, dry queue, STEP/DIR stalls: measured at most 0.82
  steps above v_plan(s) (the random event runs of the tests; 1.34 before the
  decisions were registered); the tests hold it to 2 steps.  The override toggling
  every 29 clocks through a long ramp: 0.19 steps (1.49 before).
* the speed changes by at most ``accel`` in any 2^DIV clocks (proved by the
  cadence rule), except the documented dry case above.
* creep (clocks at the exit speed before the last move, no events): at most the
  distance of the two clocks between E reaching d_exit and the staircase's
  start, 2 v_peak / exit speed clocks, plus the 2^-16 rounding of d_exit;
  triangles whose peak the staircase reaches only in part more.
* the host's reach test (``accelerates``) adds a tick and four clocks of v_peak to
  the worst-phase acceleration distance: the registered target and the override
  pipeline may hold a segment's first step up back by three clocks or clamp it
  at the previous segment's product, which costs up to a tick.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from fractions import Fraction

from .encoding import OUTPUT_POWER_FULL

# --- fixed point ----------------------------------------------------------------------------

COST_FRAC = 16                      # costs and distances: BLU x 2^16
SPEED_FRAC = 38                     # speed register, speed step, credit: BLU x 2^38
FIELD_SPEED_FRAC = 32               # v_cruise / v_exit fields: BLU per clock x 2^32
SPEED_SHIFT = SPEED_FRAC - FIELD_SPEED_FRAC     # 6: field -> register
COST_SHIFT = SPEED_FRAC - COST_FRAC             # 22: cost -> credit units
FIELD_SPEED_BITS = 32               # v < 1 BLU per clock
ACCEL_BITS = 34                     # speed step < 2^-4 BLU per clock
LINE_COST_BITS = 18                 # line cost < 4 BLU
DIST_EXTRA_BITS = 3                 # a segment is < 2^(W + 3) BLU long
OVERRIDE_ONE = 128                  # the override in 1/128 (128 = 100 %)
OVERRIDE_STEPS = 8                  # clocks of the override's bit-by-bit product
POWER_FULL = OUTPUT_POWER_FULL      # a profile's power field at 100 %, as an OUTPUT's
CREDIT_CEILING = 1 << 41            # credit units: above every cap; no gain at or above it

COST_AXIS = 1 << COST_FRAC                          # 65536
COST_DIAG = round(math.sqrt(2) * (1 << COST_FRAC))  # 92682

CLASS_AXIS, CLASS_DIAG, CLASS_LINE = 0, 1, 2

TICK_MIN_S = 80e-6                  # choose_div: the shortest tick (82 us at 50 MHz)
CLOCK_RANGE_HZ = (10_000_000, 200_000_000)
MAX_ERROR = 0.01                    # the 1 %
# the speed follows a step of the exit staircase RAMP_LAG - 1 clocks late (the
# staircase register, the target register, the speed register); each level adds
# RAMP_LAG times its step so that at full speed it still lasts a tick
RAMP_LAG = 4
# the staircase starts on the clock after the first clock whose earned distance
# reached d_exit: at most TRIGGER_CLOCKS clocks of gain beyond d_exit
TRIGGER_CLOCKS = 2


def distance_bits(width: int) -> int:
    """Width of s, d_exit, d_stop for a core of position width ``width``."""
    return width + DIST_EXTRA_BITS + COST_FRAC


class ProfileRangeError(ValueError):
    """A quantity does not fit its field (or not within 1 %); the message names it."""

    def __init__(self, quantity: str, reason: str):
        super().__init__(f"{quantity}: {reason}")
        self.quantity = quantity


@dataclass(frozen=True)
class ProfileParams:
    """One segment's profile, the fields of a PROFILE command."""

    v_cruise: int           # BLU per clock x 2^32, < 2^32
    v_exit: int             # BLU per clock x 2^32, <= v_cruise
    accel: int              # speed step per tick, BLU per clock x 2^38, 1 .. 2^34 - 1
    line_cost: int = 0      # one line iteration, BLU x 2^16, < 2^18; 0 for an arc
    d_exit: int = 0         # BLU x 2^16 from the segment's start
    d_stop: int = 0         # BLU x 2^16, <= d_exit
    # the output stage's power for the segments run under this profile (laser mode):
    # set_power 1 loads power (PWM duty, 65536 = 100 %) when the stage takes the
    # segment; 0 leaves the power as it is (power then 0).  The stage itself does not
    # read them (``spec.outputs``, ``spec.core``)
    set_power: int = 0
    power: int = 0

    def largest_cost(self) -> int:
        return self.line_cost if self.line_cost else COST_DIAG

    def check(self, width: int = 32) -> None:
        """Raise ProfileRangeError naming the first field that does not fit."""
        dist = 1 << distance_bits(width)
        for name, value, top in (("v_cruise", self.v_cruise, 1 << FIELD_SPEED_BITS),
                                 ("v_exit", self.v_exit, self.v_cruise + 1),
                                 ("accel", self.accel, 1 << ACCEL_BITS),
                                 ("line_cost", self.line_cost, 1 << LINE_COST_BITS),
                                 ("d_exit", self.d_exit, dist),
                                 ("d_stop", self.d_stop, self.d_exit + 1),
                                 ("set_power", self.set_power, 2),
                                 ("power", self.power, POWER_FULL + 1)):
            if not 0 <= value < top:
                raise ProfileRangeError(name, f"{value} outside 0 .. {top - 1}")
        if self.accel == 0:
            raise ProfileRangeError("accel", "must be > 0")
        if self.power and not self.set_power:
            raise ProfileRangeError("power", "must be 0 unless set_power")


def move_cost(cost_class: int, profile: ProfileParams) -> int:
    """Cost (BLU x 2^16) of a move of ``cost_class`` in a segment of ``profile``."""
    if cost_class == CLASS_AXIS:
        return COST_AXIS
    if cost_class == CLASS_DIAG:
        return COST_DIAG
    return profile.line_cost


@dataclass
class ProfileInputs:
    head_valid: int = 0         # a move is at the head of the move queue
    head_class: int = CLASS_AXIS
    head_last: int = 0          # it is its segment's last move
    ready: int = 1              # every axis the head move steps is ready
    next_valid: int = 0         # the next segment's profile is available
    next_profile: ProfileParams | None = None
    hold: int = 0
    stop: int = 0
    override: int = OVERRIDE_ONE    # 1/128 steps, 0..128 (above 128 counts as 128)
    abort: int = 0              # immediate stop: the edge clears everything but ``dry``


@dataclass
class ProfileOutputs:
    """Registered state as the RTL shows it during the clock."""

    v: int                  # speed register, BLU per clock x 2^38
    dry: int                # sticky: a dry queue forced a deceleration
    busy: int               # a segment is current or the speed is not 0


@dataclass
class ProfileView:
    """Combinational, during the clock."""

    pop: bool = False       # the head move is made at this edge
    take: bool = False      # the next profile becomes current at this edge
    cost: int = 0           # cost of the head move (BLU x 2^16)
    target: int = 0         # target speed T (register units)
    ramp_on: bool = False   # the exit staircase runs after this edge
    ramp_step: bool = False     # it steps down at this edge
    ramp_v: int = 0         # its speed after this edge
    ramp_dry: bool = False  # it heads for the creep speed (dry queue) after this edge
    dry_now: bool = False   # the dry staircase steps down at this edge (sets dry)
    ramp_left: int = 0      # the staircase's distance to its next step after this edge
    ramp_moved: bool = False    # it starts, steps or returns from the dry queue at this edge
    credit: int = 0         # credit after this edge (while a segment is current)
    gain: int = 0           # the earned distance grows by this at this edge
    holding: bool = False   # hold, at rest: no move pops
    stopped: bool = False   # stop, at rest: the rest is dropped at this edge


def ramp_left_floor(div: int) -> int:
    """The least value of the staircase's remainder ``ramp_left`` (it saturates
    there): 2^(div + 40), so that it is div + 42 bits signed."""
    return 1 << (div + 40)


class ProfileStage:
    """Clock-by-clock model of the profile stage (``div``: tick = 2^div clocks).

    Registers: ``v`` (speed), ``target`` (the speed's target, registered a clock
    ahead), ``credit``, ``full`` (the credit was at its cap), ``s`` (popped distance
    in the segment), ``since`` / ``last_dir`` (the step cadence), ``cur`` (the
    current profile, with ``accel`` and ``v_cruise`` kept after it ends), ``ov_q``
    (override), ``ov_acc`` / ``ov_count`` / ``ov_target`` (its product with the cruise
    speed, bit by bit: ``OVERRIDE_STEPS`` clocks), ``dry`` (sticky), ``past_exit`` /
    ``past_stop`` (the earned distance compared with d_exit / d_stop a clock earlier)
    and the exit staircase:
    ``ramp_on``, ``ramp_dry``, ``ramp_v`` (its speed), ``ramp_left`` (distance, BLU x
    2^38, before its next step; DIV + 42 bits signed, saturating at
    -``ramp_left_floor``) and ``ramp_changed`` (it started, stepped or returned from the
    dry queue at the edge before, so it does not step on this clock)."""

    def __init__(self, div: int, width: int = 32):
        if not 1 <= div <= 24:
            raise ValueError("DIV must be 1..24")
        self.div = div
        self.tick = 1 << div
        self.width = width
        self.reset()

    def reset(self) -> None:
        self.cur: ProfileParams | None = None
        self.v = 0
        self.target = 0
        self.credit = 0
        self.full = False
        self.s = 0
        self.accel = 0              # speed step of the last current segment
        self.v_cruise = 0           # cruise speed of the last current segment (field)
        self.since = self.tick      # clocks since the last speed step, saturating
        self.last_dir = 0           # direction of the last speed step (+1, -1, 0)
        self.dry = 0
        self.ov_q = OVERRIDE_ONE    # the override input, registered
        self.ov_acc = 0             # the product so far (v_cruise x ov_q's top bits)
        self.ov_count = 0           # its steps still to go (0: ov_target is done)
        self.ov_target = 0          # (v_cruise << 6) * ov_q >> 7 once done
        self.past_exit = False
        self.past_stop = False
        self.ramp_on = False
        self.ramp_dry = False
        self.ramp_v = 0
        self.ramp_left = 0
        self.ramp_changed = False

    def outputs(self) -> ProfileOutputs:
        return ProfileOutputs(v=self.v, dry=self.dry,
                              busy=int(self.cur is not None or self.v != 0))

    def _ramp(self, i: ProfileInputs, w: ProfileView) -> None:
        """The exit staircase: a speed limit that starts at the segment's peak on the
        clock after the earned distance reached d_exit (or d_stop with the queue
        dry: ``past_exit`` / ``past_stop``) and steps down by ``accel`` on each clock
        that starts with its remainder ``ramp_left`` negative, down to the exit speed
        (the creep speed when dry).  Each level is a distance: 2^div clocks of its
        speed, plus RAMP_LAG times the step that started it (the speed follows the
        staircase RAMP_LAG - 1 clocks late and spends them at the level above); the
        first is 2^div - 1 clocks of its speed.  At full speed the levels therefore
        last exactly a tick, the first step comes a tick after the start, and
        ``exit_ramp_distance`` is its length; slower (override, hold) it keeps the
        same distances, so the stage rejoins it instead of finishing early and
        creeping."""
        cur, accel, div = self.cur, self.accel, self.div
        exit_speed = cur.v_exit << SPEED_SHIFT if cur.v_exit else accel
        dry_cond = bool(not i.next_valid and cur.v_exit)
        on, dry_mode, ramp_v = self.ramp_on, self.ramp_dry, self.ramp_v
        step = False
        start = False
        returned = False
        if not on:
            if self.past_exit:
                on, start, ramp_v = True, True, cur.v_cruise << SPEED_SHIFT
            elif self.past_stop and dry_cond:
                on, start, dry_mode = True, True, True
                ramp_v = cur.v_cruise << SPEED_SHIFT
        elif dry_mode and not dry_cond:
            # the next profile came: back to the plan
            returned = True
            if not self.past_exit:
                on, dry_mode = False, False
            else:
                dry_mode, ramp_v = False, max(ramp_v, exit_speed)
        else:
            # the level ran out on an earlier clock; not on the clock after the
            # staircase moved: the level of its next step is made from its speed and
            # floor after that edge, registered a clock later
            step = self.ramp_left < 0 and not self.ramp_changed
        left = self.ramp_left - w.gain
        if step:
            floor = accel if dry_mode else exit_speed
            above = ramp_v
            ramp_v = max(ramp_v - accel, floor)
            left += (ramp_v << div) + RAMP_LAG * (above - ramp_v)
        elif start:
            left = (ramp_v << div) - ramp_v - w.gain
        # saturating below: only its sign decides, and a level adds < 2^(div + 40),
        # so a remainder further down only appears where the levels are shorter
        # than a clock's gain (profiles not from the planner)
        left = max(left, -ramp_left_floor(div))
        w.ramp_on, w.ramp_dry, w.ramp_step, w.ramp_v = on, dry_mode, step, ramp_v
        w.ramp_moved = start or step or returned
        w.ramp_left = left if on else 0
        # the flag: the dry staircase really came down (a next profile arriving before
        # its first step, as at a program's start while the second segment is still
        # being validated, leaves no trace)
        w.dry_now = bool(on and dry_mode and step)

    def covers(self, cost: int) -> bool:
        """Whether the credit covers a move of this cost (``move_cost``)."""
        return (self.credit >> COST_SHIFT) >= cost

    def view(self, i: ProfileInputs) -> ProfileView:
        w = ProfileView()
        cur = self.cur
        w.target = self.target
        if cur is None:
            w.take = bool(i.next_valid and not i.stop)
            w.holding = bool(i.hold and self.v == 0)
            w.stopped = bool(i.stop and self.v == 0)
            return w
        w.cost = move_cost(i.head_class, cur) if i.head_valid else 0
        at_rest_stop = bool(i.stop and self.v == 0)
        # at rest under hold nothing pops, not even a move the credit already
        # covers (it pops on release): holding means no step until then
        at_rest_hold = bool(i.hold and self.v == 0)
        can_pop = bool(i.head_valid and self.covers(w.cost))
        w.pop = can_pop and bool(i.ready) and not at_rest_stop and not at_rest_hold
        w.stopped = at_rest_stop
        w.holding = at_rest_hold
        w.take = bool(w.pop and i.head_last and i.next_valid)
        # credit: gains the speed of this clock unless it was at its cap a clock ago
        spent = (w.cost << COST_SHIFT) if w.pop else 0
        w.gain = 0 if self.full else self.v
        w.credit = self.credit - spent + w.gain
        self._ramp(i, w)
        return w

    def next_target(self, halt: bool) -> int:
        """The target of the next clock, from this clock's registers: 0 under hold or
        stop (``halt``) or with no segment, else the least of the cruise speed, the
        override on it (unless it is 100 %) and (while it runs) the exit staircase."""
        cur = self.cur
        if cur is None or halt:
            return 0
        target = cur.v_cruise << SPEED_SHIFT
        if self.ov_q != OVERRIDE_ONE:
            target = min(target, self.ov_target)
        if self.ramp_on:
            target = min(target, self.ramp_v)
        return target

    def override_settled(self) -> bool:
        """Whether the override's product is done and, where the target reads it
        (override below 128), that of the registers now: it then stays as it is
        until an edge changes an operand."""
        return self.ov_count == 0 and (
            self.ov_q == OVERRIDE_ONE or self.ov_target == (self.v_cruise * self.ov_q) >> 1)

    def _override_step(self, restart: bool) -> None:
        """The override's product at an edge, from this clock's ``ov_q`` and
        ``v_cruise``: restarted by an edge that changes either, else one bit."""
        if restart:
            self.ov_count, self.ov_acc = OVERRIDE_STEPS, 0
        elif self.ov_count:
            self.ov_count -= 1
            bit = (self.ov_q >> self.ov_count) & 1
            acc = (self.ov_acc << 1) + (self.v_cruise if bit else 0)
            if self.ov_count:
                self.ov_acc = acc
            else:
                self.ov_target = acc >> 1   # the last step leaves ov_acc

    def clock(self, i: ProfileInputs) -> ProfileView:
        """One rising edge; returns the view of the clock that ended.  ``abort``: the
        edge clears the segment, speed, target, credit, staircase, cadence and the
        override's product, which then stands done at 0 (not ``dry``; the override is
        registered as on any edge) and pops nothing."""
        if i.abort:
            dry = self.dry
            self.reset()
            self.dry = dry
            self.ov_q = min(i.override, OVERRIDE_ONE)
            return ProfileView()
        w = self.view(i)
        # speed: one step of accel towards the registered target, same-direction
        # steps a tick apart
        v, t = self.v, self.target
        direction = 0
        if t > v and (self.last_dir != 1 or self.since >= self.tick):
            direction, v = 1, min(v + self.accel, t)
        elif t < v and (self.last_dir != -1 or self.since >= self.tick):
            direction, v = -1, max(v - self.accel, t)
        if direction:
            self.last_dir, self.since = direction, 1
        elif self.since < self.tick:
            self.since += 1
        self.target = self.next_target(bool(i.hold or i.stop))
        self._override_step(min(i.override, OVERRIDE_ONE) != self.ov_q
                            or (w.take and self.ov_q != OVERRIDE_ONE))
        # registered compares of this clock's registers, for the next clock
        cur = self.cur
        full = past_exit = past_stop = False
        ceiling = self.credit >= CREDIT_CEILING
        if cur is not None:
            full = self.credit >= (cur.largest_cost() << COST_SHIFT) << 1
            earned = self.s + (self.credit >> COST_SHIFT)
            past_exit, past_stop = earned >= cur.d_exit, earned >= cur.d_stop
        # credit and distance
        segment_ends = False
        if w.stopped:
            self.cur, self.credit, self.s = None, 0, 0
        elif self.cur is not None:
            self.credit = w.credit
            if w.pop:
                self.s += w.cost
                if i.head_last:
                    self.s, self.cur, segment_ends = 0, None, True
        # the compares belong to the segment they were made in; the ceiling to none
        if segment_ends or w.stopped:
            full = past_exit = past_stop = False
        full = full or (ceiling and not w.stopped)
        self.full, self.past_exit, self.past_stop = full, past_exit, past_stop
        # the exit staircase; it ends with its segment
        self.ramp_on, self.ramp_dry, self.ramp_v = w.ramp_on, w.ramp_dry, w.ramp_v
        self.ramp_left = w.ramp_left
        self.ramp_changed = w.ramp_moved
        if segment_ends or w.stopped or not w.ramp_on:
            self.ramp_on, self.ramp_dry, self.ramp_left = False, False, 0
        if w.take:
            self.cur = i.next_profile
            self.accel = i.next_profile.accel
            self.v_cruise = i.next_profile.v_cruise
        if w.dry_now:
            self.dry = 1
        # no segment after this edge: nothing to pace, the speed is 0 at once (after a
        # planned stop that is one step from the creep speed; after a dry end with
        # the segment too short to slow down, the documented excess, flagged by dry)
        self.v = v if self.cur is not None else 0
        self.ov_q = min(i.override, OVERRIDE_ONE)
        return w


# --- host side: the distances, bit-exact ---------------------------------------------------

def ramp_distance(v_from: int, v_to: int, accel: int, div: int) -> int:
    """Distance (BLU x 2^38) earned from the clock whose edge makes the first speed
    step down from ``v_from`` until the first clock at ``v_to`` (register units),
    steps of ``accel`` every 2^div clocks, the last one clamped at ``v_to``:
    v_from (the trigger clock) + 2^div * sum_{k=1}^{N-1} (v_from - k accel),
    N = ceil((v_from - v_to) / accel).  0 if v_from <= v_to."""
    if v_from <= v_to:
        return 0
    n = -(-(v_from - v_to) // accel)
    m = n - 1
    return v_from + ((m * v_from - accel * (m * n // 2)) << div)


def accel_distance(v_from: int, v_to: int, accel: int, div: int) -> int:
    """Largest distance (BLU x 2^38) earned from a segment's first clock at ``v_from``
    until the first clock at ``v_to`` > v_from, when the first step may wait up to
    2^div - 1 clocks (the previous step was also up): 2^div * (v_from + sum_{k=1}^{M-1}
    (v_from + k accel)).  0 if v_to <= v_from."""
    if v_to <= v_from:
        return 0
    m = -(-(v_to - v_from) // accel)
    return (m * v_from + accel * ((m - 1) * m // 2)) << div


def exit_ramp_distance(v_from: int, v_to: int, accel: int, div: int) -> int:
    """Distance (BLU x 2^38) the stage earns from the clock its exit staircase starts
    at ``v_from`` until its first clock at ``v_to`` (register units), at full speed:
    the staircase steps every 2^div clocks from a tick after its start, and the speed
    follows each step RAMP_LAG - 1 clocks late, so a first level of 2^div +
    RAMP_LAG - 1 clocks at v_from, then ``ramp_distance`` less its first clock.  0
    if v_from <= v_to."""
    if v_from <= v_to:
        return 0
    return ((v_from << div) + ramp_distance(v_from, v_to, accel, div)
            + (RAMP_LAG - 2) * v_from)


@dataclass(frozen=True)
class ExitPlan:
    """What ``exit_distance`` found: the distance and the assumptions behind it."""

    d_exit: int             # BLU x 2^16
    accelerates: bool       # the peak is surely reached before d_exit (by steps up)
    fits: bool              # the segment is long enough (else d_exit is 0 and the
                            # segment ends above the exit speed)


def exit_distance(length: int, v_entry: int, v_peak: int, v_exit: int, accel: int,
                  div: int) -> ExitPlan:
    """d_exit for a segment of cost ``length`` (BLU x 2^16) entered at ``v_entry``,
    peaking at ``v_peak`` and leaving at ``v_exit`` (field units, 2^-32; 0 = the
    creep speed ``accel``), so that the stage, running without events, makes the
    segment's last move at exactly the exit speed.

    The conditions (see the model): the staircase starts on the clock n0 after the
    first clock with E >= d_exit, so E(n0) < d_exit + 2 v (two clocks' gain), or
    E(n0) < the carry + v_entry < 3 v_entry when d_exit is reached on the segment's
    first clock; the segment's last move pops on the first clock with E >= length;
    E(n0) + exit_ramp_distance <= length therefore keeps every clock of the
    staircase before it, and the last move is made at the exit speed.
    ``accelerates``: from v_entry the stage surely reaches v_peak before d_exit
    (worst phase of its steps up, ``accel_distance``, plus a tick and four clocks:
    the target register may hold the first step back or clamp it; the override's
    product does not, at the 100 % the plan is for); else it may start the staircase
    below the peak and end it early (it then runs the rest at the exit speed: slower,
    never faster)."""
    vp = v_peak << SPEED_SHIFT
    vin = v_entry << SPEED_SHIFT
    vout = v_exit << SPEED_SHIFT if v_exit else accel
    total = length << COST_SHIFT
    budget = total - exit_ramp_distance(vp, vout, accel, div) - TRIGGER_CLOCKS * vp
    reach = (2 * vin + accel_distance(vin, vp, accel, div)
             + (((1 << div) + 4) * vp if vp > vin else 0))
    accelerates = vp > vin and reach <= budget
    fits = budget >= 2 * vin and budget >= vp
    return ExitPlan(max(budget, 0) >> COST_SHIFT, accelerates, fits)


def max_entry_speed(length: int, v_exit: int, accel: int, div: int,
                    v_limit: int) -> int:
    """Largest entry speed (field units) <= v_limit from which a segment of cost
    ``length`` that only decelerates still fits (``exit_distance(...).fits``): the
    host's backward pass in integers."""
    lo, hi = 0, v_limit
    if exit_distance(length, hi, hi, v_exit, accel, div).fits:
        return hi
    while lo < hi:
        mid = (lo + hi + 1) // 2
        if exit_distance(length, mid, mid, v_exit, accel, div).fits:
            lo = mid
        else:
            hi = mid - 1
    return lo


def peak_speed(length: int, v_entry: int, v_cruise: int, v_exit: int, accel: int,
               div: int) -> int:
    """The speed the segment is planned to reach (field units): ``v_cruise`` when the
    staircase reaches it before ``d_exit`` (a trapezoid), else the largest speed below
    it that it reaches (a triangle; binary search, the conditions being monotone in
    the peak), else max(v_entry, v_exit) (the segment only decelerates, or cannot
    even reach its exit speed: the stage then ends it below, never above)."""
    def good(vp):
        plan = exit_distance(length, v_entry, vp, v_exit, accel, div)
        return plan.fits and plan.accelerates

    floor = max(v_entry, v_exit)
    if v_cruise <= floor or good(v_cruise):
        return max(v_cruise, floor)
    if not good(floor + 1):
        return floor
    return _largest_good(floor + 1, v_cruise - 1, good)


def _largest_good(lo: int, hi: int, good) -> int:
    """Largest x in [lo, hi] with ``good(x)``, for a ``good`` that holds up to some
    point and not beyond (bisection); ``lo`` when none above it is good."""
    while lo < hi:
        mid = (lo + hi + 1) // 2
        if good(mid):
            lo = mid
        else:
            hi = mid - 1
    return lo


def max_exit_speed(length: int, v_entry: int, accel: int, div: int, v_limit: int) -> int:
    """Largest exit speed (field units) <= v_limit that a segment of cost ``length``
    entered at ``v_entry`` surely reaches before its d_exit (the host's forward pass
    in integers); v_entry if it cannot accelerate at all."""
    def good(ve):
        plan = exit_distance(length, v_entry, ve, ve, accel, div)
        return plan.fits and plan.accelerates

    if v_limit <= v_entry or good(v_limit):
        return v_limit
    return _largest_good(v_entry, v_limit - 1, good)


def make_profile(length: int, v_entry: int, v_cruise: int, v_exit: int, accel: int,
                 div: int, line_cost: int = 0) -> ProfileParams:
    """The PROFILE fields of one segment entered at ``v_entry`` (field units): the
    peak (``peak_speed``) as its cruise speed, d_exit and d_stop computed bit-exactly
    (d_stop: decelerate to the creep speed; equal to d_exit when v_exit is 0, never
    after it)."""
    peak = peak_speed(length, v_entry, v_cruise, v_exit, accel, div)
    d_exit = exit_distance(length, v_entry, peak, v_exit, accel, div).d_exit
    d_stop = d_exit
    if v_exit:
        d_stop = min(d_exit,
                     exit_distance(length, v_entry, peak, 0, accel, div).d_exit)
    return ProfileParams(peak, v_exit, accel, line_cost, d_exit, d_stop)


def plan_integer(lengths, v_cruise, v_exit, accel, div, line_costs=None):
    """Profiles for a chain of segments (the host's integer pass).  ``v_exit[k]`` is
    the planned junction speed after segment k (field units; the last one 0).  A
    backward pass lowers junction speeds a segment cannot decelerate from in
    integers (staircase, trigger clock, possible late first step), a forward pass
    those a segment cannot surely accelerate to (grbl's ``planner_recalculate``
    passes, on the stage's own integers); each segment's peak is ``peak_speed``.
    Returns the ProfileParams; running them without events, every segment's last
    move is made at exactly its exit speed (the creep speed for 0)."""
    n = len(lengths)
    line_costs = line_costs or [0] * n
    exits = list(v_exit)
    for k in range(n - 1, -1, -1):
        entry_max = max_entry_speed(lengths[k], exits[k], accel[k], div,
                                    max(v_cruise[k], exits[k]))
        if k > 0:
            exits[k - 1] = min(exits[k - 1], entry_max, v_cruise[k])
    out = []
    v_in = 0
    for k in range(n):
        exits[k] = min(exits[k], max_exit_speed(lengths[k], v_in, accel[k], div, exits[k]))
        out.append(make_profile(lengths[k], v_in, max(v_cruise[k], v_in), exits[k],
                                accel[k], div, line_costs[k]))
        v_in = exits[k]
    return out


# --- host side: units ------------------------------------------------------------------------

def choose_div(clock_hz: int) -> int:
    """DIV for a clock: the smallest with a tick 2^DIV / clock_hz >= 80 us (82 us at
    50 MHz, DIV 12; 10 MHz: 10, 200 MHz: 14).  Long enough that the slowest
    acceleration (5 mm/s^2 on arcs, 10 um BLU) is a speed step of >= 2^-32.2 BLU per
    clock, within 1 % in 2^-38; short enough for a fine staircase (50,000 mm/s^2 at
    80-160 us is 4-8 mm/s a step)."""
    lo, hi = CLOCK_RANGE_HZ
    if not lo <= clock_hz <= hi:
        raise ProfileRangeError("clock_hz", f"{clock_hz} outside {lo} .. {hi}")
    need = Fraction(clock_hz) * Fraction(TICK_MIN_S)
    div = 0
    while (1 << div) < need:
        div += 1
    return div


def _field(quantity: str, exact: Fraction, bits: int, nearest: bool = False) -> int:
    if exact < 0:
        raise ProfileRangeError(quantity, "must be >= 0")
    value = round(exact) if nearest else math.floor(exact)
    if value >= 1 << bits:
        raise ProfileRangeError(quantity, f"{float(exact):.6g} does not fit {bits} bits")
    if exact > 0 and abs(exact - value) / exact > MAX_ERROR:
        raise ProfileRangeError(quantity, f"{float(exact):.6g} LSB: error above 1 %")
    return value


def speed_exact(mm_s: float, blu_mm: float, clock_hz: int) -> Fraction:
    """A path speed in mm/s in the v_cruise / v_exit field's units, exactly (any size)."""
    return Fraction(mm_s) / Fraction(blu_mm) / clock_hz * (1 << FIELD_SPEED_FRAC)


def speed_field(mm_s: float, blu_mm: float, clock_hz: int, quantity: str = "speed") -> int:
    """A path speed in mm/s as a v_cruise / v_exit field (floor: never faster)."""
    return _field(quantity, speed_exact(mm_s, blu_mm, clock_hz), FIELD_SPEED_BITS)


def accel_field(mm_s2: float, blu_mm: float, clock_hz: int, div: int,
                quantity: str = "accel") -> int:
    """A path acceleration in mm/s^2 as the speed step per tick (nearest: at the
    slowest corner the step is 56 LSB, where a floor could lose 1.8 %; the host's
    distances use the rounded step, so the profile stays consistent)."""
    exact = (Fraction(mm_s2) / Fraction(blu_mm) / clock_hz / clock_hz
             * (1 << div) * (1 << SPEED_FRAC))
    value = _field(quantity, exact, ACCEL_BITS, nearest=True)
    if value == 0:
        raise ProfileRangeError(quantity, "rounds to 0")
    return value


def line_cost_field(length_mm: float, iterations: int, blu_mm: float) -> int:
    """Cost of one line iteration, (length / iterations) in BLU of X, x 2^16
    (nearest)."""
    exact = Fraction(length_mm) / iterations / Fraction(blu_mm) * (1 << COST_FRAC)
    value = round(exact)
    if not 0 < value < 1 << LINE_COST_BITS:
        raise ProfileRangeError("line_cost", f"{float(exact):.6g} does not fit 18 bits")
    if abs(value - exact) / exact > MAX_ERROR:
        raise ProfileRangeError("line_cost", "error above 1 %")
    return value


# --- a driver for tests and the host's time estimate ----------------------------------------

@dataclass
class RunResult:
    pops: list = field(default_factory=list)        # (clock, segment, index) per move
    v: list = field(default_factory=list)           # speed register per clock
    segment: list = field(default_factory=list)     # current segment per clock (-1: none)
    s: list = field(default_factory=list)           # popped distance per clock
    holding: list = field(default_factory=list)
    stopped_at: int | None = None
    dry: int = 0
    clocks: int = 0


def run_segments(profiles, moves_per_segment, div: int, inputs=None, arrival=None,
                 ready=None, max_clocks: int = 10_000_000, trace: bool = False) -> RunResult:
    """Run the stage over ``profiles`` and their moves (a list of cost classes per
    segment) and return the pop clock of every move.  ``arrival[k]``: first clock at
    which segment k's profile and moves are available (default 0: the queue never
    runs dry); ``inputs(clock)`` -> (hold, stop, override); ``ready(clock)`` -> the
    STEP/DIR readiness.  Stops when every move is popped (or dropped by stop) and
    the speed is 0."""
    stage = ProfileStage(div)
    res = RunResult()
    n = len(profiles)
    seg_in = 0                  # next profile to hand over
    cur_seg = -1
    idx = 0                     # index of the head move within cur_seg
    clock = 0
    while clock < max_clocks:
        hold, stop, override = inputs(clock) if inputs else (0, 0, OVERRIDE_ONE)
        nxt_ok = seg_in < n and (arrival is None or clock >= arrival[seg_in])
        head = cur_seg >= 0 and stage.cur is not None
        inp = ProfileInputs(
            head_valid=int(head), next_valid=int(nxt_ok),
            next_profile=profiles[seg_in] if nxt_ok else None,
            hold=hold, stop=stop, override=override,
            ready=int(ready(clock)) if ready else 1)
        if head:
            moves = moves_per_segment[cur_seg]
            inp.head_class = moves[idx]
            inp.head_last = int(idx == len(moves) - 1)
        if trace:
            res.v.append(stage.v)
            res.segment.append(cur_seg if stage.cur is not None else -1)
            res.s.append(stage.s)
        w = stage.clock(inp)
        if trace:
            res.holding.append(w.holding)
        if w.pop:
            res.pops.append((clock, cur_seg, idx))
            idx += 1
            if inp.head_last:
                cur_seg, idx = -1, 0
        if w.stopped:
            res.stopped_at = clock
            cur_seg, idx, seg_in = -1, 0, n
        if w.take:
            cur_seg, idx = seg_in, 0
            seg_in += 1
        clock += 1
        if seg_in == n and stage.cur is None and stage.v == 0:
            break
    res.dry = stage.dry
    res.clocks = clock
    return res
