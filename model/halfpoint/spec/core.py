# SPDX-License-Identifier: Apache-2.0
"""Cycle-accurate model of the motion core ``rtl/halfpoint_core.v``.

Data path, clock by clock (issue 13: the interpolators decoupled from the pacing):

  AXI4-Stream commands -> queue (DEPTH) -> dispatcher -> arc unit (u, v)  -+-> move queue
                                                      -> line unit (NA)   -+   (MOVE_DEPTH)
      profile in force ---------------- on a segment's start -> profile queue (PROFILE_DEPTH)
  move queue head + profile queue head -> profile stage (``spec.profile``) -> pop ->
  STEP/DIR generators and positions

* Queue: takes a beat when tvalid & tready, tready = queue not full, abort_now low,
  not (stop high with the profile stage at rest) and no stop flush at this edge.
* Dispatcher: at most one command *in flight* (handed to a unit and not yet
  started or rejected), so the two units run segments in program order.  It
  decodes the queue head: a bad opcode, reserved bits or a field that does not fit
  W is rejected at once (popped, error code, no motion); a line with all deltas
  zero is dropped as a no-op; a PROFILE becomes the profile in force (a bad one is
  rejected, E_PROFILE_FIELD, and forgets the profile in force); a motion command
  with no profile in force, or an arc under a line's profile (line cost not 0) or
  a line under an arc's, is rejected (E_PROFILE); otherwise the head goes to its
  unit (popped when the unit takes it).  The in-flight flag clears on the edge
  where the unit starts the segment, or one clock after the unit's reject pulse.
* Profiles: a motion command is handed to its unit only while the profile queue
  has room (its count before the edge); once the unit has validated it (it waits
  in the unit's pending slot), its profile (the one in force: nothing can change it
  while a command is in flight) and CONT flag enter the profile queue, so the
  profile stage knows the next segment is coming as soon as it is known to be
  good, long before its first move (an arc the validator rejects never enters).
* Interpolators: a unit may start its pending segment when the other unit is idle
  (not running before the edge: a boundary between an arc and a line costs the
  interpolators one clock, which the move queue hides; the other unit's last move
  does not feed the start, so no end test lies in front of a load).  The running
  unit makes a move on every edge at which the move queue has room (its count
  before the edge, so the interpolators never wait for the pacing in the same
  clock); the move enters the queue with its steps, its cost
  class (axis move, diagonal arc move, line iteration) and whether it is its
  segment's last.
* Profile stage (``spec.profile.ProfileStage``, the one definition of the pacing):
  pops the head move when its credit covers the move's cost and every axis the move
  steps is ready for its direction (the STEP/DIR generators); takes the next profile
  when the current segment's last move pops (or when none is current).  ``hold``
  decelerates to rest and waits; ``stop`` decelerates to rest and then drops
  everything not yet moved, like abort_now, one clock later: an edge at rest with
  stop high (the stage's ``stopped``: the stage drops its own segment and credit,
  pops and takes nothing; the rest of the core clocks as on any edge, a reject there
  reported, but an OUTPUT does not load while stop is high) sets the flush register,
  and the next edge is the flush (``_flush``; the stage sees stop held high at it,
  so it takes nothing from the queues being dropped).  A stop held high at rest
  therefore flushes at every edge from the second one on.  The flush is a register so
  that no path runs from the stage's speed register through the dispatcher to the
  queue's clock enables.  ``feed_override`` (1/128, 0..128) scales the cruise speed,
  its changes ramping at the segment's acceleration.
* Helix (``spec.helix``): the arc unit's moves are in its plane (u, v); the mapper
  puts them on the command's two axes and steps the helix slots' axes against the
  arc's move count N; an arc whose move count is not N reports E_HELIX_COUNT at its
  last move (that code wins over a reject at the same edge).
* STEP/DIR: a popped move requests a step on every axis it steps; positions count
  them.
* Outputs (``spec.outputs.OutputStage``): an OUTPUT command waits at the queue
  head until everything before it has moved (nothing in flight, both units idle,
  the move and profile queues empty, the profile stage idle: no segment and speed
  0) and stop is low, then pops and loads the spindle, laser and coolant settings at
  that edge.  (An idle stage is at rest, so with stop high that edge is a stop at
  rest: the OUTPUT is dropped by the flush that follows, as it always was.)
  The output stage sees the profile stage's speed and, on each ``take``, the new
  segment's cruise speed; abort and a stop at rest switch every output off.
* Underrun: a segment with CONT set made its last move and no next profile was
  taken at that edge.  ``dry`` (sticky): the profile stage had to decelerate for a
  dry queue (see ``spec.profile``).
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace

from . import encoding as enc
from . import profile as pf
from .arc import MOVE_A, V_HOLD, ArcInputs, ArcUnitModel
from .helix import HelixCommand, HelixMapper, helix_error
from .line import L_HOLD, LineInputs, LineUnitModel
from .outputs import OutputInputs, OutputStage
from .rules import fits, wrap
from .stepgen import StepCfg, StepGenModel, StepInputs

ARC_ERR_MAP = {1: enc.E_ARC_RADIUS, 2: enc.E_ARC_RANGE, 3: enc.E_ARC_END}


def profile_fields_ok(p: pf.ProfileParams, width: int) -> bool:
    """The core's rules for a PROFILE's fields (else E_PROFILE_FIELD)."""
    top = 1 << pf.distance_bits(width)
    return (p.accel != 0 and p.v_exit <= p.v_cruise and p.d_stop <= p.d_exit
            and p.d_exit < top and p.power <= enc.OUTPUT_POWER_FULL
            and (p.set_power or p.power == 0))


def decode_for_core(cmd: int, axes: int, width: int):
    """('err', code) | ('nop',) | ('profile', ProfileParams) | ('line', deltas, cont) |
    ('arc', (cw, xs, ys, xe, ye), cont, HelixCommand) | ('output', OutputSettings): what the
    dispatcher does with the head
    (the profile rules that depend on the profile in force: ``dispatch``)."""
    d = enc.decode(cmd)
    op = d["opcode"]
    if op not in (enc.OP_LINE, enc.OP_ARC_CW, enc.OP_ARC_CCW, enc.OP_PROFILE,
                  enc.OP_OUTPUT) or not d["reserved_ok"]:
        return ("err", enc.E_OPCODE)
    if op == enc.OP_OUTPUT:
        if d["power"] > enc.OUTPUT_POWER_FULL:
            return ("err", enc.E_FIELD)
        return ("output", OutputSettings(*(d[name] for name, _, _ in enc.OUTPUT_FIELDS)))
    if op == enc.OP_PROFILE:
        params = pf.ProfileParams(*(d[name] for name, _, _ in enc.PROFILE_FIELDS))
        if not profile_fields_ok(params, width):
            return ("err", enc.E_PROFILE_FIELD)
        return ("profile", params)
    if op == enc.OP_LINE:
        deltas = d["deltas"]
        if any(deltas[axes:]):
            return ("err", enc.E_OPCODE)
        deltas = deltas[:axes]
        if not all(fits(v, width) for v in deltas):
            return ("err", enc.E_FIELD)
        if not any(deltas):
            return ("nop",)
        return ("line", tuple(deltas), d["cont"])
    xs, ys = -d["i"], -d["j"]
    xe, ye = d["x"] - d["i"], d["y"] - d["j"]
    helix = HelixCommand(d["u_axis"], d["v_axis"], d["count"], d["helix"])
    code = helix_error(helix, axes, lambda v: fits(v, width))
    if code == enc.E_OPCODE:
        return ("err", code)
    if not all(fits(v, width) for v in (d["i"], d["j"], d["x"], d["y"], xs, ys, xe, ye)):
        return ("err", enc.E_FIELD)
    if code:
        return ("err", code)
    return ("arc", (d["cw"], xs, ys, xe, ye), d["cont"], helix)


def dispatch(dec, profile):
    """The dispatcher's rule on a decoded head and the profile in force: returns
    (what happens, the profile in force after it).  What happens is dec itself for
    a motion command that may run, ('err', code) for a reject, ('nop',) for a no-op
    or an accepted PROFILE."""
    kind = dec[0]
    if kind == "err":
        return dec, (None if dec[1] == enc.E_PROFILE_FIELD else profile)
    if kind == "nop":
        return dec, profile
    if kind == "profile":
        return ("nop",), dec[1]
    if kind == "output":
        return dec, profile
    if profile is None or (kind == "arc") != (profile.line_cost == 0):
        return ("err", enc.E_PROFILE), profile
    return dec, profile


@dataclass
class OutputSettings:
    """The fields of an OUTPUT command (``encoding.OUTPUT_FIELDS``)."""

    power: int = 0
    enable: int = 0
    reverse: int = 0
    laser: int = 0
    dynamic: int = 0
    mist: int = 0
    flood: int = 0


@dataclass
class CoreInputs:
    tvalid: int = 0
    tdata: int = 0
    override: int = pf.OVERRIDE_ONE
    rst: int = 0
    abort: int = 0
    hold: int = 0
    stop: int = 0


@dataclass
class CoreOutputs:
    tready: int
    busy: int
    level: int
    move: int
    pos: tuple
    step_pins: int
    dir_pins: int
    err: int
    err_code: int
    underrun: int
    dry: int
    speed: int
    spindle_enable: int = 0
    spindle_reverse: int = 0
    spindle_pwm: int = 0
    coolant_mist: int = 0
    coolant_flood: int = 0
    duty: int = 0


@dataclass
class HeadView:
    """Dispatcher, combinational: what happens to the queue head this cycle."""

    cmd: tuple | None = None        # decoded command handed to a unit ('arc' | 'line', ...)
    take: str | None = None         # the unit that takes it at this edge
    pop: bool = False               # the head leaves the queue at this edge
    err_code: int = 0               # reject reported at this edge (decode or unit)
    inflight_clear: bool = False    # a unit's reject pulse ends the command in flight
    profile: pf.ProfileParams | None = None     # the profile in force after this edge
    output: OutputSettings | None = None        # an OUTPUT executed at this edge


@dataclass
class QueuedMove:
    """An entry of the move queue."""

    steps: tuple                    # signed step per axis
    cost_class: int                 # profile.CLASS_AXIS / CLASS_DIAG / CLASS_LINE
    last: bool                      # the segment's last move


@dataclass
class CoreModel:
    """Clock-by-clock twin of ``halfpoint_core``.

    :meth:`outputs` gives what the RTL shows during the current cycle;
    :meth:`clock` applies one rising edge.  ``clock`` first computes the two
    combinational views every section reads (the dispatcher's view of the queue
    head, and the profile stage's view of the move queue head), then clocks the
    sections in the RTL's order: queue, dispatcher, units and move queue, profile
    queue and stage, STEP/DIR generators and positions, status.
    """

    axes: int = 3
    width: int = 32
    depth: int = 16
    tw: int = 16
    div: int = 12                   # profile tick 2^div clocks
    move_depth: int = 4
    profile_depth: int = 2
    cfg: list = field(default_factory=list)     # StepCfg per axis
    pwm_bits: int = 10              # the output stage's PWM period 2^pwm_bits clocks

    def __post_init__(self) -> None:
        if not 2 <= self.axes <= 6:
            raise ValueError("the core has 2..6 axes")
        if self.depth < 2 or self.depth & (self.depth - 1):
            raise ValueError("queue depth must be a power of two >= 2")
        if not 2 <= self.move_depth <= 16:
            raise ValueError("the move queue has 2..16 entries")
        if not 1 <= self.profile_depth <= 8:
            raise ValueError("the profile queue has 1..8 entries")
        if not self.cfg:
            self.cfg = [StepCfg() for _ in range(self.axes)]
        self.reset()

    def reset(self) -> None:
        self.queue: list[int] = []
        self.inflight: str | None = None
        self.profile: pf.ProfileParams | None = None    # the profile in force
        self.pend_cont = False                          # CONT of the command in flight
        self.accepted = False               # its profile entered the profile queue
        self.arc = ArcUnitModel(self.width)
        self.helix = HelixMapper(self.axes)
        self.helix_err = False              # E_HELIX_COUNT at this edge (the arc's last move)
        self.line = LineUnitModel(self.axes, self.width)
        self.moves: list[QueuedMove] = []               # the move queue
        self.profiles: list[tuple] = []                 # the profile queue: (params, cont)
        self.stage = pf.ProfileStage(self.div, self.width)
        self.stage_cont = False                         # CONT of the stage's segment
        self.stepgens = [StepGenModel(self.tw) for _ in range(self.axes)]
        self.out_stage = OutputStage(self.pwm_bits)
        self.pos = [0] * self.axes
        self.o_move = 0
        self.o_err = 0
        self.o_err_code = 0
        self.o_underrun = 0
        # abort_now and stop registered at each edge (the core acts on them from the
        # edge after they rise; tready depends on these registers)
        self.abort_pin = 0
        self.stop_pin = 0
        # the stop flush register: set at an edge at rest with stop high, the next
        # edge drops everything not yet moved
        self.flush_q = False

    def _flush(self, i: CoreInputs, stage_in: pf.ProfileInputs | None = None) -> None:
        """An edge with abort high, or with the stop flush register set (``stage_in``:
        the stage's inputs with stop held high; it is at rest with no segment since
        the edge before): no move, everything not yet moved dropped, the profile in
        force forgotten."""
        self.queue.clear()
        self.inflight = None
        self.accepted = False
        self.profile = None
        self.arc.clock(ArcInputs(abort=1))
        self.helix.clock(None, False, False, abort=True)
        self.helix_err = False
        self.line.clock(LineInputs(s_delta=(0,) * self.axes, abort=1))
        self.moves.clear()
        self.profiles.clear()
        self.stage_cont = False
        speed = self.stage.outputs().v
        self.stage.clock(stage_in or pf.ProfileInputs(abort=1, override=i.override))
        for sg, c in zip(self.stepgens, self.cfg):
            sg.clock(c, StepInputs())
        self._clock_outputs(None, True, speed, None)
        self.o_move = 0
        self.o_err = 0

    # ------------------------------------------------------------------
    def _running(self) -> str | None:
        if self.arc.run is not None:
            return "arc"
        if self.line.run is not None:
            return "line"
        return None

    def _peek(self, unit: str) -> tuple[tuple, int]:
        """(signed steps per axis, cost class) of the running unit's next move."""
        if unit == "arc":
            kind, dx, dy = self.arc.run.peek()
            cls = pf.CLASS_DIAG if kind == MOVE_A else pf.CLASS_AXIS
            return self.helix.steps(dx, dy), cls
        return tuple(self.line.run.peek()), pf.CLASS_LINE

    def _ready(self, steps) -> bool:
        """Every axis ``steps`` steps is ready for its direction."""
        return all(
            s == 0 or (sg.outputs(c).ready_pos if s > 0 else sg.outputs(c).ready_neg)
            for s, sg, c in zip(steps, self.stepgens, self.cfg))

    def outputs(self) -> CoreOutputs:
        step_pins = dir_pins = 0
        for k, (sg, c) in enumerate(zip(self.stepgens, self.cfg)):
            o = sg.outputs(c)
            step_pins |= o.step_pin << k
            dir_pins |= o.dir_pin << k
        so = self.stage.outputs()
        busy = bool(self.queue) or self.inflight is not None \
            or self.arc.outputs().busy or self.line.outputs().busy \
            or bool(self.moves) or bool(self.profiles) or bool(so.busy) \
            or any(sg.state != 0 for sg in self.stepgens)
        # a stop at rest now (the stage's stopped) or the stop flush at this edge
        at_rest_stop = (self.stop_pin or self.flush_q) and so.v == 0
        return CoreOutputs(
            tready=int(len(self.queue) < self.depth and not self.abort_pin
                       and not at_rest_stop),
            busy=int(busy), level=len(self.queue), move=self.o_move, pos=tuple(self.pos),
            step_pins=step_pins, dir_pins=dir_pins, err=self.o_err,
            err_code=self.o_err_code, underrun=self.o_underrun, dry=so.dry, speed=so.v,
            **self._output_pins())

    # -- combinational views ------------------------------------------
    def head_view(self, stop: int = 0) -> HeadView:
        """Dispatcher: decode the queue head (when nothing is in flight), apply the
        profile rules and see which unit takes it; the units' reject pulses.  ``stop``
        (the registered stop): an OUTPUT does not load (with the machine idle that is a
        stop at rest, and the next edge drops it)."""
        h = HeadView(profile=self.profile)
        if self.inflight is None and self.queue:
            dec, h.profile = dispatch(decode_for_core(self.queue[0], self.axes, self.width),
                                      self.profile)
            if dec[0] == "err":
                h.pop, h.err_code = True, dec[1]
            elif dec[0] == "nop":
                h.pop = True
            elif dec[0] == "output":
                if self.downstream_idle() and not stop:
                    h.pop, h.output = True, dec[1]
            else:
                h.cmd = dec
                unit = self.arc if dec[0] == "arc" else self.line
                if unit.outputs().s_ready and len(self.profiles) < self.profile_depth:
                    h.take, h.pop = dec[0], True
        arc_o, line_o = self.arc.outputs(), self.line.outputs()
        if arc_o.reject:
            h.err_code = ARC_ERR_MAP[arc_o.err_code]
        if line_o.reject:
            h.err_code = enc.E_OPCODE  # empty lines never reach the unit
        h.inflight_clear = bool(arc_o.reject or line_o.reject)
        return h

    def downstream_idle(self) -> bool:
        """Everything handed out before has moved: both units idle, the move and
        profile queues empty, the profile stage idle (no segment, speed 0).  (Nothing
        is in flight when the dispatcher looks at the head.)"""
        return not (self.arc.outputs().busy or self.line.outputs().busy or self.moves
                    or self.profiles or self.stage.outputs().busy)

    def stage_inputs(self, i: CoreInputs) -> pf.ProfileInputs:
        """The profile stage's inputs: the move queue's head and the profile queue's."""
        inp = pf.ProfileInputs(hold=i.hold, stop=i.stop, override=i.override)
        if self.moves:
            head = self.moves[0]
            inp.head_valid, inp.head_class, inp.head_last = 1, head.cost_class, int(head.last)
            inp.ready = int(self._ready(head.steps))
        if self.profiles:
            inp.next_valid, inp.next_profile = 1, self.profiles[0][0]
        return inp

    # -- the edge, section by section -----------------------------------
    def clock(self, i: CoreInputs) -> pf.ProfileView | None:
        """One rising edge; returns the profile stage's view of the clock (None on
        reset and flush edges: abort, or the stop flush register set)."""
        if i.rst:
            self.reset()
            return None
        # the registered abort_now and stop act at this edge; the inputs enter them
        raw_abort, raw_stop = i.abort, i.stop
        i = replace(i, abort=self.abort_pin, stop=self.stop_pin)
        self.abort_pin, self.stop_pin = raw_abort, raw_stop
        if i.abort:
            self.flush_q = False
            self._flush(i)
            return None
        # a stop at rest during this clock flushes at the next edge; a flush edge
        # (the register set) holds the stage's stop high
        flush, self.flush_q = self.flush_q, bool(i.stop and self.stage.v == 0)
        if flush:
            self._flush(i, self.stage_inputs(replace(i, stop=1)))
            return None
        sin = self.stage_inputs(i)
        w = self.stage.view(sin)
        head = self.head_view(i.stop)
        self._clock_queue(i, head, w.stopped)
        loading, push = self._clock_units(head)
        popped = self.moves[0] if w.pop else None
        self._clock_move_queue(w, push)
        speed = self.stage.outputs().v
        taken = self.profiles[0][0] if w.take else None
        self._clock_stage(sin, w, loading)
        self._clock_outputs(head.output, False, speed, taken)
        self._clock_stepgens(popped)
        self._clock_status(head, popped, w)
        return w

    def _clock_queue(self, i: CoreInputs, head: HeadView, at_rest_stop: bool) -> None:
        """Pop the head if it left; push a beat (tready from the level before the edge;
        low at a stop at rest)."""
        push = i.tvalid and len(self.queue) < self.depth and not at_rest_stop
        if head.pop:
            self.queue.pop(0)
        if push:
            self.queue.append(i.tdata)
        self.profile = head.profile
        if head.take is not None:
            self.inflight = head.take
            self.pend_cont = head.cmd[2]

    def _clock_units(self, head: HeadView) -> tuple[str | None, QueuedMove | None]:
        """Clock both units, the running one first (a unit starts its pending segment
        only when the other was not running before the edge).  Returns (the unit that
        started a segment, the move made at this edge)."""
        running = self._running()
        produce = len(self.moves) < self.move_depth
        # the command in flight validated (waiting in its unit's pending slot): its
        # profile enters the profile queue (there is room: taken only with room)
        accept = not self.accepted and (self.arc.vstate == V_HOLD or self.line.vstate == L_HOLD)
        move = None
        if running is not None and produce:
            steps, cls = self._peek(running)
            move = QueuedMove(steps, cls, False)
        loading = None
        order = ["arc", "line"] if running != "line" else ["line", "arc"]
        for u in order:
            other_idle = (running is None) or (running == u)
            offer = head.take == u
            if u == "arc":
                model, hold = self.arc, V_HOLD
                if offer:
                    cw, xs, ys, xe, ye = head.cmd[1]
                    inp = ArcInputs(s_valid=1, s_cw=cw, s_xs=xs, s_ys=ys, s_xe=xe, s_ye=ye)
                else:
                    inp = ArcInputs()
            else:
                model, hold = self.line, L_HOLD
                inp = LineInputs(s_valid=1, s_delta=head.cmd[1]) if offer \
                    else LineInputs(s_delta=(0,) * self.axes)
            inp.en = int(produce and running == u)
            inp.start_en = int(other_idle)
            holding = model.vstate == hold
            model.clock(inp)
            if running == u and move is not None and model.outputs().done:
                move.last = True
            if holding and model.vstate != hold:
                loading = u
        # the arc-to-axes mapper: the running arc's move, the pending arc's start, the
        # arc handed over (spec.helix)
        arc_move = running == "arc" and move is not None
        self.helix_err = arc_move and self.helix.count_error(move.last)
        self.helix.clock(head.cmd[3] if head.take == "arc" else None, loading == "arc",
                         arc_move)
        if accept:
            self.profiles.append((self.profile, self.pend_cont))
            self.accepted = True
        if loading is not None:
            self.accepted = False
            if self.inflight == loading:
                self.inflight = None
        if head.inflight_clear:
            self.inflight = None
        return loading, move

    def _clock_move_queue(self, w: pf.ProfileView, push: QueuedMove | None) -> None:
        if w.pop:
            self.moves.pop(0)
        if push is not None:
            self.moves.append(push)

    def _clock_stage(self, sin: pf.ProfileInputs, w: pf.ProfileView,
                     loading: str | None) -> None:
        """The profile stage's edge; the profile queue pops on ``take`` (the segment
        that started at this edge is pushed behind)."""
        ended = w.pop and sin.head_last
        self.o_underrun |= int(ended and self.stage_cont and not w.take)
        self.stage.clock(sin)
        if w.take:
            _, self.stage_cont = self.profiles.pop(0)
        elif ended:
            self.stage_cont = False

    def _clock_stepgens(self, popped: QueuedMove | None) -> None:
        """A step request to every axis the popped move steps; positions follow."""
        for axis, (sg, c) in enumerate(zip(self.stepgens, self.cfg)):
            st = popped.steps[axis] if popped is not None else 0
            sg.clock(c, StepInputs(req=int(st != 0), req_dir=int(st > 0)))
            if st:
                self.pos[axis] = wrap(self.pos[axis] + st, self.width)
        self.o_move = int(popped is not None)

    def _output_pins(self) -> dict:
        o = self.out_stage.outputs()
        return dict(spindle_enable=o.spindle_enable, spindle_reverse=o.spindle_reverse,
                    spindle_pwm=o.pwm, coolant_mist=o.coolant_mist,
                    coolant_flood=o.coolant_flood, duty=o.duty)

    def _clock_outputs(self, load: OutputSettings | None, off: bool, speed: int,
                       taken: pf.ProfileParams | None) -> None:
        """The output stage's edge: ``load`` an OUTPUT's settings, ``off`` (abort or a
        stop at rest), the profile stage's speed during the cycle, and the profile of
        the segment the stage takes at this edge (its cruise speed, and its power when
        it sets one)."""
        settings = load or OutputSettings()
        take = taken or pf.ProfileParams(0, 0, 0)
        self.out_stage.clock(OutputInputs(
            load=int(load is not None), load_power=settings.power,
            load_enable=settings.enable, load_reverse=settings.reverse,
            load_laser=settings.laser, load_dynamic=settings.dynamic,
            load_mist=settings.mist, load_flood=settings.flood, off=int(off),
            speed=speed, take=int(taken is not None), take_v_cruise=take.v_cruise,
            take_set_power=take.set_power, take_power=take.power))

    def _clock_status(self, head: HeadView, popped, w) -> None:
        """err / err_code (an arc's move count error wins over a reject at the
        same edge)."""
        self.o_err = int(head.err_code != 0 or self.helix_err)
        if self.helix_err:
            self.o_err_code = enc.E_HELIX_COUNT
        elif head.err_code:
            self.o_err_code = head.err_code


@dataclass
class ProgramRun:
    times: list[int]            # clock of every move strobe
    trace: list[tuple]          # positions after every move
    errors: list[int]           # err_code of every rejected command


class CoreBusy(RuntimeError):
    """A run of the core (clock by clock or event-skipping) reached its clock bound
    with the core still busy."""


def run_program(model: CoreModel, cmds, max_clocks: int = 50_000_000) -> ProgramRun:
    """Reset ``model`` and stream ``cmds`` into it back to back (the queue kept
    as full as tready allows) until the core is idle again."""
    model.clock(CoreInputs(rst=1))
    run = ProgramRun([], [], [])
    idx, cyc, idle = 0, 0, 0
    while idx < len(cmds) or idle < 4:
        if cyc >= max_clocks:
            raise CoreBusy(f"the core is still busy after {max_clocks} clocks")
        o = model.outputs()
        if o.move:
            run.times.append(cyc)
            run.trace.append(o.pos)
        if o.err:
            run.errors.append(o.err_code)
        inp = CoreInputs()
        if idx < len(cmds):
            inp = CoreInputs(tvalid=1, tdata=cmds[idx])
            if o.tready:
                idx += 1
        idle = 0 if (o.busy or idx < len(cmds)) else idle + 1
        model.clock(inp)
        cyc += 1
    return run
