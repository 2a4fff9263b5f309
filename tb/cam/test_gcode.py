# SPDX-License-Identifier: Apache-2.0
"""G-code front end: modal state, arcs, units, and every kind of bad program."""

from __future__ import annotations

import math

import pytest

from halfpoint.cam.gcode import GcodeError, load_tool_table, parse


def ends(text, **kw):
    return [(m.kind, tuple(round(v, 6) for v in m.end)) for m in parse(text, **kw).moves]


def test_modal_moves_units_and_distance_modes():
    prog = """G21 G90 F100
G0 X1 Y2
G1 X3
G91 Y1 Z-1
G20 X1
G90 G21 X0 Y0 Z0
M2"""
    assert ends(prog) == [
        ("rapid", (1, 2, 0)), ("line", (3, 2, 0)), ("line", (3, 3, -1)),
        ("line", (28.4, 3, -1)), ("line", (0, 0, 0)),
    ]


def test_arc_centre_formats_radius_format_and_full_circle():
    p = parse("G17 F50\nG1 X10 Y0\nG3 X0 Y10 I-10 J0\nG90.1 G2 X10 Y0 I0 J0\n"
              "G91.1 G2 X10 Y0 I-5 J0\nG2 X0 Y10 R-10\nG3 X10 Y0 R10\nM30").moves
    a1, a2, full, r_long, r_short = p[1:]
    assert a1.center == (0.0, 0.0) and not a1.cw
    assert a2.center == (0.0, 0.0) and a2.cw
    assert full.start == full.end and full.center == (5.0, 0.0)
    # radius format: R < 0 takes the long way round
    assert math.hypot(*(a - b for a, b in zip(r_long.center, (0.0, 0.0)))) < 1e-9
    assert math.hypot(*(a - b for a, b in zip(r_short.center, (10.0, 10.0)))) < 1e-9


def test_percent_demarcation_and_program_number():
    assert len(parse("%\nG0 X1\n%\nthis is ignored").moves) == 1
    assert len(parse("%1234\nG0 X1\nM30").moves) == 1


def test_linuxcnc_radius_rule_tolerance():
    ok = "F10\nG1 X10\nG3 X-10.004 Y0 I-10 J0\nM2"        # 0.004 mm off: within 0.005
    parse(ok)
    big = "F10\nG1 X1000\nG3 X-1000.9 Y0 I-1000 J0\nM2"   # 0.9 mm: beyond 0.5 mm
    with pytest.raises(GcodeError, match="line 3: arc end point is not on the circle"):
        parse(big)
    rel = "F10\nG1 X1000\nG3 X-1000.3 Y0 I-1000 J0\nM2"   # 0.3 mm = 0.03 %: accepted
    parse(rel)


def test_tool_table_and_comp_radius():
    tools = load_tool_table("T1 P1 D6.0 ;6 mm end mill\nT2 P2 D0.06\n")
    assert tools == {1: 3.0, 2: 0.03}
    p = parse("F10\nG41 D2 G1 X1\nG40 X2\nM2", tools=tools)
    assert p.moves[0].comp == "left" and p.moves[0].radius == 0.03
    p = parse("F10\nG42.1 D4 G1 X1\nG40 X2\nM2")
    assert p.moves[0].comp == "right" and p.moves[0].radius == 2.0


@pytest.mark.parametrize(
    "text, lineno, reason",
    [
        ("G1 X1 F10\nG5.1 X2 I1 J1\nM2", 2, "splines (G5.1) are not supported"),
        ("F10\nG1 X1\nM62 P1\nM2", 3, "unsupported M code M62"),
        ("F10\nG1 X1 A3\nM2", 2, "axis A is not supported"),
        ("F10\nG1 X1 E3\nM2", 2, "unsupported word E3"),
        ("G0 X1 X2\nM2", 1, "word X appears twice"),
        ("G0 G1 X1\nM2", 1, "two G codes of the motion group"),
        ("X1\nM2", 1, "axis words without a motion mode"),
        ("G1 X1\nM2", 1, "no feed rate set"),
        ("F10\nG1 X1 (unclosed\nM2", 2, "comment '(' is not closed"),
        ("F10\nG1 X#<nope>\nM2", 2, "named parameter #<nope> is not defined"),
        ("F10\nG2 X1 Y1\nM2", 2, "arc without I/J/K offsets or R"),
        ("F10\nG2 X1 Y1 I1 R2\nM2", 2, "either I/J/K offsets or R"),
        ("F10\nG2 X10 R2\nM2", 2, "too small for a chord"),
        ("F10\nG2 R2\nM2", 2, "cannot be a full circle"),
        ("F10\nG2 X2 Y0 K1\nM2", 2, "offset K does not belong to plane G17"),
        ("F10\nG2 X2 Y0 I0 J0\nM2", 2, "arc radius is zero"),
        ("F10\nG41 G1 X1\nM2", 2, "needs a D word"),
        ("F10\nG41 D7 G1 X1\nM2", 2, "tool 7 is not in the tool table"),
        ("F10\nG1 X1 D2\nM2", 2, "D word without G41"),
        ("F10\nG18 G41.1 D2 G1 X1\nM2", 2, "cutter compensation is supported in G17"),
        ("F10\nG41.1 D2 G1 X5\nG42.1 D2 X6\nM2", 3, "already on"),
        ("%\nG0 X1", 2, "no closing '%'"),
        ("G0 X1\n%\nM2", 2, "did not open with '%'"),
        ("F-5 G1 X1\nM2", 1, "feed rate F must be positive"),
        ("F10\nG1 X[1+2\nM2", 2, "unbalanced '['"),
    ],
)
def test_bad_program_names_line_and_reason(text, lineno, reason):
    with pytest.raises(GcodeError) as exc:
        parse(text)
    assert exc.value.lineno == lineno and reason in str(exc.value), str(exc.value)


def test_parameters_expressions_and_block_delete_reach_the_parser():
    """Parameters and expressions are evaluated before the block is parsed (LinuxCNC's
    order: a parameter set on a line takes effect after it), and a line starting with
    ``/`` is skipped (block delete on, the LinuxCNC default) or run (switch off)."""
    prog = parse("F10\n#1=2\nG1 X#1 Y[#1 * 3]\n/G1 Z5\nM2")
    assert [m.end for m in prog.moves] == [(2.0, 6.0, 0.0)]
    assert [m.lineno for m in prog.moves] == [3]
    prog = parse("F10\n#1=2\nG1 X#1 Y[#1 * 3]\n/G1 Z5\nM2", block_delete=False)
    assert [m.end for m in prog.moves] == [(2.0, 6.0, 0.0), (2.0, 6.0, 5.0)]
