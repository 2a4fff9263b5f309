# SPDX-License-Identifier: Apache-2.0
"""Spindle, laser and coolant on the host: the machine file's [spindle] table, S to PWM
power, the OUTPUT commands in program order (issue 14, item 3), and programs with them
through the core model.

The core side (the dispatcher holding an OUTPUT until everything before it has moved,
the output stage's PWM) is tested clock by clock in tb/halfpoint_core and
tb/halfpoint_outputs; here: what the host sends, and that the model runs it with the
motion before each change ending at rest.
"""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import pytest

from halfpoint.cam import machine as mc
from halfpoint.cam.gcode import parse
from halfpoint.cam.motion import Pause, build_motion, core_config, run_clocked, run_model
from halfpoint.cam.planner import Dwell, OutputChange
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


def test_laser_mode_switches_the_laser_off_for_rapids():
    text = "G21 G90 F600000\nM4 S1000\nG0 X1\nG1 X2\nG1 X3\nG0 X4\nG1 Y1\nM5\nM2\n"
    _, items = _items(text, _sim(laser_mode=True))
    seq = [("out", it.settings[:5]) if isinstance(it, OutputChange) else it.kind for it in items]
    on, off = (FULL, 1, 0, 1, 1), (0, 0, 0, 1, 0)
    # M4 then G0: nothing to send before the rapid (the laser is off already); changes
    # with no move between them are one change
    assert seq == ["rapid", ("out", on), "line", "line", ("out", off), "rapid", ("out", on),
                   "line", ("out", (FULL, 0, 0, 1, 0))]


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
