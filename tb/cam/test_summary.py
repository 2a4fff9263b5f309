# SPDX-License-Identifier: Apache-2.0
"""What a program does before it runs (issue 14, item 4): the summary's counts, bounding box
(arcs by their exact extent) and planned run time, and the travel check naming the first
block that leaves the machine's travel."""

from __future__ import annotations

import copy
import math

import pytest

from halfpoint.cam.gcode import GcodeError, parse
from halfpoint.cam.machine import from_dict
from halfpoint.cam.planner import Dwell, estimate_time, plan
from halfpoint.cam.summary import check_travel, move_box, summarise


def machine(accel=1000.0, **travel):
    axis = {"blu_mm": 0.001, "max_velocity_mm_s": 100.0, "max_accel_mm_s2": accel}
    d = {"clock_hz": 50_000_000, "axis": {k: dict(axis) for k in "xyz"},
         "planner": {"junction_deviation_mm": 0.01}}
    for key, value in travel.items():            # x_max=20 -> axis.x.travel_max_mm = 20
        d["axis"][key[0]][f"travel_{key[2:]}_mm"] = value
    return from_dict(copy.deepcopy(d))


PART = """G21 G90 F600
T3 M6
S8000 M3 M8
G0 X20 Y0 Z2
G1 Z-1
G2 X30 Y0 I5 J0
G2 X30 Y0 Z-2 I-5 J0
G4 P1.5
M0
G0 Z5
M5 M9
M30
"""


def test_summary_counts_box_and_time():
    prog = parse(PART)
    s = summarise(prog, machine())
    assert s.blocks == 12
    assert s.moves == {"rapid": 2, "line": 1, "arc": 1, "helix": 1}
    assert s.tool_changes == [(3, 2)] and s.pauses == [("M0", 9)]
    assert (s.dwells, s.dwell_seconds) == (1, 1.5)
    # the first arc bulges up to Y 5 (CW from 180 to 0 degrees), the full helix turn
    # about (25, 0) reaches X 20..30 and Y -5..5
    assert s.box == ((0.0, 30.0), (-5.0, 5.0), (-2.0, 5.0))
    text = str(s)
    for words in ("blocks: 12, moves: 5", "tool changes: T3 (line 2)", "pauses: M0 (line 9)",
                  "dwells: 1, 1.5 s", "X: 0.000 .. 30.000 mm", "Y: -5.000 .. 5.000 mm",
                  "Z: -2.000 .. 5.000 mm", "estimated run time"):
        assert words in text, text


def test_time_is_the_planners_with_the_dwells():
    m = machine()
    plain = parse("F600\nG1 X10\nG1 Y10\nM2")
    dwell = parse("F600\nG1 X10\nG1 Y10\nG4 P2\nM2")
    expected = estimate_time(plan(plain.moves, m))
    assert summarise(plain, m).seconds == pytest.approx(expected, rel=1e-12)
    assert summarise(dwell, m).seconds == pytest.approx(expected + 2.0, rel=1e-12)
    # a dwell between the moves stops the path there, as plan() does with a Dwell
    mid = parse("F600\nG1 X10\nG4 P0.5\nG1 Y10\nM2")
    items = [mid.moves[0], Dwell(0.5, 3), mid.moves[1]]
    assert summarise(mid, m).seconds == pytest.approx(estimate_time(plan(items, m)))


def test_helix_time_follows_the_helix_length():
    # 1 mm/s along a 5 mm radius full turn falling 1 mm, at an acceleration that makes
    # the ramps negligible: the time is the helix length in seconds
    prog = parse("F60\nG1 X5\nG3 X5 Y0 Z-1 I-5 J0\nM2")
    s = summarise(prog, machine(accel=50_000.0))
    assert s.seconds == pytest.approx(5.0 + math.hypot(10 * math.pi, 1.0), rel=1e-3)


def test_move_box_of_arcs_in_every_plane():
    prog = parse("F10\nG18 G2 X10 Z0 I5 K0\nG19 G3 Y0 Z4 J0 K2\nM2")
    xz, yz = prog.moves
    # G18 (plane axes Z, X) CW from angle -90 to 90 degrees the short way down: Z to -5
    lo, hi = move_box(xz)
    assert (lo, hi) == ([0, 0, -5], [10, 0, 0])
    # G19 (Y, Z) CCW from -90 to 90 degrees about (y 0, z 2): through Y 2
    lo, hi = move_box(yz)
    assert (lo, hi) == ([10, 0, 0], [10, 2, 4])


def test_travel_check_names_the_first_block_that_leaves():
    prog = parse("F100\nG0 X20 Y0\nG2 X20 Y-10 I0 J-5\nG0 Z-50\nM2")
    check_travel(prog, machine())                           # unlimited
    check_travel(prog, machine(x_max=25, z_min=-50))        # exactly at the limits
    # the arc's end points stay within X 20, but it bulges out to X 25
    with pytest.raises(GcodeError) as e:
        check_travel(prog, machine(x_max=24))
    assert e.value.lineno == 3
    assert "X reaches 25.0000 mm, above axis.x.travel_max_mm 24 mm" in e.value.reason
    with pytest.raises(GcodeError) as e:
        check_travel(prog, machine(z_min=-40))
    assert e.value.lineno == 4 and "below axis.z.travel_min_mm -40 mm" in e.value.reason
    with pytest.raises(GcodeError) as e:
        check_travel(prog, machine(y_min=-9.5, x_max=10))
    assert e.value.lineno == 2 and "axis.x.travel_max_mm 10" in e.value.reason
