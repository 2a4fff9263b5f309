# SPDX-License-Identifier: Apache-2.0
"""cam/motion: the planner's speeds as PROFILEs, run through the core model.

On the coarse simulation machine (examples/machine_sim.toml: 10 MHz, 10 um BLU, axes
up to 20 m/s), so that the runs are tens of thousands of clocks: the stream's shape
(a PROFILE before every motion command, CONT, pauses), junction speeds at 0, 30, 90,
150 and 180 degrees reaching the core's profiles and its moves, a 2,000-segment
collinear chain that cruises, and path accelerations measured from the trace against
each command's planned limit (spec/profile.py: the speed step is the nearest of the
exact one, within 1 %; the speed changes by at most one step per tick).
"""

from __future__ import annotations

import math
from pathlib import Path

import pytest

from halfpoint.cam import machine as mc
from halfpoint.cam.gcode import GcodeError, parse
from halfpoint.cam.motion import Pause, build_motion, core_config, run_clocked, run_model
from halfpoint.cam.planner import junction_speed_sqr
from halfpoint.cam.quant import quantise
from halfpoint.cam.run import move_costs, plan_items_compensated, run_program
from halfpoint.spec import encoding as enc
from halfpoint.spec import profile as pf

EX = Path(__file__).resolve().parents[2] / "examples"
SIM = mc.load(EX / "machine_sim.toml")


def _plan(text: str, machine=SIM):
    prog = parse(text)
    q = quantise(prog.moves, machine.blu)
    return q, build_motion(q, plan_items_compensated(prog, prog.moves, machine), machine)


def _run(tmp_path, text: str, holds=(), execute=None):
    f = tmp_path / "p.ngc"
    f.write_text(text)
    return run_program(str(f), execute, machine=SIM, holds=holds)


def test_a_profile_before_every_motion_command_cont_and_pauses():
    q, mp = _plan("G21 G90 F600000\nG1 X10\nG2 X20 I5 J0\nG4 P0.0003\nG1 Y5\nM2\n")
    kinds = []
    for it in mp.items:
        if isinstance(it, Pause):
            kinds.append("pause")
            continue
        d = enc.decode(it)
        kinds.append({enc.OP_PROFILE: "P", enc.OP_LINE: "L", enc.OP_ARC_CW: "A"}[d["opcode"]])
    # correcting lines may precede the arc: every motion command has its PROFILE
    assert kinds[0] == "P" and "pause" in kinds
    assert all(kinds[i - 1] == "P" for i, k in enumerate(kinds) if k in "LA")
    assert kinds.count("P") == len(q.cmds) == len(mp.commands)
    pause = mp.pauses[0]
    assert pause.clocks == 3000 and pause.lineno == 4
    before = kinds.index("pause")
    conts = [bool(c.cmd & enc.FLAG_CONT) for c in mp.commands]
    # CONT everywhere but before the pause and at the end
    n_before = sum(1 for k in kinds[:before] if k in "LA")
    assert conts == [True] * (n_before - 1) + [False] + [True] * (len(conts) - n_before - 1) \
        + [False]
    # the last command before the dwell and the last of all end at rest
    assert mp.commands[n_before - 1].profile.v_exit == 0
    assert mp.commands[-1].profile.v_exit == 0


def _speed_before(res, k_last: int, n: int = 8) -> float:
    """Path speed (BLU of X per clock) over the ``n`` moves ending with move ``k_last``."""
    costs = move_costs(res)
    t = res.cycles
    dist = sum(costs[k_last - n + 1:k_last + 1]) / res.blu[0]
    return dist / (t[k_last] - t[k_last - n])


@pytest.mark.parametrize("theta", [0, 30, 90, 150, 180])
def test_junction_speeds_reach_the_profiles_and_the_moves(tmp_path, theta):
    """Two 20 mm lines meeting at ``theta`` degrees (180: straight on, 0: reversal):
    the first command's exit speed is the planner's junction speed (junction deviation)
    in the core's field, kept by the integer passes, and the core makes the line's last
    moves at that speed."""
    turn = math.radians(180 - theta)
    x2, y2 = 20 + 20 * math.cos(turn), 20 * math.sin(turn)
    text = f"G21 G90 F900000\nG1 X20\nG1 X{x2:.6f} Y{y2:.6f}\nM2\n"
    res = _run(tmp_path, text)
    first = res.motion.commands[0]
    seg0, seg1 = [s for s in res.motion.planned]
    v_limit = min(seg0.v_limit, seg1.v_limit)
    want = min(math.sqrt(junction_speed_sqr(seg0.dir_end, seg1.dir_start, SIM, 20, 20)),
               v_limit)
    assert seg0.v_exit == pytest.approx(want, rel=1e-9)
    field = pf.speed_field(want, SIM.blu[0], SIM.clock_hz) if want > 0 else 0
    assert first.v_exit == min(field, first.v_cruise)
    assert first.profile.v_exit == first.v_exit          # long lines: nothing to lower
    if theta == 180:
        assert first.profile.v_exit == first.profile.v_cruise
    elif theta == 0:
        assert first.profile.v_exit == 0
    else:
        assert 0 < first.profile.v_exit < first.profile.v_cruise
    # the core's last moves of the first line: the last at the exit speed (the creep
    # speed, one speed step, for a stop), the ones before it at most one step above
    last = first.moves - 1
    v = _speed_before(res, last)
    step = first.profile.accel / (1 << pf.SPEED_FRAC) / (1 << pf.SPEED_SHIFT) \
        * (1 << pf.SPEED_SHIFT)
    ve = first.profile.v_exit / (1 << pf.FIELD_SPEED_FRAC) or step
    assert 0.95 * ve <= v <= 1.05 * (ve + step), (v, ve, step)
    if theta in (150, 180):
        assert v > 2 * step                  # far from a stop
    assert res.execution.dry == 0 and res.execution.underrun == 0


def _accel_check(res, ticks: int = 4):
    """(largest measured path acceleration / its command's limit, allowance used): the
    distance earned on a grid of W = ``ticks`` ticks, speeds over each W, accelerations
    between neighbouring W; every value against the largest limit of the commands
    whose moves lie within reach, allowing for the trace's granularity (the distance
    at a grid point is known to within 3 move costs: the credit holds up to two)."""
    div = res.motion.div
    w = ticks << div
    costs = move_costs(res)
    limit_of = []
    for pc in res.motion.commands:
        limit_of += [pc.profile.accel / (1 << pf.SPEED_FRAC) / (1 << div)] * pc.moves
    cycles = res.cycles
    end = res.execution.cycles
    grid = list(range(0, end + 2 * w, w))
    s = [0.0] * len(grid)
    lim = [0.0] * len(grid)
    acc = 0.0
    for c, cost, a in zip(cycles, costs, limit_of):
        acc += cost / res.blu[0]
        j = c // w + 1                    # the move is before grid point j
        s[j] = acc
        lim[j - 1] = max(lim[j - 1], a)
    for j in range(1, len(s)):
        s[j] = max(s[j], s[j - 1])
    cmax = max(costs) / res.blu[0]
    allowance = 4 * 3 * cmax / (w * w)
    worst = 0.0
    for j in range(len(grid) - 3):
        v1 = (s[j + 1] - s[j]) / w
        v2 = (s[j + 2] - s[j + 1]) / w
        near = max(lim[max(j - 1, 0):j + 4])
        if near == 0:
            continue
        worst = max(worst, (abs(v2 - v1) / w - allowance) / near)
    return worst, allowance


PINS_BOUND = 1 + 2 * pf.MAX_ERROR

PROGRAM = ("G21 G90 G17 F900000\nG1 X10\nG1 X20 Y5\nG2 X30 Y5 I5 J0\n"
           "G3 X30 Y15 I0 J5\nG1 X5 Y15\nG0 X0 Y0\nM2\n")


def test_accelerations_from_the_trace_stay_within_the_limits(tmp_path):
    res = _run(tmp_path, PROGRAM)
    worst, allowance = _accel_check(res)
    # the pins' bound: the stage's speed register changes by at most accel per tick
    # (tb/halfpoint_profile); the pins follow it through the credit and the STEP/DIR
    # readiness, which this grid only partly allows for: measured 1.013 on this program
    # (2026-11-23), held to 2 % (PINS_BOUND, stated in the README)
    assert worst <= PINS_BOUND, worst
    # the measure sees the ramps: it is not vacuous
    assert worst > 0.5, worst
    # and with a hold in the middle (decelerating at the planned rate and back)
    held = _run(tmp_path, PROGRAM, holds=[(30000, 40000)])
    assert held.lattice == res.lattice
    worst_h, _ = _accel_check(held)
    assert worst_h <= PINS_BOUND, worst_h
    assert held.execution.cycles > res.execution.cycles


def test_accel_check_fails_on_a_core_that_jumps(tmp_path):
    """The same check on a run whose commands claim a quarter of the acceleration they
    ran with fails: the check can fail."""
    res = _run(tmp_path, PROGRAM)
    for pc in res.motion.commands:
        pc.profile = pf.ProfileParams(pc.profile.v_cruise, pc.profile.v_exit,
                                      max(1, pc.profile.accel // 4), pc.profile.line_cost,
                                      pc.profile.d_exit, pc.profile.d_stop)
    worst, _ = _accel_check(res)
    assert worst > PINS_BOUND


def test_two_thousand_collinear_segments_cruise(tmp_path):
    """The issue's test: 2,000 segments of 0.2 mm in one direction (off the axes, so
    the lattice commands zigzag) run at F in the core: the integer passes keep every
    junction at the cruise speed except where the chain starts and stops, and the run
    takes the feed's time plus the two ramps.  (A slower machine than SIM: the
    integer forward pass lets a segment climb only the speed steps it surely reaches
    within itself, a tick of travel each, so segments must be longer than one tick's
    travel at cruise, 10 BLU here; see the report on spec.profile.plan_integer.)"""
    text = (EX / "machine_sim.toml").read_text()
    text = text.replace("max_accel_mm_s2 = 20000000.0", "max_accel_mm_s2 = 2000000.0")
    slow = mc.loads(text, "slow sim machine")
    lines = ["G21 G90 F60000", "G1 X0 Y0"]
    for k in range(1, 2001):
        lines.append(f"G1 X{0.192 * k:.4f} Y{0.056 * k:.4f}")
    f = tmp_path / "chain.ngc"
    f.write_text("\n".join(lines) + "\nM2\n")
    res = run_program(str(f), machine=slow)
    cmds = res.motion.commands
    assert len(cmds) >= 2000
    cruising = sum(1 for c in cmds[:-1] if c.profile.v_exit == c.profile.v_cruise
                   == c.v_cruise)
    assert cruising >= len(cmds) - 20, cruising
    v = cmds[len(cmds) // 2].profile.v_cruise / (1 << pf.FIELD_SPEED_FRAC)
    assert v == pytest.approx(1000 / slow.clock_hz / slow.blu[0], rel=1e-3)
    length = 2000 * math.hypot(0.192, 0.056) / slow.blu[0]
    ramp = v / (cmds[0].profile.accel / (1 << pf.SPEED_FRAC)) * (1 << res.motion.div)
    assert res.execution.cycles <= 1.03 * (length / v + ramp)
    assert res.execution.dry == 0 and res.execution.underrun == 0


def test_dwell_is_a_timed_pause_in_program_order(tmp_path):
    text = "G21 G90 F600000\nG1 X5\nG4 P0.0004\nG1 X10\nM2\n"
    res = _run(tmp_path, text, execute=run_clocked)
    first = res.motion.commands[0].moves
    t = res.cycles
    gap = t[first] - t[first - 1]
    assert gap >= 4000                       # the core stopped, then waited 0.4 ms
    assert gap < 4000 + 3000                 # and went on: idle detection and ramp-up


def test_fast_model_executor_equals_the_clocked_one(tmp_path):
    """run_model's fast path (spec.fastcore, streams without pauses) against the
    clock-by-clock executor on the same stream: every move and its cycle."""
    text = "G21 G90 F600000\nG1 X5\nG1 X10 Y3\nG2 X14 Y3 I2 J0\nM2\n"
    res = _run(tmp_path, text, execute=run_clocked)
    items = res.motion.items
    cfg = core_config(SIM)
    assert run_model(items, cfg) == run_clocked(items, cfg)


def test_long_runs_with_pauses_keep_the_lattice_path(tmp_path):
    """run_paused_fast (long jobs with dwells): the same moves as the clock-by-clock
    core, cycles within a few ticks after each pause, and it says it is approximate."""
    from halfpoint.cam.motion import run_paused_fast

    text = "G21 G90 F600000\nG1 X5\nG4 P0.0004\nG1 X10 Y-3\nG4 P0.0001\nG0 X0 Y0\nM2\n"
    res = _run(tmp_path, text, execute=run_clocked)
    fast = run_paused_fast(res.motion.items, core_config(SIM))
    exact = res.execution
    assert fast.approximate and not exact.approximate
    assert [p for _, p in fast.moves] == [p for _, p in exact.moves]
    assert max(abs(a - b) for (a, _), (b, _) in zip(fast.moves, exact.moves)) <= 16
    assert abs(fast.cycles - exact.cycles) <= 16


def test_run_model_measures_a_paused_job_only_up_to_the_clocked_limit(tmp_path, monkeypatch):
    """With pauses, run_model runs the stream clock by clock when it is short and on the
    paused fast model when it is long; the fast run that decides stops at the clocked
    limit instead of running a long job to its end first (until 2026-11-28 a G4 P0 on an
    8,650-command raster made its run take 81 s instead of 45)."""
    from halfpoint.cam import motion

    text = "G21 G90 F600000\nG1 X5\nG4 P0.0004\nG1 X10 Y-3\nM2\n"
    items = _run(tmp_path, text, execute=run_clocked).motion.items
    cfg = core_config(SIM)
    limits = []
    real = motion._fast

    def spy(cmds, config, holds, max_clocks):
        limits.append(max_clocks)
        return real(cmds, config, holds, max_clocks)

    monkeypatch.setattr(motion, "_fast", spy)
    assert not run_model(items, cfg).approximate            # short: clock by clock
    assert limits and max(limits) <= motion.CLOCKED_LIMIT
    monkeypatch.setattr(motion, "CLOCKED_LIMIT", 5000)      # the same job counts as long
    limits.clear()
    long = run_model(items, cfg)
    assert long.approximate and limits[0] <= 5000
    assert [p for _, p in long.moves] == [p for _, p in run_clocked(items, cfg).moves]


def test_compensated_moves_keep_their_dwells_in_order():
    prog = parse("G21 F600\nG0 X-5\nG41.1 D2 G1 X0 Y0\nG4 P1\nX10\nG40 X15\nM2\n")
    from halfpoint.cam.comp import compensate
    comp = compensate(prog.moves)
    items = plan_items_compensated(prog, comp.moves)
    kinds = [type(it).__name__ for it in items]
    assert kinds.count("Dwell") == 1
    k = kinds.index("Dwell")
    # the dwell follows the entry move (line 3) and precedes the line 5 move
    assert items[k - 1].lineno == 3 and items[k + 1].lineno == 5


def test_too_slow_a_feed_for_the_fixed_point_names_the_line(tmp_path):
    # 0.001 mm/min on the 10 um, 10 MHz machine: 1.7e-11 BLU per clock, under the LSB
    with pytest.raises(GcodeError, match="line 3: the core's fixed point cannot hold"):
        _plan("G21 G90 F6000\nG1 X1\nG1 X2 F0.001\nM2\n")
