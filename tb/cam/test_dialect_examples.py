# SPDX-License-Identifier: Apache-2.0
"""The issue 14 examples: the CAM-style part (tools, canned cycles, helices, coolant) parses
into the moves and events its blocks ask for, and the parametric program (subroutines and
loops) gives the same path and end position as its hand-expanded equivalent."""

from __future__ import annotations

import dataclasses
from pathlib import Path

import pytest

from halfpoint.cam.comp import compensate
from halfpoint.cam.gcode import Coolant, Dwell, Spindle, ToolChange, load_tool_table, parse
from halfpoint.cam.machine import load_default
from halfpoint.cam.summary import check_travel, summarise

EX = Path(__file__).resolve().parents[2] / "examples"


def cam_style():
    tools = load_tool_table((EX / "tools.tbl").read_text())
    return parse((EX / "cam_style.ngc").read_text(), tools=tools)


def line_of(text: str, n_word: str) -> int:
    """The file line holding block ``n_word`` (e.g. "N95")."""
    return next(k for k, ln in enumerate(text.splitlines(), 1) if ln.startswith(n_word + " "))


def test_cam_style_part_moves_and_events():
    text = (EX / "cam_style.ngc").read_text()
    prog = cam_style()
    assert prog.ended
    # the three helical turns of the bore, then the flat turn, about X30 Y30
    bore = [m for m in prog.moves if m.kind == "arc" and m.center == (30.0, 30.0)]
    assert [m.end for m in bore] == [(37.0, 30.0, z) for z in (-1.0, -2.0, -3.0, -3.0)]
    assert [m.lineno for m in bore] == [line_of(text, f"N{n}") for n in (95, 100, 105, 110)]
    assert all(m.cw and m.feed == 600 for m in bore)
    # the contour runs with G42 and the 6 mm mill's radius, at G64 P0.01
    contour = [m for m in prog.moves if m.comp == "right"]
    assert len(contour) == 9 and {m.radius for m in contour} == {3.0}
    assert {(m.path_mode, m.path_tolerance) for m in contour} == {("G64", 0.01)}
    # the holes: the feed moves of the cycles go to the bottoms, pecks to -8 in 2.5 mm steps
    n245, n265 = line_of(text, "N245"), line_of(text, "N265")
    feeds = [(m.end, m.lineno) for m in prog.moves
             if m.kind == "line" and n245 <= m.lineno <= n265]
    assert [e for e, _ in feeds] == [
        (10, 10, -3), (50, 10, -3), (50, 50, -3),
        (10, 50, -0.5), (10, 50, -3), (10, 50, -5.5), (10, 50, -8),
        (30, 45, -0.5), (30, 45, -3), (30, 45, -5.5), (30, 45, -8)]
    # G91 G28 Z0 goes straight up to the stored position, the machine origin
    homes = [m for m in prog.moves if m.lineno in (line_of(text, "N205"),
                                                   line_of(text, "N285"))]
    assert [m.end[2] for m in homes] == [0.0, 0.0] and all(m.kind == "rapid" for m in homes)
    kinds = [(type(e).__name__, e.lineno) for e in prog.events]
    assert kinds == [
        ("ToolChange", line_of(text, "N25")), ("Spindle", line_of(text, "N30")),
        ("Coolant", line_of(text, "N40")), ("Spindle", line_of(text, "N200")),
        ("Coolant", line_of(text, "N200")), ("ToolChange", line_of(text, "N215")),
        ("Spindle", line_of(text, "N220")), ("Coolant", line_of(text, "N225")),
        ("Dwell", line_of(text, "N255")), ("Coolant", line_of(text, "N275")),
        ("Spindle", line_of(text, "N280"))]
    ev = prog.events
    assert (ev[0], ev[5]) == (ToolChange(tool=1, lineno=ev[0].lineno, before=1),
                              ToolChange(tool=2, lineno=ev[5].lineno, before=ev[5].before))
    assert dataclasses.astuple(ev[1])[2:] == (True, True, 8000.0)
    assert ev[2] == Coolant(mist=False, flood=True, lineno=ev[2].lineno, before=1)
    assert ev[4] == Coolant(mist=False, flood=False, lineno=ev[4].lineno, before=ev[4].before)
    assert isinstance(ev[8], Dwell) and ev[8].seconds == 0.3
    # the dwell of G82 sits between its feed to the bottom and its retract
    assert prog.moves[ev[8].before - 1].end == (50.0, 50.0, -3.0)
    assert isinstance(ev[10], Spindle) and not ev[10].on
    assert prog.moves[-1].end == (0.0, 0.0, 0.0)


def test_cam_style_part_compensates_and_summarises():
    prog = cam_style()
    assert compensate(prog.moves).warnings == []
    machine = load_default()
    check_travel(prog, machine)
    s = summarise(prog, machine)
    text = (EX / "cam_style.ngc").read_text()
    assert s.moves["helix"] == 3
    assert s.tool_changes == [(1, line_of(text, "N25")), (2, line_of(text, "N215"))]
    assert s.box == ((-10.0, 65.0), (-10.0, 60.0), (-8.0, 15.0))
    assert s.seconds > 0


PARAMETRIC = EX / "parametric.ngc"
EXPANDED = EX / "parametric_expanded.ngc"


def key(m):
    return (m.kind, m.start, m.end, m.center, m.cw, m.feed, m.plane, m.path_mode)


def test_parametric_program_equals_its_hand_expansion():
    """The issue's criterion: a LinuxCNC nc_files-style program with subroutines and
    expressions gives the same end position and the same path as its hand expansion."""
    prog = parse(PARAMETRIC.read_text())
    hand = parse(EXPANDED.read_text())
    assert len(prog.moves) == len(hand.moves) == 26
    assert [key(m) for m in prog.moves] == [key(m) for m in hand.moves]
    assert prog.moves[-1].end == hand.moves[-1].end == (0.0, 0.0, 3.0)
    assert prog.ended and hand.ended and prog.notes == hand.notes == []
    assert [(m.kind, m.text) for m in prog.messages] == [("DEBUG", "grid done: 2 rows")]
    # two slots and two circles: the features alternate with row + column
    arcs = [m.center for m in prog.moves if m.kind == "arc"]
    assert arcs == [(50.0, 10.0), (20.0, 30.0)]


@pytest.mark.parametrize("name", ["cam_style.ngc", "parametric.ngc", "parametric_expanded.ngc"])
def test_examples_keep_the_line_limit_and_a_header(name):
    lines = (EX / name).read_text().splitlines()
    head = [ln for ln in lines[:3] if ln != "%"]
    assert head[0] == "(SPDX-License-Identifier: Apache-2.0)"
    assert head[1].startswith("(halfpoint example")
    assert max(len(ln) for ln in lines) <= 100
