# SPDX-License-Identifier: Apache-2.0
"""The G-code dialect of issue 14, item 1, construct by construct: each test a program and
its expected moves and events (LinuxCNC's documented semantics and its interp_cycles.cc),
and every refusal with the line it names."""

from __future__ import annotations

import math

import pytest

from halfpoint.cam.gcode import (Coolant, Dwell, GcodeError, MachineState, Pause, Spindle,
                                 ToolChange, arc_length, load_tool_table, parse)


def pts(prog):
    """(kind, end rounded to 1e-9) of every move."""
    return [(m.kind, tuple(round(v, 9) + 0.0 for v in m.end)) for m in prog.moves]


def error(text, **kw):
    with pytest.raises(GcodeError) as exc:
        parse(text, **kw)
    return exc.value


# ------------------------------------------------------------------ motion, planes, feed

def test_modal_motion_continues_g0_g1_g2_g3():
    prog = parse("F100\nG0 X1\nY2\nG1 X3\nZ-1\nG2 X5 Y2 I1 J0\nX3 Y2 I-1 J0\nM2")
    assert pts(prog) == [("rapid", (1, 0, 0)), ("rapid", (1, 2, 0)), ("line", (3, 2, 0)),
                         ("line", (3, 2, -1)), ("arc", (5, 2, -1)), ("arc", (3, 2, -1))]
    assert [m.cw for m in prog.moves[4:]] == [True, True]
    assert prog.moves[5].center == (4.0, 2.0)


def test_arcs_in_g18_and_g19_use_their_planes_words():
    prog = parse("F100\nG18 G2 X10 Z0 I5 K0\nG19 G3 Y10 Z0 J5 K0\nM2")
    xz, yz = prog.moves
    assert (xz.plane, xz.center, xz.end) == (18, (0.0, 5.0), (10.0, 0.0, 0.0))
    assert (yz.plane, yz.center, yz.end) == (19, (5.0, 0.0), (10.0, 10.0, 0.0))
    with pytest.raises(GcodeError, match="offset J does not belong to plane G18"):
        parse("F100\nG18 G2 X10 I5 J1\nM2")


def test_a_zero_word_of_the_third_axis_is_accepted_as_freecad_writes_it():
    prog = parse("F100\nG2 X10 Y0 I5 J0 K0\nM2")
    assert prog.moves[0].center == (5.0, 0.0)
    e = error("F100\nG2 X10 Y0 I5 J0 K0.5\nM2")
    assert e.lineno == 2 and "offset K does not belong to plane G17" in e.reason


def test_helical_arc_moves_the_normal_axis_with_the_arc():
    prog = parse("F100\nG17 G2 X10 Y0 Z-2 I5 J0\nG18 G3 X0 Y3 I-5 K0\nM2")
    helix, side = prog.moves
    assert helix.start == (0.0, 0.0, 0.0) and helix.end == (10.0, 0.0, -2.0)
    assert helix.center == (5.0, 0.0) and helix.cw
    assert arc_length(helix) == pytest.approx(math.hypot(5 * math.pi, 2.0))
    assert side.plane == 18 and side.end == (0.0, 3.0, -2.0)     # Y is G18's linear axis
    assert side.center == (-2.0, 5.0)                            # (Z, X) in G18


def test_helical_full_turn_and_radius_form():
    prog = parse("F60\nG1 X5\nG3 X5 Y0 Z-1 I-5 J0\nG2 X-5 Y0 Z-2 R5\nM2")
    turn, half = prog.moves[1:]
    assert turn.start[:2] == turn.end[:2] and turn.end[2] == -1
    assert arc_length(turn) == pytest.approx(math.hypot(10 * math.pi, 1.0))
    assert half.center == pytest.approx((0.0, 0.0), abs=1e-12) and half.end[2] == -2


def test_inverse_time_feed_converts_to_mm_per_min_from_the_length():
    prog = parse("G93\nG1 X30 F2\nG2 X40 Y0 Z-1 I5 J0 F1\nG94 F500\nG1 X0\nM2")
    line, arc, back = prog.moves
    assert line.feed == pytest.approx(60.0)                  # 30 mm in 1/2 min
    assert arc.feed == pytest.approx(math.hypot(5 * math.pi, 1.0))   # one minute
    assert back.feed == 500.0
    assert error("G93\nG1 X30 F2\nX40\nM2").reason.startswith("G93 (inverse time) needs F")
    # an inverse-time F is no feed rate after G94
    assert "no feed rate set" in error("G93 G1 X1 F2\nG94 X2\nM2").reason
    # G0 needs no F in G93
    assert pts(parse("G93\nG0 X4\nM2")) == [("rapid", (4, 0, 0))]


def test_units_and_arc_p_word():
    prog = parse("G20 F10\nG1 X1\nM2")
    assert prog.moves[0].end == (25.4, 0.0, 0.0) and prog.moves[0].feed == 254.0
    e = error("F10\nG2 X0 Y0 I1 P1.5\nM2")
    assert e.lineno == 2 and "arc turns P must be a whole number >= 1" in e.reason


def test_arc_p_turns_add_full_circles_before_the_arc():
    prog = parse("F100\nG1 X5\nG3 X5 Y0 Z-3 I-5 J0 P3\nG2 X0 Y-5 Z-8 I-5 J0 P2\nM2")
    turns = prog.moves[1:]
    assert [m.start for m in turns[:3]] == [(5, 0, 0), (5, 0, -1), (5, 0, -2)]
    assert [m.end for m in turns[:3]] == [(5, 0, -1), (5, 0, -2), (5, 0, -3)]
    # a full circle then the quarter: Z falls 5 mm over 2.25 turns, in proportion
    circle, quarter = turns[3:]
    assert circle.start == (5, 0, -3) and circle.end[:2] == (5, 0) and circle.cw
    assert circle.end[2] == pytest.approx(-3 - 5 * 1 / 1.25)
    assert quarter.start == circle.end and quarter.end == (0, -5, -8)
    assert {m.center for m in turns} == {(0.0, 0.0)} and {m.lineno for m in turns[3:]} == {4}
    g93 = parse("G93\nG1 X5 F1\nG3 X5 Y0 I-5 J0 P2 F1\nM2").moves[1:]
    assert [m.feed for m in g93] == pytest.approx([20 * math.pi] * 2)     # both in 1 min
    e = error("F10\nG41.1 D1 G1 X5\nG3 X5 Y0 I-5 J0 P2\nM2")
    assert e.lineno == 3 and "multi-turn arcs with cutter compensation" in e.reason


# ------------------------------------------------------------------ coordinates

def test_work_offsets_g10_l2_and_g54_to_g59_3():
    prog = parse("G10 L2 P2 X10 Y20\nG10 L2 P9 Z-5\nG55\nG0 X1 Y1\nG59.3 G0 Z1\nG54\n"
                 "G0 X1 Y1 Z0\nM2")
    assert pts(prog) == [("rapid", (11, 21, 0)), ("rapid", (11, 21, -4)),
                         ("rapid", (1, 1, 0))]


def test_g10_l2_p0_is_the_current_system_and_ignores_g91():
    prog = parse("G56\nG91\nG10 L2 P0 X5\nG90 G0 X0\nM2")
    assert pts(prog) == [("rapid", (5, 0, 0))]


def test_g10_l20_makes_the_current_position_the_given_value():
    prog = parse("G0 X5 Y5\nG10 L20 P1 X0 Y0\nG0 X1\nG10 L20 P0 X10\nG0 X10\nM2")
    # after L20 the G54 X offset is 5, then 6 - 10 = -4
    assert pts(prog) == [("rapid", (5, 5, 0)), ("rapid", (6, 5, 0)), ("rapid", (6, 5, 0))]


@pytest.mark.parametrize("text, reason", [
    ("G10 L2 P10 X1\nM2", "P must be 0-9"),
    ("G10 L1 P1 Z1\nM2", "G10 L1 (tool table) is not supported"),
    ("G10 L2 P1 R30\nM2", "rotated coordinate systems"),
    ("G10 L2 X1\nM2", "G10 L2 needs P"),
    ("G10 P1 X1\nM2", "G10 needs L"),
])
def test_g10_errors(text, reason):
    e = error(text)
    assert e.lineno == 1 and reason in e.reason, e.reason


def test_g92_family():
    prog = parse("G0 X10\nG92 X0\nG0 X5\nG92.1\nG0 X5\nM2")
    assert pts(prog) == [("rapid", (10, 0, 0)), ("rapid", (15, 0, 0)), ("rapid", (5, 0, 0))]
    prog = parse("G0 X10\nG92 X0\nG92.2\nG0 X1\nG92.3\nG0 X1\nM2")
    assert pts(prog) == [("rapid", (10, 0, 0)), ("rapid", (1, 0, 0)), ("rapid", (11, 0, 0))]
    # G92 stacks on the work offset
    prog = parse("G10 L2 P1 X100\nG0 X0\nG92 X10\nG0 X10\nM2")
    assert pts(prog) == [("rapid", (100, 0, 0)), ("rapid", (100, 0, 0))]
    assert "G92 needs at least one axis word" in error("G92\nM2").reason


def test_g53_moves_in_machine_coordinates_for_one_block():
    prog = parse("G10 L2 P1 X100\nG0 X1\nG53 G0 X1\nG0 X2\nG91 G53 X3\nM2")
    assert pts(prog) == [("rapid", (101, 0, 0)), ("rapid", (1, 0, 0)), ("rapid", (102, 0, 0)),
                         ("rapid", (3, 0, 0))]          # G53 is absolute in G91 too
    assert "G53 needs G0 or G1" in error("F10\nG2 X2 I1\nG53 X0\nM2").reason


def test_g28_g30_and_their_stored_positions():
    home = {"g28": (10, 20, 30), "g30": (-1, -2, -3)}
    prog = parse("G0 X1 Y1 Z1\nG28\nG30\nM2", positions=home)
    assert pts(prog)[1:] == [("rapid", (10, 20, 30)), ("rapid", (-1, -2, -3))]
    # through an intermediate point, only the named axes go home
    prog = parse("G0 X1 Y1 Z1\nG28 Z5\nG91 G28 X0\nM2", positions=home)
    assert pts(prog)[1:] == [("rapid", (1, 1, 5)), ("rapid", (1, 1, 30)),
                             ("rapid", (10, 1, 30))]
    # G28.1 / G30.1 store the current machine position
    prog = parse("G0 X5 Y6 Z7\nG28.1\nG0 X0 Y0 Z0\nG28\nG30.1\nG0 X1\nG30\nM2")
    assert pts(prog)[-3:] == [("rapid", (5, 6, 7)), ("rapid", (1, 6, 7)), ("rapid", (5, 6, 7))]
    # default: the machine origin
    assert pts(parse("G0 X5\nG28\nM2"))[-1] == ("rapid", (0, 0, 0))
    assert parse("G28\nM2", positions=MachineState(g28=(1, 2, 3))).moves[0].end == (1, 2, 3)
    e = error("F10\nG41.1 D2 G1 X5\nG28\nM2")
    assert e.lineno == 3 and "G28 with cutter compensation on" in e.reason
    assert "takes no axis words" in error("G28.1 X1\nM2").reason
    assert "both use the axis words" in error("G28 G0 X1\nM2").reason


# ------------------------------------------------------------------ tools

TOOLS = "T1 P1 Z25 D6 ; 6 mm mill\nT2 P2 Z-10 D3\n; units: mm\n"


def test_tool_change_event_and_length_offsets():
    tools = load_tool_table(TOOLS)
    assert tools.offsets == {1: (0.0, 25.0), 2: (0.0, -10.0)}
    prog = parse("T1 M6\nG43\nG0 Z0\nT2 M6 G43 H2\nG0 Z0\nG43.1 Z-3\nG0 Z0\nG49\nG0 Z0\n"
                 "G43 H0\nM2", tools=tools)
    assert pts(prog) == [("rapid", (0, 0, 25)), ("rapid", (0, 0, -10)), ("rapid", (0, 0, -3)),
                         ("rapid", (0, 0, 0))]
    assert prog.events == [ToolChange(tool=1, lineno=1, before=0),
                           ToolChange(tool=2, lineno=4, before=1)]
    # the offset changes the program coordinate, not the machine position
    prog = parse("G43.1 Z10\nG0 X1\nM2")
    assert pts(prog) == [("rapid", (1, 0, 0))]
    assert "G43 without H needs a tool" in error("G43\nM2").reason
    assert "tool 7 is not in the tool table" in error("G43 H7\nM2", tools=tools).reason
    assert "G43.1 needs the offsets" in error("G43.1\nM2").reason
    assert "M6 without a tool" in error("M6\nM2").reason


def test_cutter_radius_still_comes_from_the_table():
    tools = load_tool_table(TOOLS)
    prog = parse("T1 M6\nF10\nG41 G1 X10\nX20\nG40 X30\nM2", tools=tools)
    assert prog.moves[0].radius == 3.0 and prog.moves[0].comp == "left"


# ------------------------------------------------------------------ canned cycles

def test_g81_g98_returns_to_the_initial_level_g99_to_r():
    prog = parse("F100\nG0 Z10\nG98 G81 X10 Y0 Z-5 R2\nX20\nG99 X30\nX40\nG98 X50\nG80\n"
                 "G0 Z3\nG98 G81 X60 Z-5 R2\nM2")
    assert pts(prog) == [
        ("rapid", (0, 0, 10)),
        ("rapid", (10, 0, 10)), ("rapid", (10, 0, 2)), ("line", (10, 0, -5)),
        ("rapid", (10, 0, 10)),
        ("rapid", (20, 0, 10)), ("rapid", (20, 0, 2)), ("line", (20, 0, -5)),
        ("rapid", (20, 0, 10)),
        ("rapid", (30, 0, 10)), ("rapid", (30, 0, 2)), ("line", (30, 0, -5)),
        ("rapid", (30, 0, 2)),
        ("rapid", (40, 0, 2)), ("line", (40, 0, -5)), ("rapid", (40, 0, 2)),
        # G98 again: back to the initial level of the series (10), not the current Z
        ("rapid", (50, 0, 10)), ("rapid", (50, 0, 2)), ("line", (50, 0, -5)),
        ("rapid", (50, 0, 10)),
        # after G80 a new series starts from Z 3
        ("rapid", (50, 0, 3)), ("rapid", (60, 0, 3)), ("rapid", (60, 0, 2)),
        ("line", (60, 0, -5)), ("rapid", (60, 0, 3)),
    ]
    assert {m.path_mode for m in prog.moves[1:] if m.lineno != 9} == {"G61"}  # exact path
    assert {m.feed for m in prog.moves if m.kind == "line"} == {100.0}


def test_cycle_below_r_rises_to_r_first():
    prog = parse("F100\nG0 X5 Z-1\nG98 G81 X10 Z-5 R2\nM2")
    assert pts(prog)[1:] == [("rapid", (5, 0, 2)), ("rapid", (10, 0, 2)),
                             ("line", (10, 0, -5)), ("rapid", (10, 0, 2))]


def test_l_repeats_in_g91_step_from_hole_to_hole():
    prog = parse("F100\nG0 Z5\nG91 G81 X10 Z-3 R-3 L3\nM2")
    # R = 5 - 3 = 2 above the start, Z = R - 3 = -1; G99 (the default) returns to R
    assert pts(prog)[1:] == [
        ("rapid", (10, 0, 5)), ("rapid", (10, 0, 2)), ("line", (10, 0, -1)),
        ("rapid", (10, 0, 2)),
        ("rapid", (20, 0, 2)), ("line", (20, 0, -1)), ("rapid", (20, 0, 2)),
        ("rapid", (30, 0, 2)), ("line", (30, 0, -1)), ("rapid", (30, 0, 2)),
    ]
    # in G91, R counts from the initial level of the series, not from where the tool is
    prog = parse("F100\nG0 Z5\nG91 G81 X10 Z-3 R-3\nX10\nM2")
    assert pts(prog)[-3:] == [("rapid", (20, 0, 2)), ("line", (20, 0, -1)),
                              ("rapid", (20, 0, 2))]


def test_g82_and_g89_dwell_at_the_bottom():
    prog = parse("F100\nG0 Z5\nG82 X1 Z-1 R1 P0.5\nX2\nG80\nG98 G89 X3 Z-2 R1 P2\nM2")
    assert pts(prog)[1:] == [
        ("rapid", (1, 0, 5)), ("rapid", (1, 0, 1)), ("line", (1, 0, -1)), ("rapid", (1, 0, 1)),
        ("rapid", (2, 0, 1)), ("line", (2, 0, -1)), ("rapid", (2, 0, 1)),
        ("rapid", (3, 0, 1)), ("line", (3, 0, -2)), ("line", (3, 0, 1)),
    ]
    assert prog.events == [Dwell(seconds=0.5, lineno=3, before=4),
                           Dwell(seconds=0.5, lineno=4, before=7),
                           Dwell(seconds=2.0, lineno=6, before=10)]


def test_g85_feeds_out_to_r_then_rapids_to_the_clear_level():
    prog = parse("F100\nG0 Z5\nG98 G85 X1 Z-2 R1\nM2")
    assert pts(prog)[1:] == [("rapid", (1, 0, 5)), ("rapid", (1, 0, 1)), ("line", (1, 0, -2)),
                             ("line", (1, 0, 1)), ("rapid", (1, 0, 5))]


def test_g73_breaks_chips_with_a_short_backoff():
    prog = parse("F100\nG0 Z3\nG99 G73 Z-1 R1 Q0.6\nM2")
    z = [m.end[2] for m in prog.moves[1:]]
    assert [m.kind for m in prog.moves[1:]] == ["rapid"] + ["line", "rapid"] * 4
    assert z == pytest.approx([1, 0.4, 0.654, -0.2, 0.054, -0.8, -0.546, -1, 1])


def test_g83_retracts_to_r_between_pecks():
    prog = parse("F100\nG0 Z5\nG98 G83 Z-1 R1 Q0.8\nM2")
    z = [m.end[2] for m in prog.moves[1:]]
    assert [m.kind for m in prog.moves[1:]] == ["rapid"] + ["line", "rapid", "rapid"] * 2 + \
        ["line", "rapid"]
    # peck to 0.2, out to R, back down to 0.2 + 0.254, peck to -0.6, ..., -1, out to 5 (G98)
    assert z == pytest.approx([1, 0.2, 1, 0.454, -0.6, 1, -0.346, -1, 5])
    # G20: the back-off is 0.010 inch
    inch = parse("G20 F10\nG0 Z1\nG99 G83 Z-0.2 R0.1 Q0.2\nM2")
    assert inch.moves[4].end[2] == pytest.approx((-0.1 + 0.01) * 25.4)


@pytest.mark.parametrize("text, lineno, reason", [
    ("F10\nG81 X1 R1\nM2", 2, "G81 needs Z the first time"),
    ("F10\nG81 X1 Z-1\nM2", 2, "G81 needs R the first time"),
    ("F10\nG81 X1 Z2 R1\nM2", 2, "R plane (1 mm) is below the bottom Z (2 mm)"),
    ("F10\nG83 X1 Z-1 R1\nM2", 2, "G83 needs Q"),
    ("F10\nG73 X1 Z-1 R1 Q-1\nM2", 2, "peck depth Q must be positive"),
    ("F10\nG82 X1 Z-1 R1\nM2", 2, "G82 needs P"),
    ("F10\nG81 X1 Z-1 R1 L0\nM2", 2, "L must be a whole number of repeats >= 1"),
    ("G81 X1 Z-1 R1\nM2", 1, "no feed rate set (F) for G81"),
    ("G93 F1\nG81 X1 Z-1 R1\nM2", 2, "inverse time feed (G93) with canned cycles"),
    ("F10\nG41.1 D1 G1 X5\nG81 X1 Z-1 R1\nM2", 3, "canned cycles with cutter compensation"),
    ("F10\nG18 G81 X1 Z-1 R1\nM2", 2, "canned cycles are supported in G17 only"),
    ("F10\nG81 X1 Z-1 R1 Q1\nM2", 2, "word Q1 is not used by G81"),
    ("F10\nG81 X1 Z-1 R1\nG80 X2\nM2", 3, "axis words with G80"),
    ("F10\nG81 X1 Z-1 R1\nG80\nX2\nM2", 4, "axis words without a motion mode"),
    ("F10\nG81 X1 Z-1 R1\nR3\nM2", 3, "canned-cycle words without axis words"),
    ("F10\nG81 X1 Z-1 R1\nG82 X2\nM2", 3, "G82 needs Z the first time"),
])
def test_canned_cycle_errors(text, lineno, reason):
    e = error(text)
    assert e.lineno == lineno and reason in e.reason, e.reason


# ------------------------------------------------------------------ path control

def test_path_control_is_recorded_on_every_move():
    prog = parse("F10\nG1 X1\nG61 X2\nG61.1 X3\nG64 P0.02 Q0.01 X4\nG64 P0.1 X5\nG64 X6\n"
                 "G20 G64 P0.001 X7\nM2")
    assert [m.path_mode for m in prog.moves] == ["G64", "G61", "G61.1", "G64", "G64", "G64",
                                                 "G64"]
    assert [m.path_tolerance for m in prog.moves] == pytest.approx([0, 0, 0, 0.02, 0.1, 0,
                                                                    0.0254])
    assert [m.naive_tolerance for m in prog.moves] == pytest.approx([0, 0, 0, 0.01, 0.1, 0,
                                                                     0.0254])
    assert "must not be negative" in error("G64 P-1\nM2").reason


# ------------------------------------------------------------------ program flow, spindle

def test_pauses_dwells_and_the_program_end():
    prog = parse("G0 X1\nM0\nG4 P1.5\nG0 X2\nM1\nG0 X3 M0\nM30\nG0 X9")
    assert pts(prog) == [("rapid", (1, 0, 0)), ("rapid", (2, 0, 0)), ("rapid", (3, 0, 0))]
    assert prog.ended and prog.notes == []
    assert prog.events == [Pause(reason="M0", lineno=2, before=1),
                           Dwell(seconds=1.5, lineno=3, before=1),
                           Pause(reason="M0", lineno=6, before=3)]
    # M1 pauses only with the optional-stop switch on
    prog = parse("G0 X1\nM1\nM2", optional_stop=True)
    assert prog.events == [Pause(reason="M1", optional=True, lineno=2, before=1)]
    assert "G4 needs P" in error("G4\nM2").reason
    assert "must not be negative" in error("G4 P-1\nM2").reason


def test_a_program_without_m2_ends_at_the_end_of_the_file_with_a_note():
    prog = parse("G0 X1\nG0 X2\n")
    assert not prog.ended and len(prog.moves) == 2
    assert prog.notes == ["no M2 or M30: the program ends at the end of the file (line 2); "
                          "LinuxCNC requires one"]
    prog = parse("%\nG0 X1\n%\n")
    assert prog.ended and prog.notes == []


def test_spindle_and_coolant_events_in_program_order():
    prog = parse("S1000 M3\nG0 X1\nS2000\nM4\nM7\nM8\nG0 X2\nM9 M5\nS50\nM2")
    assert prog.events == [
        Spindle(on=True, cw=True, speed=1000, lineno=1, before=0),
        Spindle(on=True, cw=True, speed=2000, lineno=3, before=1),
        Spindle(on=True, cw=False, speed=2000, lineno=4, before=1),
        Coolant(mist=True, flood=False, lineno=5, before=1),
        Coolant(mist=True, flood=True, lineno=6, before=1),
        Spindle(on=False, cw=False, speed=2000, lineno=8, before=2),
        Coolant(mist=False, flood=False, lineno=8, before=2),
    ]
    assert parse("M7 M8\nM2").events == [Coolant(mist=True, flood=True, lineno=1)]
    assert "spindle speed S must not be negative" in error("S-1\nM2").reason
    assert "two M codes of the spindle group" in error("M3 M5\nM2").reason


def test_order_of_execution_within_a_block():
    """LinuxCNC's order: F, S, T, M6, M3-M5, M7-M9, G4, ..., motion, M0."""
    prog = parse("F100\nG0 X1 M0 G4 P1 M8 M3 S500 T2 M6\nM2")
    assert [type(e).__name__ for e in prog.events] == ["ToolChange", "Spindle", "Coolant",
                                                       "Dwell", "Pause"]
    assert [e.before for e in prog.events] == [0, 0, 0, 0, 1]


# ------------------------------------------------------------------ refusals

@pytest.mark.parametrize("text, reason", [
    ("G7\nM2", "lathe diameter mode (G7)"),
    ("G8\nM2", "lathe radius mode (G8)"),
    ("G33 Z-1 K1\nM2", "spindle-synchronised motion (G33)"),
    ("G33.1 Z-1 K1\nM2", "rigid tapping (G33.1)"),
    ("G76 P1 Z-1\nM2", "threading (G76)"),
    ("G16\nM2", "polar coordinates (G15/G16)"),
    ("G15\nM2", "polar coordinates (G15/G16)"),
    ("G0 @5 ^30\nM2", "polar coordinates ('@' radius, '^' angle)"),
    ("G0 A90\nM2", "axis A is not supported"),
    ("G0 W1\nM2", "axis W is not supported"),
    ("F10 G86 X1 Z-1 R1 P1\nM2", "canned cycle G86 is not supported"),
    ("G38.2 Z-1 F10\nM2", "probing"),
    ("G95\nM2", "feed per revolution"),
    ("M60\nM2", "unsupported M code M60"),
    ("G1 X1 F10 H2\nM2", "unsupported word H2 here"),
])
def test_refused_words_name_the_line(text, reason):
    e = error(text)
    assert e.lineno == 1 and reason in e.reason, e.reason


# ------------------------------------------------------------------ machine state as parameters

def test_system_parameters_read_the_state_the_blocks_before_left():
    """The interpreter runs each block through the parser as it goes, so a line reads the
    offsets, position, tool and modes that the lines before it set (LinuxCNC's numbered
    parameters #5161-#5428 and the named #<_x>...)."""
    tools = load_tool_table(TOOLS)
    prog = parse("G10 L2 P1 X5\nG0 X#5221\n"               # G54 X offset 5 -> X 5 + 5
                 "G0 X3 Y4\nG0 X[#5420 * 2] Y#<_abs_y>\n"  # program X 3 -> 6; Y 4
                 "G0 Z7\nG0 Z[#<_z> + 1]\n"
                 "G55\nG0 X#5220\n"                        # G55 in use: 2 (offset 0)
                 "T2 M6\nG0 Y#5400 Z#<_current_tool>\n"
                 "G43.1 Z1\nG0 Z#5403\n"                   # offset 1: program Z 1 -> 2
                 "G92 X0\nG0 Y#5211 Z#5210\n"              # G92 X offset 2, applied
                 "G28\nG0 X#5161 Y#5182\nM2", tools=tools,
                 positions={"g28": (1, 2, 3), "g30": (4, 5, 6)})
    assert pts(prog) == [
        ("rapid", (10, 0, 0)), ("rapid", (8, 4, 0)), ("rapid", (11, 4, 0)),
        ("rapid", (11, 4, 7)), ("rapid", (11, 4, 8)), ("rapid", (2, 4, 8)),
        ("rapid", (2, 2, 2)), ("rapid", (2, 2, 2)), ("rapid", (2, 2, 2)),
        ("rapid", (1, 2, 3)), ("rapid", (3, 5, 3))]


def test_tool_diameter_parameter_5410_reads_the_loaded_tool():
    """LinuxCNC's #5410, the loaded tool's diameter (every ngcgui milling subroutine
    reads it after loading its tool; it was refused as machine state halfpoint did not
    provide), in program units; 0 without a tool; #5411-#5413 (lathe angles and
    orientation) 0."""
    tools = load_tool_table(TOOLS)
    prog = parse("G0 X#5410\nT1 M6\nG0 X#5410\nT2 M6\nG20\nG0 Y#5410\n"
                 "G21 G0 Z[#5411 + #5412 + #5413]\nM2", tools=tools)
    assert pts(prog) == [("rapid", (0, 0, 0)), ("rapid", (6, 0, 0)),
                         ("rapid", (6, 3, 0)), ("rapid", (6, 3, 0))]


def test_named_modal_parameters_and_program_units():
    # a line reads the values from before it: G21 G91 count from the next line on
    prog = parse("G20 G0 X1\nG0 Y#<_x>\nG21 G91\nG0 Z[#<_metric> + #<_incremental> * 10]\n"
                 "G90 G0 X[#<_motion_mode> / 10] Y[#<_coord_system> / 10] Z[#<_plane>]\n"
                 "F123 S456 M3 M8\nG0 X#<_feed> Y#<_rpm> Z[#<_spindle_on> + #<_flood>]\nM2")
    assert pts(prog) == [("rapid", (25.4, 0, 0)), ("rapid", (25.4, 25.4, 0)),
                         ("rapid", (25.4, 25.4, 11)), ("rapid", (0, 54, 170)),
                         ("rapid", (123, 456, 2))]
    e = error("G0 X#<_ccomp>\nM2")
    assert e.lineno == 1 and "does not track" in e.reason


@pytest.mark.parametrize("text, lineno, reason", [
    ("G43 H1.5\nM2", 1, "H must be a whole tool number >= 0"),
    ("F10\nG41.1 D1 G1 X5\nG53 G1 X0\nM2", 3, "G53 with cutter compensation on"),
    ("F10\nG41.1 D1 G1 X5\nG55 X6\nM2", 3, "cannot change the coordinate system with cutter"),
    ("F10\nT1 M6\nG41.1 D1 G1 X5\nT2 M6\nM2", 4, "tool change with cutter compensation on"),
    ("M0 M2\n", 1, "two M codes of the stopping group"),
    ("G4 P1 G92 X0\nM2", 1, "two G codes of the non-modal group"),
    ("G17 G18\nM2", 1, "two G codes of the plane group"),
    ("T-1\nM2", 1, "tool number T must be a whole number >= 0"),
    ("G93 G94\nM2", 1, "two G codes of the feed mode group"),
    ("G0 X1 L2\nM2", 1, "unsupported word L2 here"),
])
def test_more_errors_name_the_line(text, lineno, reason):
    e = error(text)
    assert e.lineno == lineno and reason in e.reason, e.reason
