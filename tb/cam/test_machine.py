# SPDX-License-Identifier: Apache-2.0
"""The machine file: the shipped example, ns -> clock ticks (checked on the step
generator's model pins), the ranges the issue names, and an error naming the key
for every kind of bad file."""

from __future__ import annotations

import copy
import dataclasses
from pathlib import Path

import pytest

from halfpoint.cam.gcode import parse
from halfpoint.cam.machine import (TIMING_DEFAULTS_NS, MachineError, check_program, from_dict,
                                   load, loads, ns_to_ticks)
from halfpoint.spec.stepgen import StepCfg, StepGenModel, StepInputs

EXAMPLE = Path(__file__).resolve().parents[2] / "examples" / "machine.toml"


def base() -> dict:
    axis = {"blu_mm": 0.001, "max_velocity_mm_s": 100.0, "max_accel_mm_s2": 1000.0}
    return {"clock_hz": 50_000_000,
            "axis": {"x": dict(axis), "y": dict(axis), "z": dict(axis)},
            "planner": {"junction_deviation_mm": 0.01}}


def test_example_machine_file_loads_with_its_documented_values():
    m = load(EXAMPLE)
    assert m.clock_hz == 50_000_000
    assert m.blu == (0.001, 0.001, 0.001)
    assert m.max_velocity == (100.0, 100.0, 50.0)
    assert m.max_accel == (1000.0, 1000.0, 500.0)
    assert m.junction_deviation_mm == 0.01
    for a in m.axes:
        # 2 us at 50 MHz = 100 ticks, 5 us = 250 ticks
        assert (a.timing.steplen, a.timing.stepspace, a.timing.dirsetup,
                a.timing.dirhold) == (100, 100, 250, 250)
        assert a.max_step_rate(m.clock_hz) == 250_000
    # every key of the example is commented: no key line without a comment above it
    lines = EXAMPLE.read_text().splitlines()
    for k, line in enumerate(lines):
        if "=" in line and not line.lstrip().startswith("#"):
            commented = "#" in line or lines[k - 1].lstrip().startswith("#")
            assert commented, f"example line {k + 1} has no comment"


def test_defaults_apply_when_timing_keys_are_absent():
    m = from_dict(base())
    ns = m.axis("y").timing_ns
    assert ns == TIMING_DEFAULTS_NS
    assert m.axis("y").timing.steplen == 100 and m.axis("y").timing.dirhold == 250


@pytest.mark.parametrize("ns, clock, minimum, ticks", [
    (2000, 50_000_000, 1, 100),      # exact
    (2001, 50_000_000, 1, 101),      # rounded up, never down
    (1999, 50_000_000, 1, 100),
    (20, 50_000_000, 1, 1),          # one clock period exactly
    (21, 50_000_000, 1, 2),
    (0, 50_000_000, 1, 1),           # STEP length and space are at least one tick
    (0, 50_000_000, 0, 0),           # DIR setup and hold may be zero
    (100, 30_000_000, 0, 3),         # 100 ns * 30 MHz = 3 exactly (3.0000000000000004 in floats)
    (2.5, 200_000_000, 0, 1),        # 0.5 tick -> 1
    (1, 10_000_000, 0, 1),
    (5000, 200_000_000, 0, 1000),
])
def test_ns_to_ticks_rounds_up_exactly(ns, clock, minimum, ticks):
    assert ns_to_ticks(ns, clock, minimum) == ticks


def _pin_times(cfg: StepCfg, dirs) -> dict:
    """Drive the step generator's model with requests in directions ``dirs`` as soon as it
    is ready and measure, from the pins only, the shortest STEP high and low times, the
    shortest DIR hold after STEP fell and DIR setup before STEP rose (in clocks)."""
    g = StepGenModel(16)
    step_prev, dir_prev = None, None
    rise = fall = dir_change = None
    got = {"high": [], "low": [], "hold": [], "setup": []}
    queue = list(dirs)
    for cycle in range(20000):
        o = g.outputs(cfg)
        if step_prev is not None:
            if o.step_pin and not step_prev:
                if fall is not None:
                    got["low"].append(cycle - fall)
                if dir_change is not None and (fall is None or dir_change > fall):
                    got["setup"].append(cycle - dir_change)
                rise = cycle
            if not o.step_pin and step_prev:
                got["high"].append(cycle - rise)
                fall = cycle
            if o.dir_pin != dir_prev:
                if fall is not None:
                    got["hold"].append(cycle - fall)
                dir_change = cycle
        step_prev, dir_prev = o.step_pin, o.dir_pin
        req = 0
        if queue:
            d = queue[0]
            if (o.ready_pos if d else o.ready_neg):
                req = 1
                queue.pop(0)
        g.clock(cfg, StepInputs(req=req, req_dir=d if req else 0))
        if not queue and not o.busy and cycle > 10 and not req:
            break
    return {k: min(v) for k, v in got.items() if v}


@pytest.mark.parametrize("clock, ns", [
    (50_000_000, {"steplen_ns": 2000, "stepspace_ns": 2000, "dirsetup_ns": 5000,
                  "dirhold_ns": 5000}),
    (10_000_000, {"steplen_ns": 150, "stepspace_ns": 50, "dirsetup_ns": 310,
                  "dirhold_ns": 1}),
    (200_000_000, {"steplen_ns": 1000, "stepspace_ns": 4000, "dirsetup_ns": 0,
                   "dirhold_ns": 20000}),
    (33_333_333, {"steplen_ns": 33, "stepspace_ns": 95, "dirsetup_ns": 61,
                  "dirhold_ns": 31}),
])
def test_ticks_give_at_least_the_asked_times_on_the_step_generator_pins(clock, ns):
    d = base()
    d["clock_hz"] = clock
    d["axis"]["x"].update(ns)
    d["axis"]["x"]["max_velocity_mm_s"] = 1.0
    t = from_dict(d).axis("x").timing
    cfg = StepCfg(steplen=t.steplen, stepspace=t.stepspace, dirsetup=t.dirsetup,
                  dirhold=t.dirhold)
    got = _pin_times(cfg, [1, 1, 0, 0, 1, 0, 1, 1])
    period_ns = 1e9 / clock
    assert got["high"] == t.steplen                      # STEP is active exactly steplen ticks
    assert got["high"] * period_ns >= ns["steplen_ns"]
    assert got["low"] * period_ns >= ns["stepspace_ns"]
    assert got["hold"] * period_ns >= ns["dirhold_ns"]
    assert got.get("setup", 0) * period_ns >= ns["dirsetup_ns"]
    # and not wastefully more than one tick above what was asked (except the 1-tick minimum)
    assert (got["high"] - 1) * period_ns < max(ns["steplen_ns"], period_ns)


@pytest.mark.parametrize("clock, blu, vel, acc, timing", [
    (10_000_000, 0.0001, 0.1, 10.0, {}),
    (10_000_000, 0.01, 500.0, 50_000.0, {}),
    (200_000_000, 0.0001, 500.0, 50_000.0, {"steplen_ns": 5, "stepspace_ns": 5}),
    (200_000_000, 0.01, 0.1, 10.0, {}),
    (10_000_000, 0.0001, 499.0, 10.0, {"steplen_ns": 0, "stepspace_ns": 0}),   # 4.99 MHz of 5
])
def test_the_ranges_the_issue_names_are_accepted(clock, blu, vel, acc, timing):
    d = base()
    d["clock_hz"] = clock
    for name in "xyz":
        d["axis"][name].update(blu_mm=blu, max_velocity_mm_s=vel, max_accel_mm_s2=acc, **timing)
    m = loads(_toml(d))
    assert m.clock_hz == clock and m.blu == (blu,) * 3 and m.max_velocity == (vel,) * 3


def _toml(d: dict) -> str:
    out = [f"clock_hz = {d['clock_hz']!r}"]
    for name, t in d["axis"].items():
        out.append(f"[axis.{name}]")
        out += [f"{k} = {v!r}" for k, v in t.items()]
    out.append("[planner]")
    out += [f"{k} = {v!r}" for k, v in d["planner"].items()]
    return "\n".join(out) + "\n"


def _set(d, path, value):
    keys = path.split(".")
    for k in keys[:-1]:
        d = d[k]
    d[keys[-1]] = value


def _del(d, path):
    keys = path.split(".")
    for k in keys[:-1]:
        d = d[k]
    del d[keys[-1]]


BAD = [
    # (change, key named, words of the reason)
    (lambda d: _set(d, "spindel", 1), "spindel", "unknown key"),
    (lambda d: _set(d, "axis.a", {}), "axis.a", "unknown key"),
    (lambda d: _set(d, "axis.x.max_jerk", 1.0), "axis.x.max_jerk", "unknown key"),
    (lambda d: _set(d, "planner.lookahead", 8), "planner.lookahead", "unknown key"),
    (lambda d: _del(d, "clock_hz"), "clock_hz", "missing"),
    (lambda d: _del(d, "axis.y"), "axis.y", "missing"),
    (lambda d: _del(d, "axis.z.blu_mm"), "axis.z.blu_mm", "missing"),
    (lambda d: _del(d, "axis.x.max_velocity_mm_s"), "axis.x.max_velocity_mm_s", "missing"),
    (lambda d: _del(d, "axis.y.max_accel_mm_s2"), "axis.y.max_accel_mm_s2", "missing"),
    (lambda d: _del(d, "planner"), "planner", "missing"),
    (lambda d: _del(d, "planner.junction_deviation_mm"), "planner.junction_deviation_mm",
     "missing"),
    (lambda d: _set(d, "clock_hz", "50MHz"), "clock_hz", "must be a number"),
    (lambda d: _set(d, "clock_hz", 5e7 + 0.5), "clock_hz", "whole number"),
    (lambda d: _set(d, "clock_hz", 0), "clock_hz", "must be > 0"),
    (lambda d: _set(d, "axis.x.blu_mm", True), "axis.x.blu_mm", "must be a number"),
    (lambda d: _set(d, "axis.x", 5), "axis.x", "must be a table"),
    (lambda d: _set(d, "axis.x.blu_mm", 0.0), "axis.x.blu_mm", "must be > 0"),
    (lambda d: _set(d, "axis.y.blu_mm", -0.001), "axis.y.blu_mm", "must be > 0"),
    (lambda d: _set(d, "axis.z.max_velocity_mm_s", 0), "axis.z.max_velocity_mm_s", "must be > 0"),
    (lambda d: _set(d, "axis.x.max_accel_mm_s2", 0.0), "axis.x.max_accel_mm_s2", "must be > 0"),
    (lambda d: _set(d, "axis.x.max_accel_mm_s2", -5.0), "axis.x.max_accel_mm_s2", "must be > 0"),
    (lambda d: _set(d, "axis.x.max_accel_mm_s2", float("inf")), "axis.x.max_accel_mm_s2",
     "finite"),
    (lambda d: _set(d, "axis.y.steplen_ns", -1), "axis.y.steplen_ns", "must be >= 0"),
    (lambda d: _set(d, "axis.y.dirhold_ns", "5us"), "axis.y.dirhold_ns", "must be a number"),
    (lambda d: _set(d, "axis.z.dirsetup_ns", 2_000_000), "axis.z.dirsetup_ns", "16-bit"),
    (lambda d: _set(d, "planner.junction_deviation_mm", -0.01), "planner.junction_deviation_mm",
     "must be >= 0"),
    # 100 mm/s at 0.1 um is 1e6 steps/s; 2 us + 2 us allows 250,000
    (lambda d: _set(d, "axis.y.blu_mm", 0.0001), "axis.y.max_velocity_mm_s", "STEP timing"),
    (lambda d: _set(d, "axis.x.stepspace_ns", 20_000), "axis.x.max_velocity_mm_s",
     "STEP timing"),
]


@pytest.mark.parametrize("change, key, reason", BAD, ids=[b[1] + ":" + b[2] for b in BAD])
def test_bad_machine_files_name_the_key(change, key, reason):
    d = copy.deepcopy(base())
    change(d)
    with pytest.raises(MachineError) as e:
        from_dict(d, "mill.toml")
    assert e.value.key == key
    assert str(e.value).startswith(f"mill.toml: {key}: ")
    assert reason in e.value.reason


def test_step_rate_error_says_what_the_timing_allows():
    d = base()
    d["axis"]["x"]["max_velocity_mm_s"] = 250.001       # 250,001 steps/s > 250,000
    with pytest.raises(MachineError, match=r"axis\.x\.max_velocity_mm_s: 250\.001 mm/s at "
                                           r"blu_mm 0\.001 needs 250001 steps/s.*at most 250000"):
        from_dict(d)
    d["axis"]["x"]["max_velocity_mm_s"] = 250.0          # exactly the STEP rate: accepted
    assert from_dict(d).axis("x").max_velocity_mm_s == 250.0


def test_toml_errors_and_unreadable_files_are_machine_errors(tmp_path):
    with pytest.raises(MachineError, match="not valid TOML"):
        loads("clock_hz = = 5\n", "bad.toml")
    with pytest.raises(MachineError, match="axis.x.blu_mm: missing required value"):
        loads(_toml(base()).replace("blu_mm = 0.001\n", "", 1))
    with pytest.raises(MachineError, match="cannot read"):
        load(tmp_path / "nowhere.toml")
    p = tmp_path / "m.toml"
    p.write_text(_toml(base()))
    assert load(p).source == str(p)


def test_x_and_y_blu_must_match_only_when_the_program_has_arcs():
    d = base()
    d["axis"]["y"]["blu_mm"] = 0.002
    m = from_dict(d, "m.toml")
    lines = parse("G21 F100\nG1 X1 Y1\nG1 X2\nM2").moves
    check_program(m, lines)                                   # no arc: fine
    arcs = parse("G21 F100\nG1 X1\nG1 X2\nG3 X3 Y1 I0 J1\nM2").moves
    with pytest.raises(MachineError, match=r"m\.toml: axis\.y\.blu_mm: 0\.002 differs from "
                                           r"axis\.x\.blu_mm 0\.001.*first on line 4"):
        check_program(m, arcs)
    check_program(from_dict(base()), arcs)                    # same BLU: fine


def test_the_shipped_default_is_the_example_machine():
    """load_default reads the file inside the package; it is examples/machine.toml."""
    from halfpoint.cam.machine import load, load_default

    ex = Path(__file__).resolve().parents[2] / "examples" / "machine.toml"
    assert load_default() == dataclasses.replace(load(ex), source=load_default().source)


# ------------------------------------------------------------------ issue 14: travel, positions

def test_travel_limits_and_stored_positions_are_optional():
    m = from_dict(base())
    assert all(a.travel_min_mm == -float("inf") and a.travel_max_mm == float("inf")
               for a in m.axes)
    assert m.g28 == (0.0, 0.0, 0.0) and m.g30 == (0.0, 0.0, 0.0)
    d = base()
    d["axis"]["x"].update(travel_min_mm=-10, travel_max_mm=300.5)
    d["axis"]["z"]["travel_max_mm"] = 0
    d["positions"] = {"g28": [1, 2, 3], "g30": [0, 0, -5.5]}
    m = from_dict(d)
    assert (m.axis("x").travel_min_mm, m.axis("x").travel_max_mm) == (-10.0, 300.5)
    assert (m.axis("z").travel_min_mm, m.axis("z").travel_max_mm) == (-float("inf"), 0.0)
    assert m.g28 == (1.0, 2.0, 3.0) and m.g30 == (0.0, 0.0, -5.5)
    # the parser takes the positions from the machine
    assert parse("G28\nG30\nM2", positions=m).moves[1].end == (0.0, 0.0, -5.5)
    assert load(EXAMPLE).g28 == (0.0, 0.0, 0.0)


BAD_14 = [
    (lambda d: _set(d, "axis.x.travel_min_mm", "low"), "axis.x.travel_min_mm",
     "must be a number"),
    (lambda d: _set(d, "axis.y.travel_max_mm", float("nan")), "axis.y.travel_max_mm",
     "finite"),
    (lambda d: (_set(d, "axis.z.travel_min_mm", 5), _set(d, "axis.z.travel_max_mm", 5)),
     "axis.z.travel_max_mm", "must be above travel_min_mm"),
    (lambda d: _set(d, "positions", 3), "positions", "must be a table"),
    (lambda d: _set(d, "positions", {"g29": [0, 0, 0]}), "positions.g29", "unknown key"),
    (lambda d: _set(d, "positions", {"g28": [0, 0]}), "positions.g28",
     "array of three numbers"),
    (lambda d: _set(d, "positions", {"g30": [0, "a", 0]}), "positions.g30",
     "must be a number"),
]


@pytest.mark.parametrize("change, key, reason", BAD_14, ids=[b[1] + ":" + b[2] for b in BAD_14])
def test_bad_travel_and_position_keys_name_the_key(change, key, reason):
    d = copy.deepcopy(base())
    change(d)
    with pytest.raises(MachineError) as e:
        from_dict(d, "mill.toml")
    assert e.value.key == key and reason in e.value.reason, str(e.value)
