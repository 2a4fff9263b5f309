# SPDX-License-Identifier: Apache-2.0
"""Motion plans: the quantiser's commands with their PROFILEs, dwells as pauses, and
the executors that run them (issue 13, items 3 and 6).

``build_motion(q, items, machine)`` takes the quantiser's output (``q.cmds``, with
``q.src`` naming the compensated ``Move`` behind each command) and ``items``, the
same moves with the program's dwells (``planner.Dwell``), output changes
(``planner.OutputChange``) and laser powers (``planner.PowerChange``) in program
order, and returns a ``MotionPlan``: the command stream with a PROFILE before every
motion command, a ``Pause`` where a dwell is and an OUTPUT command where an output
change is.

* Speeds come from the planner (``planner.plan`` over ``items`` with the machine:
  F, G0 at the axes' maximum speed, per-axis limits, junction deviation, lookahead).
  A command's cruise speed is its move's planned cruise (``Segment.v_cruise``), a
  line command's also at most what the axes allow along its own lattice direction;
  its acceleration is its move's (``Segment.accel``), a line command's also at
  most the axes' limit along its direction.
* Path unit: the profile stage's, one BLU of X for every command (``spec.profile``:
  a diagonal arc move costs sqrt(2), a line iteration its Euclidean length over its
  iteration count, ``line_cost``).  So every speed in mm/s is turned into BLU of X
  per clock (``profile.speed_field``, floor: never faster) and every acceleration
  into a speed step per tick of 2^DIV clocks (``profile.accel_field``, nearest,
  DIV = ``profile.choose_div(clock_hz)``); a line's ``line_cost`` is its true
  length in mm over its iterations (``profile.line_cost_field``), so axes with
  different BLUs keep their true speed.
* Junctions: between commands of two moves, the planner's junction speed (the
  first move's ``v_exit``).  A correcting line the quantiser puts at the start of a
  move (a line command followed by more commands of the same move) belongs to that
  junction: it is entered and left at the junction speed.  Between the commands of
  one move (arc pieces, the correcting lines between them, single-step fallback
  lines) the junction is bounded only by the two commands' cruise speeds: the
  quantiser's detours there are lattice-sized.
* The program starts at rest, and ends at rest, and so does the last command before
  every dwell.  ``profile.plan_integer`` then runs the backward and forward passes
  over the whole chain on the stage's own integers (they only lower speeds) and
  gives the bit-exact ``d_exit`` / ``d_stop`` of every PROFILE.
* CONT is set on every motion command followed by another without a pause between.
* A dwell (G4 P seconds) is a ``Pause`` of round(seconds x clock_hz) clocks in
  program order: the executor stops feeding commands there until the core is idle,
  then waits those clocks.
* An output change (``planner.OutputChange``: M3/M4/M5, M7/M8/M9, and S outside
  laser mode) is an OUTPUT command in program order; the motion before it ends at rest
  (the core runs it once everything before it has moved).
* A power change (``planner.PowerChange``, laser mode: S, and 0 for a G0) is no
  command and no stop: from the move after it on (in item order, until the next
  one), every motion command's PROFILE has ``set_power`` 1 and its ``power``, so the
  core's output stage takes that power when its profile stage takes the command's
  segment, with the motion running.  Under M4 (``dynamic``) the stage's duty is the
  power times speed / the PROFILE's v_cruise; where v_cruise is below the programmed
  feed F (a segment too short to reach it, a small arc, an axis limit) the power is
  scaled by v_cruise / F, so that the duty is S x speed / F, as grbl's M4.  Every
  command of one move (arc pieces, correcting lines) carries that move's power.  Moves
  before the first power change (all of them outside laser mode) have PROFILEs with
  ``set_power`` 0, as before.

Executors (``run_model`` and ``run_clocked`` here; ``halfpoint.sim.engines`` has the
RTL one; a faster model can take the same place) are functions ``(items, CoreConfig, holds) ->
Execution``: ``items`` the plan's commands (ints) and ``Pause`` markers, ``holds``
the (A, B) cycle intervals with ``hold`` high (A <= cycle < B).  Both share
``Feeder``, the clock-by-clock policy: offer the next command on every cycle
(tvalid high while there is one), advance when tready was high, wait at a pause,
drive hold, record every move as (cycle of the edge that made it, position after it).
Cycle 0 is the first cycle after reset.
"""

from __future__ import annotations

import math
from dataclasses import astuple, dataclass, field, replace
from fractions import Fraction

from ..spec import encoding as enc
from ..spec import profile as pf
from ..spec.core import CoreBusy, decode_for_core
from ..spec.program import segment_moves
from ..spec.stepgen import StepCfg
from .gcode import GcodeError, Move
from .machine import Machine, MachineError
from .planner import (Dwell, OutputChange, PowerChange, Segment, plan, plane_share,
                      projected_limit)

AXES = 3
WIDTH = 32


@dataclass(frozen=True)
class Pause:
    """A dwell in the command stream: wait until the core is idle, then ``clocks``."""

    clocks: int
    seconds: float
    lineno: int


@dataclass
class PlannedCommand:
    """One motion command of a plan."""

    index: int                  # in q.cmds
    cmd: int                    # the command as sent (CONT set where it applies)
    kind: str                   # "line" or "arc"
    move: Move                  # the compensated move behind it
    segment: Segment            # its planned segment
    moves: int                  # lattice moves it makes
    length: int                 # cost length, BLU x 2^16
    v_cruise: int               # the limits handed to plan_integer (field units)
    v_exit: int
    accel: int
    profile: pf.ProfileParams   # what plan_integer made of them (with the move's power
                                # in laser mode), as sent


@dataclass
class MotionPlan:
    items: list                 # encoded commands (int) and Pause, in order
    commands: list              # PlannedCommand per motion command
    planned: list               # planner.plan's output (Segment and Dwell)
    div: int
    clock_hz: int
    blu: tuple

    @property
    def pauses(self) -> list:
        return [it for it in self.items if isinstance(it, Pause)]

    @property
    def outputs(self) -> int:
        """OUTPUT commands (spindle, laser, coolant changes: each a stop)."""
        return sum(1 for it in self.items if not isinstance(it, Pause)
                   and it & enc.OPCODE_MASK == enc.OP_OUTPUT)

    @property
    def power_changes(self) -> int:
        """Motion commands whose PROFILE sets another power than the one before it
        (laser mode: carried with the motion, no stop)."""
        last, count = None, 0
        for c in self.commands:
            if c.profile.set_power and c.profile.power != last:
                count += 1
                last = c.profile.power
        return count


def _range_error(lineno: int, exc: pf.ProfileRangeError) -> GcodeError:
    return GcodeError(lineno, f"the core's fixed point cannot hold this block's {exc}")


def _line_limits(deltas, blu, machine: Machine):
    """(length mm, unit direction weights) of a line command's lattice vector."""
    mm = [d * b for d, b in zip(deltas, blu)]
    length = math.sqrt(sum(c * c for c in mm))
    return length, tuple(abs(c) / length for c in mm)


def build_motion(q, items, machine: Machine, width: int = WIDTH) -> MotionPlan:
    """The command stream of a quantised program (module docstring)."""
    clock = machine.clock_hz
    try:
        div = pf.choose_div(clock)
    except pf.ProfileRangeError as exc:
        raise MachineError("clock_hz", str(exc), machine.source) from None
    blu = machine.blu[:AXES]
    bx = blu[0]
    # the power in force for each move (laser mode's PowerChange items, which the
    # planner plans through: they leave the plan)
    power_of = {}               # id(move) -> (power, dynamic)
    power = None
    kept = []
    for it in items:
        if isinstance(it, PowerChange):
            power = (it.power, it.dynamic)
            continue
        if power is not None and not isinstance(it, Dwell):
            power_of[id(it)] = power
        kept.append(it)
    items = kept
    planned = plan(items, machine)
    seg_of = {id(it): sg for it, sg in zip(items, planned) if isinstance(sg, Segment)}
    order = {}                  # id(move) -> its index among the moves
    dwells = []                 # (index of the first move after it, Dwell)
    for it in items:
        if isinstance(it, Dwell):
            dwells.append((len(order), it))
        else:
            order[id(it)] = len(order)
    n = len(q.cmds)
    first_of_move = [k == 0 or q.src[k] is not q.src[k - 1] for k in range(n)]
    last_of_move = [k == n - 1 or q.src[k + 1] is not q.src[k] for k in range(n)]

    # dwells before each command; a pause ends the chain before it at rest
    pauses_before: list[list] = [[] for _ in range(n + 1)]
    d = 0
    for k in range(n):
        at = order[id(q.src[k])]
        while d < len(dwells) and dwells[d][0] <= at:
            pauses_before[k].append(dwells[d][1])
            d += 1
    pauses_before[n] = [dw for _, dw in dwells[d:]]

    kinds, counts, lengths, lcs, cruise_mm, accel_mm = [], [], [], [], [], []
    for k, cmd in enumerate(q.cmds):
        m = q.src[k]
        seg = seg_of[id(m)]
        dec = decode_for_core(cmd, AXES, width)
        if dec[0] == "line":
            deltas = dec[1]
            iters = max(abs(v) for v in deltas)
            length_mm, weights = _line_limits(deltas, blu, machine)
            try:
                lc = pf.line_cost_field(length_mm, iters, bx)
            except pf.ProfileRangeError as exc:
                raise _range_error(m.lineno, exc) from None
            v_axes = projected_limit(machine.max_velocity, weights)
            a_axes = projected_limit(machine.max_accel, weights)
            vc = min(seg.v_cruise, v_axes) if seg.v_cruise > 0 else v_axes
            ac = min(seg.accel, a_axes) if seg.accel > 0 else a_axes
            kinds.append("line")
            counts.append(iters)
            lengths.append(iters * lc)
            lcs.append(lc)
        elif dec[0] == "arc":
            moves = segment_moves(dec, width, AXES)
            if moves is None:
                raise GcodeError(m.lineno, "the core would reject this arc command")
            diag = sum(1 for c in moves[1] if c == pf.CLASS_DIAG)
            kinds.append("arc")
            counts.append(len(moves[1]))
            lengths.append(diag * pf.COST_DIAG + (len(moves[1]) - diag) * pf.COST_AXIS)
            lcs.append(0)
            # the core paces an arc in its plane: a helix's speeds times its plane share
            vc, ac = seg.v_cruise * plane_share(seg), seg.accel * plane_share(seg)
            if vc <= 0 or ac <= 0:
                raise GcodeError(m.lineno, "the planner gave this arc no speed")
        else:
            raise GcodeError(m.lineno, f"the quantiser made a command the core does not run "
                                       f"({dec})")
        cruise_mm.append(vc)
        accel_mm.append(ac)

    # junction speed bounds (mm/s) after each command
    exit_mm = []
    for k in range(n):
        m = q.src[k]
        if k == n - 1 or pauses_before[k + 1]:
            exit_mm.append(0.0)
        elif last_of_move[k]:
            sg = seg_of[id(m)]                          # the planner's junction speed
            exit_mm.append(sg.v_exit * (plane_share(sg) if kinds[k] == "arc" else 1.0))
        elif first_of_move[k] and kinds[k] == "line":
            # a correcting line at the start of its move: part of the junction before it
            exit_mm.append(seg_of[id(q.src[k - 1])].v_exit if k > 0 and
                           not pauses_before[k] else 0.0)
        else:
            exit_mm.append(math.inf)                 # within a move: the cruise speeds
    vcs, exits, accs = [], [], []
    for k in range(n):
        m = q.src[k]
        try:
            vc = pf.speed_field(cruise_mm[k], bx, clock, "cruise speed")
            if vc == 0:
                raise pf.ProfileRangeError("cruise speed", f"{cruise_mm[k]:.6g} mm/s is 0 in "
                                           "the 2^-32 BLU per clock field")
            # a junction speed is a limit: its floor is always safe, however coarse
            ve = vc if exit_mm[k] >= cruise_mm[k] else math.floor(pf.speed_exact(exit_mm[k],
                                                                                 bx, clock))
            acc = pf.accel_field(accel_mm[k], bx, clock, div)
        except pf.ProfileRangeError as exc:
            raise _range_error(m.lineno, exc) from None
        vcs.append(vc)
        exits.append(min(ve, vc))
        accs.append(acc)
    profiles = pf.plan_integer(lengths, vcs, exits, accs, div, lcs) if n else []

    out_items: list = []
    commands: list[PlannedCommand] = []
    for k, cmd in enumerate(q.cmds):
        for dw in pauses_before[k]:
            out_items.append(_pause(dw, clock))
        p = profiles[k]
        if id(q.src[k]) in power_of:
            power, dynamic = power_of[id(q.src[k])]
            if dynamic:
                power = _dynamic_power(power, p.v_cruise, q.src[k], seg_of[id(q.src[k])],
                                       kinds[k], bx, clock)
            p = replace(p, set_power=1, power=power)
        try:
            p.check(width)
        except pf.ProfileRangeError as exc:
            raise _range_error(q.src[k].lineno, exc) from None
        cont = k < n - 1 and not pauses_before[k + 1]
        sent = cmd | enc.FLAG_CONT if cont else cmd
        out_items.append(enc.encode_profile(*astuple(p)))
        out_items.append(sent)
        commands.append(PlannedCommand(k, sent, kinds[k], q.src[k], seg_of[id(q.src[k])],
                                       counts[k], lengths[k], vcs[k], exits[k], accs[k], p))
    for dw in pauses_before[n]:
        out_items.append(_pause(dw, clock))
    return MotionPlan(out_items, commands, planned, div, clock, tuple(blu))


def _dynamic_power(power: int, v_cruise: int, m: Move, seg: Segment, kind: str, bx: float,
                   clock: int) -> int:
    """M4's power for a command of move ``m`` whose PROFILE has ``v_cruise``: the core's
    output stage makes the duty power x speed / v_cruise, and v_cruise is the segment's
    planned peak, below the programmed feed where the segment is too short to reach it,
    on a small arc or above an axis's limit; so the power is scaled by v_cruise / F
    (floor), and the duty is S x speed / F, grbl's M4, on every segment."""
    if power == 0 or m.kind == "rapid" or not m.feed > 0:
        return power
    share = Fraction(plane_share(seg)) if kind == "arc" else Fraction(1)
    feed = pf.speed_exact(Fraction(m.feed) / 60 * share, bx, clock)  # v_cruise's units
    if v_cruise >= math.floor(feed):                      # at F (its field is a floor)
        return power
    return int(power * v_cruise / feed)


def _pause(dw: Dwell, clock: int):
    """A dwell's ``Pause``, or an output change's OUTPUT command."""
    if isinstance(dw, OutputChange):
        return enc.encode_output(*dw.settings)
    return Pause(round(Fraction(dw.seconds) * clock), dw.seconds, dw.lineno)


# --- executors ---------------------------------------------------------------------------------

@dataclass(frozen=True)
class CoreConfig:
    """What an executor builds the core with."""

    axes: int = AXES
    width: int = WIDTH
    div: int = 12
    cfg: tuple = ()             # StepCfg per axis
    depth: int = 16
    tw: int = 16
    move_depth: int = 4
    profile_depth: int = 2

    def step_cfg(self) -> list:
        return list(self.cfg) if self.cfg else [StepCfg() for _ in range(self.axes)]


def core_config(machine: Machine, width: int = WIDTH) -> CoreConfig:
    """The core a machine file asks for: DIV from its clock, STEP/DIR timing in ticks."""
    try:
        div = pf.choose_div(machine.clock_hz)
    except pf.ProfileRangeError as exc:
        raise MachineError("clock_hz", str(exc), machine.source) from None
    cfg = tuple(StepCfg(a.timing.steplen, a.timing.stepspace, a.timing.dirsetup,
                        a.timing.dirhold) for a in machine.axes)
    return CoreConfig(len(machine.axes), width, div, cfg)


@dataclass
class Execution:
    moves: list = field(default_factory=list)       # (cycle, position after the move)
    errors: list = field(default_factory=list)      # err_code of every rejected command
    dry: int = 0                # the core's sticky dry flag at the end
    underrun: int = 0           # the core's sticky underrun flag at the end
    cycles: int = 0             # cycles run
    approximate: bool = False   # cycles after a pause not clock-exact (run_paused_fast)


IDLE_CYCLES = 4                 # idle cycles after the last item that end a run


class Feeder:
    """The clock-by-clock policy every executor follows (module docstring); its end
    rule is ``spec.core.run_program``'s (4 cycles without ``busy`` after the last
    command), so a run without pauses is that function's run.

    Each cycle: ``step(cycle, out)`` with the core's outputs during that cycle (any
    object with tready, busy, level, move, pos, err, err_code, underrun, dry) returns
    (tvalid, tdata, hold) to drive for the edge that ends it."""

    def __init__(self, items, holds=()):
        self.items = list(items)
        self.holds = sorted((int(a), int(b)) for a, b in holds)
        self.idx = 0
        self.wait = None            # None; "idle": a pause waits for idle; int: clocks left
        self.idle = 0
        self.run = Execution()

    def hold_at(self, cycle: int) -> int:
        return int(any(a <= cycle < b for a, b in self.holds))

    @property
    def done(self) -> bool:
        return self.idx >= len(self.items) and self.idle >= IDLE_CYCLES

    def step(self, cycle: int, out) -> tuple[int, int, int]:
        run = self.run
        if out.move:
            run.moves.append((cycle - 1, tuple(out.pos)))
        if out.err:
            run.errors.append(out.err_code)
        run.underrun = out.underrun
        run.dry = out.dry
        run.cycles = cycle + 1
        tvalid = tdata = 0
        while self.idx < len(self.items):
            item = self.items[self.idx]
            if isinstance(item, Pause):
                if self.wait is None:
                    self.wait = "idle"
                if self.wait == "idle":
                    if out.busy or out.level:
                        break
                    self.wait = item.clocks
                if self.wait > 0:
                    self.wait -= 1
                    break
                self.wait = None
                self.idx += 1
                continue
            tvalid, tdata = 1, item
            if out.tready:
                self.idx += 1
            break
        self.idle = 0 if (out.busy or self.idx < len(self.items)) else self.idle + 1
        return tvalid, tdata, self.hold_at(cycle)


def max_clocks_for(items, holds=(), floor: int = 50_000_000) -> int:
    """A generous bound on a run's cycles (pauses and holds added to ``floor``)."""
    pause = sum(it.clocks for it in items if isinstance(it, Pause))
    held = sum(max(0, b - a) for a, b in holds)
    return floor + pause + held


def run_clocked(items, config: CoreConfig, holds=(), max_clocks: int | None = None
                ) -> Execution:
    """The clock-by-clock core model (``spec.core.CoreModel``) as an executor."""
    from ..spec.core import CoreInputs, CoreModel

    model = CoreModel(config.axes, config.width, config.depth, config.tw, config.div,
                      config.move_depth, config.profile_depth, config.step_cfg())
    model.clock(CoreInputs(rst=1))
    feeder = Feeder(items, holds)
    limit = max_clocks or max_clocks_for(items, holds)
    cycle = 0
    while not feeder.done:
        if cycle >= limit:
            raise CoreBusy(f"the core is still busy after {limit} clocks")
        tvalid, tdata, hold = feeder.step(cycle, model.outputs())
        model.clock(CoreInputs(tvalid=tvalid, tdata=tdata, hold=hold))
        cycle += 1
    return feeder.run


CLOCKED_LIMIT = 400_000         # a stream with pauses runs clock by clock up to this long


def _fast(cmds, config: CoreConfig, holds, max_clocks):
    from ..spec.fastcore import run_fast

    return run_fast(list(cmds), config.axes, config.width, config.depth, config.tw,
                    config.div, config.move_depth, config.profile_depth, config.step_cfg(),
                    holds, max_clocks=max_clocks)


def run_model(items, config: CoreConfig, holds=(), max_clocks: int | None = None
              ) -> Execution:
    """The core model as an executor.  Without pauses: ``spec.fastcore.run_fast``
    (event-skipping, bit-exact with the clock-by-clock model and tested so).  With
    pauses (the fast model has no pause markers): ``run_clocked`` when the run is short
    (under ``CLOCKED_LIMIT`` clocks, measured by a fast run without the pauses), else
    ``run_paused_fast``, exact in its lattice path but not cycle-exact after a pause
    (``Execution.approximate`` says so)."""
    limit = max_clocks or max_clocks_for(items, holds)
    if not any(isinstance(it, Pause) for it in items):
        r = _fast(items, config, holds, limit)
        # run_fast gives the cycle in which ``move`` shows; the edge that made it ended
        # the cycle before
        return Execution([(t - 1, tuple(p)) for t, p in zip(r.times, r.trace)],
                         list(r.errors), r.dry, r.underrun, r.clocks)
    cmds = [it for it in items if not isinstance(it, Pause)]
    pauses = sum(it.clocks for it in items if isinstance(it, Pause))
    # short or long: a fast run without the pauses, stopped at the clocked run's limit
    # (a long job is not run to its end twice)
    budget = min(CLOCKED_LIMIT - pauses, limit)
    if budget > 0:
        try:
            _fast(cmds, config, holds, budget)
        except CoreBusy:
            pass
        else:
            return run_clocked(items, config, holds, limit)
    return run_paused_fast(items, config, holds, limit)


def run_paused_fast(items, config: CoreConfig, holds=(), max_clocks: int | None = None
                    ) -> Execution:
    """Long streams with pauses on the fast model: each stretch between pauses runs on a
    fresh core (``run_fast``) from the position the last one reached, the pause's clocks
    after it went idle.  The lattice path, the errors and the flags are the core's; the
    cycles after a pause can differ from the clock-by-clock core's by the STEP/DIR
    generators' state a reset forgets (DIR setup and hold: a few ticks per pause)."""
    limit = max_clocks or max_clocks_for(items, holds)
    run = Execution()
    run.approximate = True
    offset = 0
    pos = (0,) * config.axes
    chunk: list = []
    mask = (1 << config.width) - 1

    def flush(chunk, offset, pos):
        shifted = [(a - offset, b - offset) for a, b in holds if b > offset]
        r = _fast(chunk, config, [(max(a, 0), b) for a, b in shifted], limit)
        for t, p in zip(r.times, r.trace):
            q = tuple(((u + v + (1 << (config.width - 1))) & mask) - (1 << (config.width - 1))
                      for u, v in zip(pos, p))
            run.moves.append((offset + t - 1, q))
        run.errors += list(r.errors)
        run.dry |= r.dry
        run.underrun |= r.underrun
        # the core went idle IDLE_CYCLES before run_fast stopped
        return offset + r.clocks - IDLE_CYCLES, (run.moves[-1][1] if run.moves else pos)

    for it in items:
        if isinstance(it, Pause):
            if chunk:
                offset, pos = flush(chunk, offset, pos)
                chunk = []
            offset += it.clocks
            continue
        chunk.append(it)
    if chunk:
        offset, pos = flush(chunk, offset, pos)
    run.cycles = offset + IDLE_CYCLES
    return run


__all__ = ["Pause", "PlannedCommand", "MotionPlan", "build_motion", "CoreConfig", "core_config",
           "Execution", "Feeder", "run_clocked", "run_model",
           "run_paused_fast"]
