# SPDX-License-Identifier: Apache-2.0
"""Cycle-accurate model of the motion core ``rtl/halfpoint_core.v``.

Data path, clock by clock:

  AXI4-Stream commands -> queue (DEPTH) -> dispatcher -> arc unit (X, Y)
                                                      -> line unit (NA axes)
  feed-rate generator + step/dir generators decide `go`; the running unit
  makes its move on `go`; positions and STEP/DIR pins follow.

* Queue: takes a beat when tvalid & tready, tready = queue not full.
* Dispatcher: at most one command *in flight* (handed to a unit and not yet
  started or rejected), so the two units run segments in program order.  It
  decodes the queue head: a bad opcode, reserved bits or a field that does
  not fit W is rejected at once (popped, error code, no motion); a line with
  all deltas zero is dropped as a no-op; otherwise the head goes to its unit
  (popped when the unit takes it).  The in-flight flag clears on the edge
  where the unit starts the segment, or one clock after the unit's reject
  pulse.
* Sequencing: a unit may start its pending segment when the other unit is
  idle or making its last move at this edge, so a segment boundary costs no
  clock when the next segment has been validated in time.
* Feed: a credit accumulator gains rate x k per clock (k in {0, 1, 2} from
  the feed override: an accumulator of `override` percent per clock, k = how
  many hundreds it passes; the override is registered, so a change takes
  effect one clock later); a move needs credit >= its cost, 2^24 for a move
  of one axis or a line iteration, round(sqrt(2) 2^24) for a diagonal arc
  move, and spends it.  Credit is capped at 2^26 and does not grow while no
  segment runs.
* STEP/DIR: every axis the next move steps must be ready for its direction;
  otherwise the move waits (held back, never dropped).
* Underrun: a segment with CONT set ended and no segment started at that edge.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

from . import encoding as enc
from .arc import MOVE_A, V_HOLD, ArcInputs, ArcUnitModel
from .line import L_HOLD, LineInputs, LineUnitModel
from .rules import fits, wrap
from .stepgen import StepCfg, StepGenModel, StepInputs

COST_AXIS = enc.RATE_ONE
COST_DIAG = round(math.sqrt(2) * enc.RATE_ONE)
CREDIT_CAP = 1 << 26
OVERRIDE_MAX = 200

ARC_ERR_MAP = {1: enc.E_ARC_RADIUS, 2: enc.E_ARC_RANGE, 3: enc.E_ARC_END}


def decode_for_core(cmd: int, axes: int, width: int):
    """('err', code) | ('nop',) | ('line', deltas, rate, cont) |
    ('arc', (cw, xs, ys, xe, ye), rate, cont): what the dispatcher does."""
    d = enc.decode(cmd)
    op = d["opcode"]
    if op not in (enc.OP_LINE, enc.OP_ARC_CW, enc.OP_ARC_CCW) or not d["reserved_ok"]:
        return ("err", enc.E_OPCODE)
    if op == enc.OP_LINE:
        deltas = d["deltas"]
        if any(deltas[axes:]):
            return ("err", enc.E_OPCODE)
        deltas = deltas[:axes]
        if not all(fits(v, width) for v in deltas):
            return ("err", enc.E_FIELD)
        if not any(deltas):
            return ("nop",)
        return ("line", tuple(deltas), d["rate"], d["cont"])
    xs, ys = -d["i"], -d["j"]
    xe, ye = d["x"] - d["i"], d["y"] - d["j"]
    if not all(fits(v, width) for v in (d["i"], d["j"], d["x"], d["y"], xs, ys, xe, ye)):
        return ("err", enc.E_FIELD)
    return ("arc", (d["cw"], xs, ys, xe, ye), d["rate"], d["cont"])


@dataclass
class CoreInputs:
    tvalid: int = 0
    tdata: int = 0
    override: int = 100
    rst: int = 0
    abort: int = 0


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


@dataclass
class HeadView:
    """Dispatcher, combinational: what happens to the queue head this cycle."""

    cmd: tuple | None = None        # decoded command handed to a unit ('arc' | 'line', ...)
    take: str | None = None         # the unit that takes it at this edge
    pop: bool = False               # the head leaves the queue at this edge
    err_code: int = 0               # reject reported at this edge (decode or unit)
    inflight_clear: bool = False    # a unit's reject pulse ends the command in flight


@dataclass
class MoveView:
    """Feed and STEP/DIR readiness, combinational: the move of this cycle."""

    unit: str | None = None         # the unit in its run stage
    steps: list = field(default_factory=list)   # signed step per axis of its next move
    cost: int = COST_AXIS           # credit the move needs
    go: bool = False                # the move is made at this edge
    rate: int = 0                   # rate of the running segment
    cont: bool = False              # CONT of the running segment


@dataclass
class CoreModel:
    """Clock-by-clock twin of ``halfpoint_core``.

    :meth:`outputs` gives what the RTL shows during the current cycle;
    :meth:`clock` applies one rising edge.  ``clock`` first computes the two
    combinational views every section reads (the dispatcher's view of the
    queue head, and the move the feed and STEP/DIR readiness allow), then
    clocks the sections in the RTL's order: queue, dispatcher, units, feed,
    STEP/DIR generators and positions, status.
    """

    axes: int = 3
    width: int = 32
    depth: int = 16
    tw: int = 16
    cfg: list = field(default_factory=list)     # StepCfg per axis

    def __post_init__(self) -> None:
        if not 2 <= self.axes <= 6:
            raise ValueError("the core has 2..6 axes (arcs use axes 0 and 1)")
        if self.depth < 2 or self.depth & (self.depth - 1):
            raise ValueError("queue depth must be a power of two >= 2")
        if not self.cfg:
            self.cfg = [StepCfg() for _ in range(self.axes)]
        self.reset()

    def reset(self) -> None:
        self.queue: list[int] = []
        self.inflight: str | None = None
        self.arc = ArcUnitModel(self.width)
        self.line = LineUnitModel(self.axes, self.width)
        self.pend = {"arc": (0, False), "line": (0, False)}    # (rate, cont) handed over
        self.act = {"arc": (0, False), "line": (0, False)}     # of the running segment
        self.credit = 0
        self.ov_acc = 0
        self.ov_in = 0              # the override input, clamped, registered
        self.stepgens = [StepGenModel(self.tw) for _ in range(self.axes)]
        self.pos = [0] * self.axes
        self.o_move = 0
        self.o_err = 0
        self.o_err_code = 0
        self.o_underrun = 0
        self.abort_pin = 0          # abort as last driven: tready depends on it

    def move_cost(self, diagonal: bool) -> int:
        """Credit a move needs: a diagonal arc move is sqrt(2) times as long."""
        return COST_DIAG if diagonal else COST_AXIS

    def _abort(self) -> None:
        """An edge with abort high: no move, everything not yet moved dropped."""
        self.queue.clear()
        self.inflight = None
        self.arc.clock(ArcInputs(abort=1))
        self.line.clock(LineInputs(s_delta=(0,) * self.axes, abort=1))
        self.credit = 0
        for sg, c in zip(self.stepgens, self.cfg):
            sg.clock(c, StepInputs())
        self.o_move = 0
        self.o_err = 0

    # ------------------------------------------------------------------
    def _running(self) -> str | None:
        if self.arc.run is not None:
            return "arc"
        if self.line.run is not None:
            return "line"
        return None

    def _peek(self, unit: str):
        """(signed steps per axis, diagonal) of the running unit's next move."""
        if unit == "arc":
            kind, dx, dy = self.arc.run.peek()
            return [dx, dy] + [0] * (self.axes - 2), kind == MOVE_A
        return list(self.line.run.peek()), False

    def outputs(self) -> CoreOutputs:
        step_pins = dir_pins = 0
        for k, (sg, c) in enumerate(zip(self.stepgens, self.cfg)):
            o = sg.outputs(c)
            step_pins |= o.step_pin << k
            dir_pins |= o.dir_pin << k
        busy = bool(self.queue) or self.inflight is not None \
            or self.arc.outputs().busy or self.line.outputs().busy \
            or any(sg.state != 0 for sg in self.stepgens)
        return CoreOutputs(
            tready=int(len(self.queue) < self.depth and not self.abort_pin), busy=int(busy),
            level=len(self.queue), move=self.o_move, pos=tuple(self.pos),
            step_pins=step_pins, dir_pins=dir_pins, err=self.o_err,
            err_code=self.o_err_code, underrun=self.o_underrun,
        )

    # -- combinational views ------------------------------------------
    def head_view(self) -> HeadView:
        """Dispatcher: decode the queue head (when nothing is in flight) and
        see which unit takes it; the units' reject pulses of this cycle."""
        h = HeadView()
        if self.inflight is None and self.queue:
            dec = decode_for_core(self.queue[0], self.axes, self.width)
            if dec[0] == "err":
                h.pop, h.err_code = True, dec[1]
            elif dec[0] == "nop":
                h.pop = True
            else:
                h.cmd = dec
                unit = self.arc if dec[0] == "arc" else self.line
                if unit.outputs().s_ready:
                    h.take, h.pop = dec[0], True
        arc_o, line_o = self.arc.outputs(), self.line.outputs()
        if arc_o.reject:
            h.err_code = ARC_ERR_MAP[arc_o.err_code]
        if line_o.reject:
            h.err_code = enc.E_OPCODE  # empty lines never reach the unit
        h.inflight_clear = bool(arc_o.reject or line_o.reject)
        return h

    def move_view(self) -> MoveView:
        """go: the running unit's next move is made when every axis it steps
        is ready for its direction and the credit covers its cost."""
        m = MoveView(steps=[0] * self.axes)
        m.unit = self._running()
        if m.unit is None:
            return m
        m.rate, m.cont = self.act[m.unit]
        m.steps, diagonal = self._peek(m.unit)
        m.cost = self.move_cost(diagonal)
        ready = all(
            s == 0 or (sg.outputs(c).ready_pos if s > 0 else sg.outputs(c).ready_neg)
            for s, sg, c in zip(m.steps, self.stepgens, self.cfg)
        )
        m.go = ready and self.credit >= m.cost
        return m

    # -- the edge, section by section -----------------------------------
    def clock(self, i: CoreInputs) -> None:
        if i.rst:
            self.reset()
            return
        self.abort_pin = i.abort
        override = min(i.override, OVERRIDE_MAX)
        if i.abort:
            self.ov_in = override
            self._abort()
            return
        head = self.head_view()
        move = self.move_view()
        self._clock_queue(i, head)
        self._clock_dispatcher(head)
        ending, loading = self._clock_units(head, move)
        self._clock_feed(move, override)
        self._clock_stepgens(move)
        self._clock_status(head, move, ending, loading)

    def _clock_queue(self, i: CoreInputs, head: HeadView) -> None:
        """Pop the head if it left; push a beat (tready from the level before the edge)."""
        push = i.tvalid and len(self.queue) < self.depth
        if head.pop:
            self.queue.pop(0)
        if push:
            self.queue.append(i.tdata)

    def _clock_dispatcher(self, head: HeadView) -> None:
        """The command handed to a unit is in flight; its rate and CONT wait
        beside the unit until the segment starts."""
        if head.take is not None:
            self.inflight = head.take
            self.pend[head.take] = (head.cmd[2], head.cmd[3])

    def _clock_units(self, head: HeadView, move: MoveView) -> tuple[bool, str | None]:
        """Clock both units, the running one first: its last move at this edge
        lets the other start its pending segment on the same edge.  Returns
        (the running segment ended, the unit that loaded a segment)."""
        ending = False
        loading = None
        order = ["arc", "line"] if move.unit != "line" else ["line", "arc"]
        for u in order:
            other_idle_or_ending = (move.unit is None) or (move.unit == u) or ending
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
            inp.en = int(move.go and move.unit == u)
            inp.start_en = int(other_idle_or_ending)
            holding = model.vstate == hold
            model.clock(inp)
            if move.unit == u and model.outputs().done:
                ending = True
            if holding and model.vstate != hold:
                loading = u
        if loading is not None:
            self.act[loading] = self.pend[loading]
            if self.inflight == loading:
                self.inflight = None
        if head.inflight_clear:
            self.inflight = None
        return ending, loading

    def _clock_feed(self, move: MoveView, override: int) -> None:
        """Credit += rate x k - cost of the move made; k from the registered
        override (k computed a clock ahead in the RTL, the same here)."""
        ov = self.ov_in
        self.ov_in = override
        s = self.ov_acc + ov
        k = 2 if s >= 200 else 1 if s >= 100 else 0
        self.ov_acc = s - 100 * k
        credit = self.credit + move.rate * k - (move.cost if move.go else 0)
        self.credit = min(credit, CREDIT_CAP)

    def _clock_stepgens(self, move: MoveView) -> None:
        """A step request to every axis the move steps; positions follow."""
        for axis, (sg, c) in enumerate(zip(self.stepgens, self.cfg)):
            st = move.steps[axis] if move.go else 0
            sg.clock(c, StepInputs(req=int(st != 0), req_dir=int(st > 0)))
            if st:
                self.pos[axis] = wrap(self.pos[axis] + st, self.width)
        self.o_move = int(move.go)

    def _clock_status(self, head: HeadView, move: MoveView, ending: bool,
                      loading: str | None) -> None:
        """err / err_code; underrun: a CONT segment ended and nothing started."""
        if ending and move.cont and loading is None:
            self.o_underrun = 1
        self.o_err = int(head.err_code != 0)
        if head.err_code:
            self.o_err_code = head.err_code


@dataclass
class ProgramRun:
    times: list[int]            # clock of every move strobe
    trace: list[tuple]          # positions after every move
    errors: list[int]           # err_code of every rejected command


def run_program(model: CoreModel, cmds) -> ProgramRun:
    """Reset ``model`` and stream ``cmds`` into it back to back (the queue kept
    as full as tready allows) until the core is idle again."""
    model.clock(CoreInputs(rst=1))
    run = ProgramRun([], [], [])
    idx, cyc, idle = 0, 0, 0
    while idx < len(cmds) or idle < 4:
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
