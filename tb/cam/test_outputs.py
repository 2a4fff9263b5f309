# SPDX-License-Identifier: Apache-2.0
"""Spindle, laser and coolant on the host: the machine file's [spindle] table, S to PWM
power, the OUTPUT commands in program order (issue 14, item 3), and programs with them
through the core model; laser mode's power carried with the motion (the PROFILEs'
power, no stop at an S word or a G0).

The core side (the dispatcher holding an OUTPUT until everything before it has moved,
the output stage's PWM) is tested clock by clock in tb/halfpoint_core and
tb/halfpoint_outputs; here: what the host sends, and that the model runs it with the
motion before each change ending at rest, and in laser mode the power switching at a
segment boundary with the motion running.
"""

from __future__ import annotations

import math
from dataclasses import replace
from fractions import Fraction
from pathlib import Path

import pytest

from halfpoint.cam import machine as mc
from halfpoint.cam.gcode import parse
from halfpoint.cam.motion import (Feeder, Pause, build_motion, core_config, run_clocked,
                                  run_model)
from halfpoint.cam.planner import Dwell, OutputChange, PowerChange, estimate_time, plan
from halfpoint.cam.quant import quantise
from halfpoint.cam.run import output_settings, plan_items_compensated, run_program
from halfpoint.spec import encoding as enc
from halfpoint.spec.core import decode_for_core

EX = Path(__file__).resolve().parents[2] / "examples"
SIM = mc.load(EX / "machine_sim.toml")
FULL = enc.OUTPUT_POWER_FULL


def _sim(**spindle) -> mc.Machine:
    return replace(SIM, **spindle)


# --- the machine file ----------------------------------------------------------------------

def _machine_text(spindle: str) -> str:
    text = (EX / "machine_sim.toml").read_text()
    return text + "\n[spindle]\n" + spindle + "\n"


def test_spindle_table_defaults_and_values():
    assert (SIM.spindle_max, SIM.spindle_min, SIM.laser_mode) == (1000.0, 0.0, False)
    m = mc.loads(_machine_text("max_speed = 24000\nmin_speed = 1000\nlaser_mode = true"))
    assert (m.spindle_max, m.spindle_min, m.laser_mode) == (24000.0, 1000.0, True)
    shipped = mc.load(EX / "machine.toml")
    assert shipped.spindle_max == 24000.0 and not shipped.laser_mode


@pytest.mark.parametrize("body, key", [
    ("max_rpm = 10", "spindle.max_rpm"),
    ("max_speed = 0", "spindle.max_speed"),
    ("max_speed = 100\nmin_speed = 100", "spindle.min_speed"),
    ("min_speed = -1", "spindle.min_speed"),
    ("laser_mode = 1", "spindle.laser_mode"),
])
def test_bad_spindle_table_names_the_key(body, key):
    with pytest.raises(mc.MachineError) as e:
        mc.loads(_machine_text(body), "m.toml")
    assert e.value.key == key and str(e.value).startswith(f"m.toml: {key}")


# --- S to power, M3/M4 in and out of laser mode -------------------------------------------

def test_output_settings_map_s_to_power():
    m = _sim(spindle_max=24000.0, spindle_min=6000.0)
    # (power, enable, reverse, laser, dynamic, mist, flood)
    assert output_settings(m, True, True, 12000, False, False) == (FULL // 2, 1, 0, 0, 0, 0, 0)
    assert output_settings(m, True, True, 30000, False, True)[0] == FULL       # clamped
    assert output_settings(m, True, True, 1000, False, False)[0] == FULL // 4  # min_speed
    assert output_settings(m, True, True, 0, False, False)[0] == 0             # S0: off
    assert output_settings(m, True, False, 24000, True, False) == (FULL, 1, 1, 0, 0, 1, 0)
    assert output_settings(m, False, True, 24000, False, False)[1] == 0
    laser = replace(m, laser_mode=True)
    assert output_settings(laser, True, False, 24000, False, False) == (FULL, 1, 0, 1, 1, 0, 0)
    assert output_settings(laser, True, True, 24000, False, False) == (FULL, 1, 0, 1, 0, 0, 0)


# --- OUTPUT commands in program order ---------------------------------------------------

PROGRAM = """G21 G90 F600000
G1 X1
M3 S500
G1 X2
M8
G1 X3
S250
G1 X4
M5 M9
G1 X5
M2
"""


def _items(text, machine):
    prog = parse(text)
    return prog, plan_items_compensated(prog, prog.moves, machine)


def test_output_changes_stand_before_their_moves():
    prog, items = _items(PROGRAM, SIM)
    shape = [("out", it.settings) if isinstance(it, OutputChange) else it.end[0]
             for it in items]
    half, quarter = FULL // 2, FULL // 4
    assert shape == [1.0, ("out", (half, 1, 0, 0, 0, 0, 0)), 2.0,
                     ("out", (half, 1, 0, 0, 0, 0, 1)), 3.0,
                     ("out", (quarter, 1, 0, 0, 0, 0, 1)), 4.0,
                     ("out", (quarter, 0, 0, 0, 0, 0, 0)), 5.0]      # M5 M9: one change
    # without a machine: the dwells only (the old behaviour)
    assert not any(isinstance(it, OutputChange) for it in plan_items_compensated(
        prog, prog.moves))


def _shape(items) -> list:
    """OUTPUTs with their settings (power, enable, reverse, laser, dynamic, mist, flood),
    power changes with their power, and the moves' kinds."""
    return [("out", it.settings) if isinstance(it, OutputChange) else
            ("power", it.power) if isinstance(it, PowerChange) else it.kind for it in items]


def test_laser_mode_switches_the_laser_off_for_rapids():
    text = "G21 G90 F600000\nM4 S1000\nG0 X1\nG1 X2\nG1 X3\nG0 X4\nG1 Y1\nM5\nM2\n"
    _, items = _items(text, _sim(laser_mode=True))
    # M4 is an OUTPUT (at rest: the program starts there); the G0s do not stop: the
    # laser stays enabled and the rapids carry power 0 in their PROFILEs, the cuts S
    assert _shape(items) == [("out", (FULL, 1, 0, 1, 1, 0, 0)), ("power", 0), "rapid",
                             ("power", FULL), "line", "line", ("power", 0), "rapid",
                             ("power", FULL), "line", ("out", (FULL, 0, 0, 1, 0, 0, 0))]


# --- laser mode: the power travels with the motion ----------------------------------------

RASTER_ROWS, RASTER_COLUMNS = 4, 5


def _raster(s_words: bool) -> str:
    """A LightBurn-style raster: M4 at the top, a G0 to the start of each row, then a G1
    per pixel (each with its own S when ``s_words``), rows back and forth, M5 at the end."""
    out = ["G21 G90", "M4 S1000" if not s_words else "M4", "G1 F30000"]
    for r in range(RASTER_ROWS):
        cols = range(RASTER_COLUMNS) if r % 2 == 0 else range(RASTER_COLUMNS - 1, -1, -1)
        out.append(f"G0 X{0 if r % 2 == 0 else RASTER_COLUMNS} Y{r * 0.5}")
        for c in cols:
            x = c + 1 if r % 2 == 0 else c
            out.append(f"G1 X{x}" + (f" S{_raster_s(r, c)}" if s_words else ""))
    return "\n".join(out + ["M5", "G0 X0 Y0", "M2"]) + "\n"


def _raster_s(r: int, c: int) -> int:
    return 100 + 150 * ((3 * r + 2 * c) % 7)            # 100 .. 1000, never twice in a row


# the sim machine with slow accelerations: a stop costs far more than a pixel's cruise,
# so a stop at every S word shows in the run time (as on a real machine)
LASER = _sim(laser_mode=True, axes=tuple(replace(a, max_accel_mm_s2=200_000.0)
                                         for a in SIM.axes))


def _motion(text: str, machine):
    prog, items = _items(text, machine)
    return prog, build_motion(quantise(prog.moves, machine.blu), items, machine)


def _decoded(mp) -> list:
    return [enc.decode(it) for it in mp.items]


def test_a_laser_raster_runs_through_its_s_words(tmp_path):
    _, mp = _motion(_raster(True), LASER)
    _, items = _items(_raster(True), LASER)
    # no stop between the first cut and the last: only power changes there
    cuts = [k for k, it in enumerate(items) if getattr(it, "kind", "") == "line"]
    between = items[cuts[0]:cuts[-1]]
    assert not any(isinstance(it, (Dwell, OutputChange)) for it in between)
    # a new power at every cut after the first (no two S in a row are the same) and 0
    # at every G0 between rows
    assert sum(isinstance(it, PowerChange) for it in between) == \
        RASTER_ROWS * RASTER_COLUMNS - 1 + RASTER_ROWS - 1
    # the command stream: OUTPUTs for M4 (first) and M5 (before the last G0), CONT on
    # every motion command in between, and every PROFILE carries its move's power (0 on
    # the G0s)
    d = _decoded(mp)
    ops = [x["opcode"] for x in d]
    assert [k for k, op in enumerate(ops) if op == enc.OP_OUTPUT] == [0, len(ops) - 3]
    motion = [k for k, op in enumerate(ops) if op == enc.OP_LINE]
    assert all(d[k]["cont"] for k in motion[:-2])       # the last G0 follows the M5
    # (M4: S's power times the PROFILE's cruise speed over F where the pixel is too short
    # to reach F, so that the core's duty, power x speed / cruise, is S x speed / F)
    feed = Fraction(30000, 60) / Fraction(LASER.blu[0]) / LASER.clock_hz * (1 << 32)
    want = []
    for c in mp.commands:
        m = c.move
        if m.kind == "rapid":
            want.append(0)
        else:
            row, x = round(m.end[1] / 0.5), round(m.end[0])
            col = x - 1 if row % 2 == 0 else x
            power = round(FULL * _raster_s(row, col) / LASER.spindle_max)
            if c.profile.v_cruise < math.floor(feed):
                power = math.floor(power * c.profile.v_cruise / feed)
            want.append(power)
    assert [c.profile.power for c in mp.commands] == want
    assert all(d[k - 1]["set_power"] == 1 and d[k - 1]["power"] == p
               for k, p in zip(motion, want))
    assert [c.profile.set_power for c in mp.commands] == [1] * len(want)
    # the planner plans through a PowerChange (no stop, no time), as if it were not there
    segs = plan(items, LASER)
    bare = plan([it for it in items if not isinstance(it, PowerChange)], LASER)
    assert [s for s in segs if not isinstance(s, PowerChange)] == bare
    assert estimate_time(segs) == estimate_time(bare)
    # the run makes the same moves at the same cycles as the raster without S words (one
    # power for all), in laser mode and as a spindle program (stops at M4 and M5 only)
    runs = []
    for text, machine in ((_raster(True), LASER), (_raster(False), LASER),
                          (_raster(False), replace(LASER, laser_mode=False))):
        f = tmp_path / "raster.ngc"
        f.write_text(text)
        res = run_program(str(f), machine=machine)
        assert not res.execution.errors
        runs.append(res)
    moves = [r.execution.moves for r in runs]
    assert moves[0] == moves[1] == moves[2]
    assert runs[0].execution.cycles == runs[2].execution.cycles
    assert estimate_time(runs[0].motion.planned) == estimate_time(runs[2].motion.planned)


def _clocked_outputs(items, config) -> list:
    """Run ``items`` on the clock-by-clock core, recording each cycle's (path speed,
    position, the output stage's power register, PWM duty)."""
    from halfpoint.spec.core import CoreInputs, CoreModel
    model = CoreModel(config.axes, config.width, config.depth, config.tw, config.div,
                      config.move_depth, config.profile_depth, config.step_cfg())
    model.clock(CoreInputs(rst=1))
    feeder = Feeder(items)
    rows, cycle = [], 0
    while not feeder.done:
        assert cycle < 200_000
        o = model.outputs()
        rows.append((o.speed, o.pos, model.out_stage.power, o.duty))
        tvalid, tdata, hold = feeder.step(cycle, o)
        model.clock(CoreInputs(tvalid=tvalid, tdata=tdata, hold=hold))
        cycle += 1
    assert not feeder.run.errors
    return rows


def test_the_power_switches_at_the_segment_boundary_with_the_motion_running():
    # M3 (constant power) in laser mode, all along X: a cut at S1000, one at S500, a G0,
    # a cut at S750; the path never stops between them
    text = ("G21 G90 F120000\nM3 S1000\nG1 X1\nG1 X2 S500\nG0 X3\nG1 X4 S750\nM5\nM2\n")
    machine = _sim(laser_mode=True)
    _, mp = _motion(text, machine)
    cfg = core_config(machine)
    rows = _clocked_outputs(mp.items, cfg)
    pwm_bits = 10                   # the core model's default
    full = 1 << pwm_bits
    blu = round(1 / machine.blu[0])
    # the power register over the run, and where it changes
    changes = [(k, rows[k - 1][2], rows[k][2]) for k in range(1, len(rows))
               if rows[k][2] != rows[k - 1][2]]
    # the M3 OUTPUT loads full power at rest; then each take of a new power
    first, *takes = changes
    assert first[1:] == (0, full) and rows[first[0]][0] == 0
    assert [c[1:] for c in takes] == [(full, full // 2), (full // 2, 0), (0, 3 * full // 4)]
    for (k, _, _), x in zip(takes, (1, 2, 3)):
        # at the edge of the segment's last move, into the next one at speed
        assert rows[k][1][0] == x * blu and rows[k - 1][1][0] == x * blu - 1
        assert rows[k - 1][0] > 0 and rows[k][0] > 0
    # no stop anywhere between the first move and the last
    moving = [k for k in range(len(rows)) if 0 < rows[k][1][0] < 4 * blu]
    assert all(rows[k][0] > 0 for k in range(moving[0], moving[-1]))
    # the PWM duty follows at speed: S500's half power during the second cut
    assert any(r[3] == full // 2 and r[0] > 0 and blu < r[1][0] < 2 * blu for r in rows)
    assert run_model(mp.items, cfg).moves == run_clocked(mp.items, cfg).moves


def test_m4_duty_is_s_times_speed_over_the_programmed_feed():
    """M4 (dynamic power) on a stroke too short to reach F, and with F above the axes'
    limit: the core's duty is power x speed / the PROFILE's cruise speed, which is the
    segment's planned peak, not F; so the power is scaled by cruise / F and the duty at
    the peak is S x speed / F, grbl's M4 (until 2026-11-28 it burned at full S at the
    lower peak).  M3 (constant power) and strokes that reach F are not scaled."""
    slow = _sim(laser_mode=True, axes=tuple(replace(a, max_accel_mm_s2=200_000.0,
                                                    max_velocity_mm_s=400.0)
                                            for a in SIM.axes))
    feed_field = Fraction(500) / Fraction(slow.blu[0]) / slow.clock_hz * (1 << 32)
    for mode, scaled in (("M4", True), ("M3", False)):
        # a 0.5 mm stroke at F30000 (500 mm/s): its peak sqrt(a L) = 316 mm/s; then a
        # 20 mm stroke at F30000 above the axes' 400 mm/s
        text = (f"G21 G90\n{mode} S1000\nG0 X0 Y0\nG1 X0.5 F30000\nG0 X5\n"
                "G1 X25 F30000\nM5\nM2\n")
        _, mp = _motion(text, slow)
        cuts = [c for c in mp.commands if c.move.kind == "line"]
        assert len(cuts) == 2
        for c in cuts:
            assert c.profile.v_cruise < 0.85 * feed_field      # neither reaches F
            want = math.floor(FULL * c.profile.v_cruise / feed_field) if scaled else FULL
            assert c.profile.power == want
        if not scaled:
            continue
        # on the clock-by-clock core: at the short stroke's peak speed the duty is
        # S x v / F within the duty's 1/1024 steps (the speed a clock or two before)
        _, short = _motion(f"G21 G90\n{mode} S1000\nG1 X0.5 F30000\nM5\nM2\n", slow)
        rows = _clocked_outputs(short.items, core_config(slow))
        blu = round(1 / slow.blu[0])
        stroke = [r for r in rows if 0 < r[1][0] < blu // 2 and r[0] > 0]
        top = max(r[0] for r in stroke)
        ratio = Fraction(top, 1 << 38) / (feed_field / (1 << 32))
        duty = max(r[3] for r in stroke if r[0] >= top * 0.98)
        assert abs(duty - 1024 * ratio) <= 16, (duty, float(1024 * ratio))
        assert duty < 0.8 * 1024


def _stops(mp) -> list:
    """The X (mm) where the motion comes to rest: the end of every motion command
    without CONT (an OUTPUT, a pause or the end follows) or with exit speed 0."""
    d = _decoded(mp)
    out = []
    for k, x in enumerate(d):
        if x["opcode"] == enc.OP_LINE and (not x["cont"] or d[k - 1]["v_exit"] == 0):
            out.append(k)
    ends = []
    pos = 0
    for k, x in enumerate(d):
        if x["opcode"] == enc.OP_LINE:
            pos += x["deltas"][0]
            if k in out:
                ends.append(round(pos * SIM.blu[0], 6))
    return ends


def test_laser_state_and_coolant_changes_still_stop():
    # laser mode: M7, M3 -> M4 and M5 are OUTPUT commands at rest (as grbl syncs them);
    # the S change on the second line is not
    text = ("G21 G90 F120000\nM3 S1000\nG1 X1\nG1 X2 S500\nM7\nG1 X3\nM4\n"
            "G1 X4 S300\nM5\nG1 X5\nM2\n")
    machine = _sim(laser_mode=True)
    _, items = _items(text, machine)
    half, s300 = FULL // 2, round(0.3 * FULL)
    assert _shape(items) == [
        ("out", (FULL, 1, 0, 1, 0, 0, 0)), ("power", FULL), "line", ("power", half), "line",
        ("out", (half, 1, 0, 1, 0, 1, 0)), "line", ("out", (half, 1, 0, 1, 1, 1, 0)),
        ("power", s300), "line", ("out", (s300, 0, 0, 1, 0, 1, 0)), ("power", 0), "line"]
    _, mp = _motion(text, machine)
    assert _stops(mp) == [2.0, 3.0, 4.0, 5.0]
    assert [c.profile.power for c in mp.commands] == [FULL, half, half, s300, 0]


def test_an_s_change_stops_outside_laser_mode_only():
    text = "G21 G90 F120000\nM3 S1000\nG1 X1\nG1 X2 S500\nG1 X3 S250\nM5\nM2\n"
    # a spindle: each S is an OUTPUT at rest, and no PROFILE sets a power
    _, items = _items(text, SIM)
    assert not any(isinstance(it, PowerChange) for it in items)
    _, mp = _motion(text, SIM)
    assert _stops(mp) == [1.0, 2.0, 3.0]
    assert all(c.profile.set_power == 0 == c.profile.power for c in mp.commands)
    assert all(x["set_power"] == 0 for x in _decoded(mp) if x["opcode"] == enc.OP_PROFILE)
    # the same program in laser mode runs through: a stop only at the end
    _, mp = _motion(text, _sim(laser_mode=True))
    assert _stops(mp) == [3.0]
    assert [c.profile.power for c in mp.commands] == [FULL, FULL // 2, FULL // 4]


def test_output_commands_end_the_motion_before_them_at_rest():
    prog, items = _items(PROGRAM, SIM)
    q = quantise(prog.moves, SIM.blu)
    mp = build_motion(q, items, SIM)
    ops = []
    for it in mp.items:
        assert not isinstance(it, Pause)
        ops.append(enc.decode(it)["opcode"])
    assert ops.count(enc.OP_OUTPUT) == 4
    # the motion command before each OUTPUT: exit speed 0 and no CONT
    for k, it in enumerate(mp.items):
        if ops[k] != enc.OP_OUTPUT:
            continue
        before = [j for j in range(k) if ops[j] in (enc.OP_LINE, enc.OP_ARC_CW, enc.OP_ARC_CCW)]
        if before:
            j = before[-1]
            assert not enc.decode(mp.items[j])["cont"]
            assert enc.decode(mp.items[j - 1])["v_exit"] == 0
        assert decode_for_core(it, 3, 32)[0] == "output"


def test_a_program_with_outputs_runs_on_the_model_clock_exact(tmp_path):
    f = tmp_path / "p.ngc"
    f.write_text(PROGRAM)
    res = run_program(str(f), machine=SIM)
    assert not res.execution.errors and res.lattice[-1][0] == round(5 / SIM.blu[0])
    # the fast model and the clock-by-clock one agree move for move, cycle for cycle
    items = res.motion.items
    cfg = core_config(SIM)
    fast, slow = run_model(items, cfg), run_clocked(items, cfg)
    assert fast.moves == slow.moves and fast.cycles == slow.cycles


def test_a_bad_output_command_is_rejected_and_moves_nothing():
    from halfpoint.spec.core import CoreInputs, CoreModel, run_program as core_run
    model = CoreModel(3, 32, 4, 16, 4, 4, 2, [])
    bad_power = enc.encode_output(FULL + 1, 1)
    bad_bit = enc.encode_output(FULL, 1) | 1 << 60
    run = core_run(model, [bad_power, bad_bit, enc.encode_output(FULL, 1, mist=1)])
    assert run.errors == [enc.E_FIELD, enc.E_OPCODE] and not run.trace
    o = model.outputs()
    assert (o.spindle_enable, o.coolant_mist) == (1, 1)
    model.clock(CoreInputs(abort=1))        # abort_now is registered: it acts a clock later
    assert model.outputs().spindle_enable == 1
    model.clock(CoreInputs())
    o = model.outputs()
    assert (o.spindle_enable, o.coolant_mist, o.spindle_pwm) == (0, 0, 0)


def test_dwell_items_still_pass():
    _, items = _items("G21 G90 F600000\nG1 X1\nG4 P0.5\nM3 S100\nG1 X2\nM2\n", SIM)
    assert [type(it) for it in items] == [type(items[0]), Dwell, OutputChange, type(items[0])]
