# SPDX-License-Identifier: Apache-2.0
"""Event-skipping model of the motion core: real jobs, bit-exact with ``spec.core``
(issue 13, item 7).

``run_fast`` streams a program into the core back to back, as
``spec.core.run_program`` does (tvalid high while commands remain, the queue as full
as tready allows), optionally with feed-hold intervals, a constant feed override and
gaps in the stream (tvalid low, but never under a beat offered and not yet taken),
and returns the cycle of every move strobe, the position after every move, the error
codes, and the final ``dry`` / ``underrun`` flags: equal to the clock-by-clock model's,
cycle for cycle.  Cycle numbering is ``run_program``'s: cycle 0 is the first clock
after reset, a move made by the edge ending cycle c is seen (``move`` high) in cycle
c + 1, and a hold interval (A, B) drives ``hold`` high in cycles A .. B - 1.

Method: the exact ``CoreModel`` runs clock by clock whenever something discrete
happens; at the start of each cycle ``_static`` and ``_stage_clocks`` check whether the
core is in a stretch where only accumulators evolve, and if so compute in closed form
the number k of clocks before the next event and apply them at once (``_skip``); an
edge where only the running unit fills the move queue (or the move strobe clears)
runs through the specification's own unit section with the stage in closed form
(``_lean_clock``).  A stretch is
quiet when, on every one of its clocks:

* no beat enters the command queue (it is full, the program is all in, or the stream
  is in a gap, which ends the stretch where it ends) and the
  dispatcher neither pops, rejects nor hands a command to a unit;
* the units neither validate (each in its idle state or holding a validated command
  that cannot start: a unit is running, the other or, for an arc behind an arc, the
  arc unit itself, which loads only into an idle run stage, the clock after its last
  move: that clock, with no unit running, is never quiet) nor produce a move (none is
  running, or the move queue is full), and no profile enters the profile queue;
* the profile stage pops no move (its credit does not cover the head move's cost, or
  the STEP/DIR generators the head move needs are not ready yet), takes no profile,
  makes no speed step (the speed equals its registered target, or the cadence counter
  has not reached a tick since a step in the same direction), its exit staircase
  neither starts (the registered compares past d_exit / past d_stop low) nor steps
  (its remainder not negative) nor moved at the edge before (``ramp_changed``), its
  credit does not reach the cap;
* the hold input does not change and the override's product (registered override,
  product, target) and the registered target have settled.

In such a stretch the credit grows by v per clock (or stays at its cap), the
staircase's remainder shrinks by the same gains, the compares of the earned distance
s + credit with d_exit and d_stop register a clock late, the cadence counter counts up
to a tick (saturating), and each STEP/DIR generator counts its timers without
requests (SETUP -> HIGH -> LOW, low_t saturating; ``_sg_advance``).  The events are
found from those closed forms: the clock whose credit first covers a bound X is
ceil((X - credit) / v) (``_first_reach``), the staircase starts the clock after the
earned distance reaches d_exit, steps on the first clock j with credit(j) > credit(0)
+ ramp_left, and the head move pops on the first clock that both covers
its cost and has every axis it steps ready (readiness only grows without requests:
``_sg_ready_at``).  The clock of each event then runs exactly.  ``spec.core``,
``spec.profile`` and ``spec.stepgen`` stay the specification: this module only reads
and sets their registers.

``run_clocked`` is the clock-by-clock reference with the same hold and override
inputs (``run_program`` plus those inputs); the tests hold the two equal on random
programs.  ``measure_clocks_per_s`` gives the bench's ``model_clocks_per_s``: simulated
clocks per second of wall time of ``run_fast`` on a fixed plate-like job.
"""

from __future__ import annotations

import bisect
import math
import time
from dataclasses import dataclass

from . import encoding as enc
from . import profile as pf
from .arc import V_HOLD, V_IDLE
from .core import CoreBusy, CoreInputs, CoreModel, HeadView, ProgramRun
from .line import L_HOLD, L_IDLE
from .rules import wrap
from .stepgen import S_HIGH, S_LOW, S_SETUP, StepCfg, StepInputs

NEVER = 1 << 200                    # "no event in sight" (larger than any clock count)


@dataclass
class FastRun(ProgramRun):
    """``run_program``'s result, plus the final flags and the work done."""

    dry: int = 0                    # the profile stage's sticky dry flag at the end
    underrun: int = 0               # the core's sticky underrun flag at the end
    clocks: int = 0                 # cycles simulated (the run's length)
    exact: int = 0                  # of which clocked one by one by the exact model
    lean: int = 0                   # ... by the lean edges (``_try_pop``, ``_lean_clock``)


class _Intervals:
    """An input as a function of the cycle (hold, or a gap in the stream): high in
    A <= cycle < B for (A, B) in the intervals."""

    def __init__(self, holds):
        self.ivals = sorted((int(a), int(b)) for a, b in holds if b > a)
        self.edges = sorted({e for iv in self.ivals for e in iv})

    def at(self, cyc: int) -> int:
        return int(any(a <= cyc < b for a, b in self.ivals))

    def next_change(self, cyc: int) -> int:
        """The first cycle after ``cyc`` where hold may differ (NEVER: none)."""
        k = bisect.bisect_right(self.edges, cyc)
        return self.edges[k] if k < len(self.edges) else NEVER


def _first_reach(c0: int, v: int, cap: int, x: int) -> int:
    """First m >= 0 with min(c0 + m v, cap) >= x (c0 <= cap), NEVER if none."""
    if c0 >= x:
        return 0
    if v <= 0 or cap < x:
        return NEVER
    return -(-(x - c0) // v)


def _sg_advance(sg, c: StepCfg, k: int) -> None:
    """``k`` edges of a STEP/DIR generator without requests, in closed form."""
    if k <= 0:
        return
    if sg.state == S_LOW:
        low_t = sg.low_t + k
        if low_t > sg.tmax:
            low_t = sg.tmax
        sg.low_t = low_t
        sg.sp_ok = int(low_t >= c.stepspace)
        sg.dh_ok = int(low_t >= c.dirhold)
        return
    steplen = max(c.steplen, 1)
    left = k
    while left:
        if sg.state == S_LOW:
            sg.low_t = min(sg.low_t + left, sg.tmax)
            left = 0
        else:
            count = max(sg.cnt - 1, 0)          # edges that only count down
            if left <= count:
                sg.cnt -= left
                left = 0
            else:
                left -= count + 1               # ... and the edge that moves on
                if sg.state == S_SETUP:
                    sg.state, sg.cnt = S_HIGH, steplen
                else:
                    sg.state, sg.low_t, sg.cnt = S_LOW, 1, min(sg.cnt, 1)
    sg.sp_ok = int(sg.low_t >= c.stepspace)
    sg.dh_ok = int(sg.low_t >= c.dirhold)


def _sg_ready_at(sg, c: StepCfg, d: int) -> int:
    """First clock j >= 0 (no requests meanwhile) during which the generator is ready
    for direction ``d`` (NEVER if it never is)."""
    if sg.state == S_LOW:
        if sg.sp_ok and (d == sg.dir or sg.dh_ok):
            return 0
        t_low, low0 = 0, sg.low_t
    else:
        t_low = max(sg.cnt - 1, 0) + 1
        if sg.state == S_SETUP:
            t_low += max(max(c.steplen, 1) - 1, 0) + 1
        low0 = 1
    need = c.stepspace if d == sg.dir else max(c.stepspace, c.dirhold)
    if need > sg.tmax:
        return NEVER
    return t_low + max(0, need - low0)


def _static(m: CoreModel, more: bool):
    """The command side and the units for the next clock(s): False if something
    discrete happens there (a beat enters the queue, the dispatcher pops, rejects or
    hands a command over, a unit validates, a validated command enters the profile
    queue or would start with no unit running), else the running unit's name or None.
    Production (the running unit filling the move queue) is left to the caller."""
    if more and len(m.queue) < m.depth:
        return False
    arc, line = m.arc, m.line
    running = "arc" if arc.run is not None else ("line" if line.run is not None else None)
    av, lv = arc.vstate, line.vstate
    if av not in (V_IDLE, V_HOLD) or lv not in (L_IDLE, L_HOLD):
        return False
    if (av == V_HOLD or lv == L_HOLD) and (not m.accepted or running is None):
        return False
    if arc.out.reject or line.out.reject:
        return False
    if m.inflight is None and m.queue:
        h = m.head_view()
        if h.pop or h.take is not None or h.err_code or h.inflight_clear:
            return False
    return running


def _stage_clocks(m: CoreModel, running, more: bool, hold: int, ovq: int, limit: int) -> int:
    """Number of clocks from now (at most ``limit``) over which the profile stage is
    quiet (module docstring), 0 if this clock is not; the STEP/DIR generators follow
    in closed form (no requests without pops).  The stage's registered decisions
    (target, credit at its cap, past d_exit / d_stop, the override's product) must be
    settled or, for the compares, found by the same closed forms."""
    st = m.stage
    if st.ov_q != ovq or not st.override_settled():
        return 0
    if st.ramp_changed:
        return 0                        # the staircase moved at the edge before
    cur = st.cur
    if st.target != st.next_target(bool(hold)):
        return 0
    k = limit
    if cur is None:
        if st.v or st.ramp_on or st.ramp_dry or st.ramp_v or st.ramp_left or m.profiles \
                or st.full or st.past_exit or st.past_stop:
            return 0
        busy = m.queue or m.inflight is not None or running is not None \
            or m.arc.vstate != V_IDLE or m.line.vstate != L_IDLE or m.moves
        if not (more or busy):
            return 0                    # run_program counts idle clocks here
        return k
    cap = (cur.largest_cost() << pf.COST_SHIFT) << 1
    c0 = st.credit
    if st.full:
        if c0 < cap:
            return 0
        v = 0                           # at its cap: no gain, stays full
    else:
        v = st.v
        k = min(k, _first_reach(c0, v, NEVER, cap))
    dry_cond = not m.profiles and cur.v_exit
    sh = pf.COST_SHIFT
    # the exit staircase
    if not st.ramp_on:
        if st.ramp_left or st.past_exit or (st.past_stop and dry_cond):
            return 0
        k = min(k, _first_reach(c0, v, NEVER, max(cur.d_exit - st.s, 0) << sh) + 1)
        if dry_cond:
            k = min(k, _first_reach(c0, v, NEVER, max(cur.d_stop - st.s, 0) << sh) + 1)
    else:
        if (st.ramp_dry and not dry_cond) or st.ramp_left < 0:
            return 0
        k = min(k, _first_reach(c0, v, NEVER, c0 + st.ramp_left + 1))
    if k == 0:
        return 0
    # the speed: a step when the target differs and the cadence allows it
    target = st.target
    if target != st.v:
        direction = 1 if target > st.v else -1
        if st.last_dir != direction or st.since >= st.tick:
            return 0
        k = min(k, st.tick - st.since)
    # the head move: pops on the first clock with the credit and every axis ready,
    # never at rest under hold (v stays 0 through the window then: no step in it)
    if m.moves and not (hold and st.v == 0):
        head = m.moves[0]
        cost = pf.move_cost(head.cost_class, cur)
        jc = _first_reach(c0, v, NEVER, cost << sh)
        if jc < k:
            jr = 0
            for s, sg, c in zip(head.steps, m.stepgens, m.cfg):
                if s:
                    jr = max(jr, _sg_ready_at(sg, c, int(s > 0)))
            k = min(k, max(jc, jr))
    return k


def _skip_stage(m: CoreModel, k: int) -> None:
    """Apply ``k`` quiet clocks of the profile stage in closed form."""
    st = m.stage
    cur = st.cur
    if cur is not None:
        v = 0 if st.full else st.v
        last = st.credit + (k - 1) * v          # the credit of the last clock
        credit = last + v
        sh = pf.COST_SHIFT
        earned = st.s + (last >> sh)
        st.full = last >= (cur.largest_cost() << sh) << 1
        st.past_exit, st.past_stop = earned >= cur.d_exit, earned >= cur.d_stop
        if st.ramp_on:
            st.ramp_left = max(st.ramp_left - (credit - st.credit),
                               -pf.ramp_left_floor(st.div))
        st.credit = credit
    st.since = min(st.since + k, st.tick)


def _skip(m: CoreModel, k: int) -> None:
    """Apply ``k`` quiet clocks of the whole core (no unit clocks a move, no pop)."""
    _skip_stage(m, k)
    for sg, c in zip(m.stepgens, m.cfg):
        _sg_advance(sg, c, k)
    ao, lo = m.arc.out, m.line.out
    ao.move = ao.step_x = ao.step_y = ao.done = ao.reject = 0
    lo.move = lo.step = lo.done = lo.reject = 0
    m.abort_pin = m.stop_pin = 0


def _try_pop(m: CoreModel, hold: int, ovq: int) -> bool:
    """The edge of this clock when it pops the head move and does nothing else
    (the caller checked ``_static`` and that no unit produces): the stage's view of a
    pop written out (``ProfileStage.view`` / ``clock``), taken only when the move is
    not its segment's last, the staircase neither starts nor steps, the speed does
    not step and the registered target and override pipeline have settled; then the
    move queue, STEP/DIR requests and positions.  False (nothing changed) when the
    clock is anything else: it then runs exactly."""
    st = m.stage
    cur = st.cur
    if cur is None or not m.moves or st.ov_q != ovq:
        return False
    if not st.override_settled() or st.target != st.next_target(bool(hold)):
        return False
    if st.ramp_changed:
        return False
    head = m.moves[0]
    if head.last:
        return False
    sh = pf.COST_SHIFT
    cost = pf.move_cost(head.cost_class, cur)
    credit, v = st.credit, st.v
    if (credit >> sh) < cost or (hold and v == 0):
        return False
    for s, sg, c in zip(head.steps, m.stepgens, m.cfg):
        if s and not sg._ready(c, int(s > 0)):
            return False
    gain = 0 if st.full else v
    new_credit = credit - (cost << sh) + gain
    dry_cond = not m.profiles and cur.v_exit
    left = 0
    if not st.ramp_on:
        if st.past_exit or (st.past_stop and dry_cond) or st.ramp_left:
            return False
    else:
        if (st.ramp_dry and not dry_cond) or st.ramp_left < 0:
            return False
        left = max(st.ramp_left - gain, -pf.ramp_left_floor(st.div))
    target = st.target
    if target > v and (st.last_dir != 1 or st.since >= st.tick):
        return False
    if target < v and (st.last_dir != -1 or st.since >= st.tick):
        return False
    earned = st.s + (credit >> sh)
    st.full = credit >= (cur.largest_cost() << sh) << 1
    st.past_exit, st.past_stop = earned >= cur.d_exit, earned >= cur.d_stop
    # the edge
    if st.since < st.tick:
        st.since += 1
    st.credit = new_credit
    st.s += cost
    st.ramp_left = left
    m.moves.pop(0)
    width = m.width
    for axis, (s, sg, c) in enumerate(zip(head.steps, m.stepgens, m.cfg)):
        if s:
            sg.clock(c, StepInputs(req=1, req_dir=int(s > 0)))
            m.pos[axis] = wrap(m.pos[axis] + s, width)
        else:
            _sg_advance(sg, c, 1)
    ao, lo = m.arc.out, m.line.out
    ao.move = ao.step_x = ao.step_y = ao.done = ao.reject = 0
    lo.move = lo.step = lo.done = lo.reject = 0
    m.o_move = 1
    m.abort_pin = m.stop_pin = 0
    return True


def _lean_clock(m: CoreModel) -> None:
    """One edge at which the stage is quiet and the command side static (the caller
    checked both): the units clock through the specification's own section
    (``CoreModel._clock_units``: production, a segment's end and the next one's
    start), the stage and the STEP/DIR generators in closed form."""
    loading, push = m._clock_units(HeadView(profile=m.profile))
    if push is not None:
        m.moves.append(push)
    if m.helix_err:                     # CoreModel._clock_status: an arc's count error
        m.o_err, m.o_err_code = 1, enc.E_HELIX_COUNT
    _skip_stage(m, 1)
    for sg, c in zip(m.stepgens, m.cfg):
        _sg_advance(sg, c, 1)
    m.o_move = 0
    m.abort_pin = m.stop_pin = 0


def _new_model(axes, width, depth, tw, div, move_depth, profile_depth, cfg) -> CoreModel:
    return CoreModel(axes, width, depth, tw, div, move_depth, profile_depth,
                     [StepCfg(**vars(c)) for c in cfg] if cfg else [])


def run_fast(cmds, axes: int, width: int, depth: int, tw: int, div: int, move_depth: int,
             profile_depth: int, cfg, holds=(), override: int = pf.OVERRIDE_ONE,
             max_clocks: int = 1 << 40, gaps=()) -> FastRun:
    """Stream ``cmds`` into a fresh core back to back until it is idle again (as
    ``spec.core.run_program``), ``hold`` high in the cycles of ``holds`` [(A, B), ...]
    (A <= cycle < B), the feed override constant, and tvalid low in the cycles of
    ``gaps`` [(A, B), ...] except while a beat offered before is still waiting for
    tready (AXI4-Stream: a beat once offered stays offered); skips the quiet
    stretches."""
    m = _new_model(axes, width, depth, tw, div, move_depth, profile_depth, cfg)
    m.clock(CoreInputs(rst=1))
    hs = _Intervals(holds)
    gs = _Intervals(gaps)
    ovq = min(override, pf.OVERRIDE_ONE)
    run = FastRun([], [], [])
    n = len(cmds)
    idx = cyc = idle = 0
    hold_next = hs.next_change(-1)
    hold = hs.at(0)
    gap_next = gs.next_change(-1)
    gap = gs.at(0)
    waiting = False                 # a beat offered in the clock before, not taken
    while idx < n or idle < 4:
        if cyc >= max_clocks:
            raise CoreBusy(f"the core is still busy after {max_clocks} clocks")
        if cyc >= hold_next:
            hold = hs.at(cyc)
            hold_next = hs.next_change(cyc)
        if cyc >= gap_next:
            gap = gs.at(cyc)
            gap_next = gs.next_change(cyc)
        offer = idx < n and (waiting or not gap)
        if not m.o_err:
            more = idx < n
            running = _static(m, offer)
            if running is not False:
                # a quiet stretch, the edge that pops, the edge after it: in one go
                # while each is possible (the command side stays static meanwhile:
                # a beat offered waits, none is offered in a gap)
                stop_at = min(hold_next, gap_next, max_clocks)
                start = cyc
                if not m.o_move and (running is None or len(m.moves) >= m.move_depth):
                    k = _stage_clocks(m, running, more, hold, ovq, stop_at - cyc)
                    if k > 0:
                        _skip(m, k)
                        cyc += k
                    if cyc < stop_at and _try_pop(m, hold, ovq):
                        cyc += 1
                        run.lean += 1
                if cyc < stop_at and (m.o_move or (running is not None
                                                   and len(m.moves) < m.move_depth)) \
                        and _stage_clocks(m, running, more, hold, ovq, 1):
                    if m.o_move:
                        run.times.append(cyc)
                        run.trace.append(tuple(m.pos))
                    _lean_clock(m)
                    cyc += 1
                    run.lean += 1
                if cyc > start:
                    idle = 0
                    waiting = offer
                    continue
        o = m.outputs()
        if o.move:
            run.times.append(cyc)
            run.trace.append(o.pos)
        if o.err:
            run.errors.append(o.err_code)
        inp = CoreInputs(hold=hold, override=override)
        waiting = False
        if offer:
            inp.tvalid, inp.tdata = 1, cmds[idx]
            if o.tready:
                idx += 1
            else:
                waiting = True
        idle = 0 if (o.busy or idx < n) else idle + 1
        m.clock(inp)
        cyc += 1
        run.exact += 1
    run.dry, run.underrun, run.clocks = m.stage.dry, m.o_underrun, cyc
    return run


def run_clocked(cmds, axes: int, width: int, depth: int, tw: int, div: int, move_depth: int,
                profile_depth: int, cfg, holds=(), override: int = pf.OVERRIDE_ONE,
                max_clocks: int = 50_000_000, gaps=()) -> FastRun:
    """The clock-by-clock reference: ``spec.core.run_program``'s loop with the same
    hold, override and stream-gap inputs as ``run_fast``."""
    m = _new_model(axes, width, depth, tw, div, move_depth, profile_depth, cfg)
    m.clock(CoreInputs(rst=1))
    hs = _Intervals(holds)
    gs = _Intervals(gaps)
    run = FastRun([], [], [])
    n = len(cmds)
    idx = cyc = idle = 0
    waiting = False
    while idx < n or idle < 4:
        if cyc >= max_clocks:
            raise CoreBusy(f"the core is still busy after {max_clocks} clocks")
        o = m.outputs()
        if o.move:
            run.times.append(cyc)
            run.trace.append(o.pos)
        if o.err:
            run.errors.append(o.err_code)
        inp = CoreInputs(hold=hs.at(cyc), override=override)
        offer = idx < n and (waiting or not gs.at(cyc))
        waiting = False
        if offer:
            inp.tvalid, inp.tdata = 1, cmds[idx]
            if o.tready:
                idx += 1
            else:
                waiting = True
        idle = 0 if (o.busy or idx < n) else idle + 1
        m.clock(inp)
        cyc += 1
    run.dry, run.underrun, run.clocks, run.exact = m.stage.dry, m.o_underrun, cyc, cyc
    return run


# --- the bench's figure -------------------------------------------------------------------

BENCH_CLOCK_HZ = 50_000_000
BENCH_DIV = 12                      # pf.choose_div(50 MHz)


def plate_job(scale: int = 1):
    """A fixed plate-like job at the shipped machine's figures (50 MHz, 1 um BLU, DIV
    12, STEP/DIR timing 100 / 100 / 250 / 250 ticks): a rounded rectangle of 4 lines
    and 4 quarter arcs (R 10 mm), then a slot of short lines, ``scale`` times, at 10 to
    100 mm/s (0.0002 .. 0.002 BLU per clock) and 1000 mm/s^2 (arcs 500), junctions
    planned.  Returns (commands, StepCfg list)."""
    r, side = 10_000, 40_000
    body = []
    for _ in range(scale):
        for dx, dy, cw_turn in ((side, 0, (0, r, r, r)), (0, side, (-r, 0, -r, r)),
                                (-side, 0, (0, -r, -r, -r)), (0, -side, (r, 0, r, -r))):
            body.append(enc.encode_line((dx, dy, 0), True))
            i, j, x, y = cw_turn
            body.append(enc.encode_arc(0, i, j, x, y, True))
        for k in range(8):
            body.append(enc.encode_line((1500, 300 * (-1) ** k, 0), True))
    if body:                        # the program's last segment ends it (no CONT)
        body[-1] = enc.encode_line((1500, -300, 0), False)
    feeds = [10.0, 100.0, 60.0, 25.0, 100.0, 40.0]

    def speed(k):
        return pf.speed_field(feeds[k % len(feeds)], 0.001, BENCH_CLOCK_HZ)

    def accel(k):
        return pf.accel_field(1000.0, 0.001, BENCH_CLOCK_HZ, BENCH_DIV) // (1 + k % 2)

    from .program import profiled
    prog = profiled(body, 3, 32, BENCH_DIV, v_cruise=speed, accel=accel,
                    junction=lambda k: speed(k) // 3)
    cfg = [StepCfg(100, 100, 250, 250) for _ in range(3)]
    return prog, cfg


def measure_clocks_per_s(scale: int = 1) -> float:
    """Simulated clocks per second of wall time of ``run_fast`` on ``plate_job``
    (the bench's ``model_clocks_per_s``)."""
    prog, cfg = plate_job(scale)
    t0 = time.perf_counter()
    res = run_fast(prog, 3, 32, 16, 16, BENCH_DIV, 4, 2, cfg)
    wall = time.perf_counter() - t0
    return res.clocks / wall if wall > 0 else math.inf
