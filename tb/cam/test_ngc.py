# SPDX-License-Identifier: Apache-2.0
"""RS274NGC interpreter front end (halfpoint.cam.ngc): one program per construct with
its expected blocks, LinuxCNC's evaluation order, the limits, every error, and a
LinuxCNC nc_files-style program that expands to its hand-expanded equivalent."""

from __future__ import annotations

import math
import random
import re
from pathlib import Path

import pytest

from halfpoint.cam.gcode import GcodeError, parse
from halfpoint.cam.ngc import Block, NgcError, expand, format_number

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"


def texts(program: str, **kw) -> list[str]:
    """The expanded blocks' text (pass-through lines keep their indentation: stripped)."""
    return [b.text.strip() for b in expand(program, **kw).blocks]


def value(expression: str) -> float:
    """The value of one expression, read back from the expanded block."""
    (block, _end) = texts(f"G0 X{expression}\nM2")
    assert block.startswith("G0 X"), block
    return float(block[4:])


def error(program: str, **kw) -> NgcError:
    with pytest.raises(NgcError) as info:
        expand(program, **kw)
    assert isinstance(info.value, GcodeError)
    return info.value


# ------------------------------------------------------------------ pass-through, numbers

def test_plain_program_passes_through_unchanged():
    text = (EXAMPLES / "plate.ngc").read_text()
    out = expand(text, "plate.ngc")
    lines = text.splitlines()
    end = lines.index("M30") + 1                 # M30 ends the program: the closing % is not run
    assert [b.text for b in out.blocks] == [ln for ln in lines[:end] if ln.strip()]
    assert [b.lineno for b in out.blocks] == [k + 1 for k, ln in enumerate(lines[:end])
                                              if ln.strip()]
    assert out.messages == [] and out.ended
    assert [(m.kind, m.end) for m in parse(out.text(), {1: 3.0}).moves] == \
        [(m.kind, m.end) for m in parse(text, {1: 3.0}).moves]


def test_format_number_round_trips_without_exponent():
    word = re.compile(r"[+-]?(?:\d+\.?\d*|\.\d+)")        # the block parser's number
    rng = random.Random(14)
    samples = [0.0, -0.0, 1.0, 2.5, 1e-7, -3e-12, 1e22, 123456789.125, 0.1 + 0.2]
    samples += [rng.uniform(-1e4, 1e4) * 10 ** rng.randint(-9, 9) for _ in range(2000)]
    for x in samples:
        text = format_number(x)
        assert "e" not in text.lower() and word.fullmatch(text), text
        assert float(text) == x
    assert format_number(5.0) == "5" and format_number(-0.25) == "-0.25"


# ------------------------------------------------------------------ parameters

def test_numbered_parameters_in_words_and_expressions():
    assert texts("#1 = 2.5\nG1 X#1 Y[#1 * 2] F100 (move)\n#31=-1\nG0 Z#31\nM2") == \
        ["G1 X2.5 Y5 F100 (move)", "G0 Z-1", "M2"]


def test_parameters_set_on_a_line_take_effect_after_the_line():
    # LinuxCNC's manual: with #3 = 15, '#3=6 G1 X#3' moves to X15 and leaves #3 = 6
    assert texts("#3=15\n#3=6 G1 X#3 F1\nG1 X#3\nM2") == ["G1 X15 F1", "G1 X6", "M2"]
    # every value on a line uses the values from before it; the last setting wins
    assert texts("#1=1 #2=[#1+1] #1=5\nG0 X#1 Y#2\nM2") == ["G0 X5 Y1", "M2"]
    assert texts("#<a>=1\n#<a>=[#<a>+1] #<b>=#<a>\nG0 X#<a> Y#<b>\nM2") == ["G0 X2 Y1", "M2"]
    # an O-word condition sees the values of the lines before it
    assert texts("#1=0\no1 while [#1 LT 2]\n#1=[#1+1] G0 X#1\no1 endwhile\nM2") == \
        ["G0 X0", "G0 X1", "M2"]


def test_indirection_and_uninitialised_numbered_parameters():
    assert texts("#1=5\n#5=7\n#7=9\nG0 X##1 Y#[#1 - 4] Z###1\nG0 X#4000\nM2") == \
        ["G0 X7 Y5 Z9", "G0 X0", "M2"]
    # '#' binds tighter than '+': #1+2 is the value of #1 plus 2
    assert value("[#1+2]") == 2.0


def test_named_parameters_local_and_global_scope():
    program = """#<_g> = 1
#<Local Name> = 2
o<s> sub
  #<_g> = [#<_g> + 10]
  #<local name> = 3            (a new local, not the caller's)
  G0 X#<localname> Y#<_G>
o<s> endsub
o<s> call
G0 X#<localname> Y#<_g>
G0 Z[EXISTS[#<localname>] + EXISTS[#<nothere>] * 10]
M2"""
    assert texts(program) == ["G0 X3 Y11", "G0 X2 Y11", "G0 Z1", "M2"]
    # the caller's locals are not visible in the subroutine
    e = error("#<a> = 1\no<s> sub\nG0 X#<a>\no<s> endsub\no<s> call\nM2")
    assert e.lineno == 3 and "#<a> is not defined" in e.reason and "called at line 5" in e.reason


def test_system_parameters_and_initial_values():
    assert texts("G0 X#5220 Y#5221 Z#<_value>\nM2") == ["G0 X1 Y0 Z0", "M2"]
    assert texts("G0 X#100 Y#<_width>\nM2", parameters={100: 4.5, "_Width": 2}) == \
        ["G0 X4.5 Y2", "M2"]


# ------------------------------------------------------------------ expressions

@pytest.mark.parametrize("expression, expected", [
    ("[2.0 / 3 * 1.5 - 5.5 / 11.0]", 0.5),          # the manual's precedence example
    ("[1 + 2 * 3]", 7.0),
    ("[[1 + 2] * 3]", 9.0),
    ("[2 ** 3 ** 2]", 64.0),                          # left to right within a group
    ("[2 * 3 ** 2]", 18.0),
    ("[-2 ** 2]", 4.0),                               # unary minus binds tighter than **
    ("[2 - -1]", 3.0),
    ("-[1 + 2]", -3.0),
    ("[7 MOD 3]", 1.0),
    ("[-7 MOD 3]", 2.0),                              # MOD is never negative
    ("[7.5 MOD 2]", 1.5),
    ("[10 - 2 - 3]", 5.0),
    ("[1 EQ 1.0000001]", 1.0),                        # TOLERANCE_EQUAL 1e-6
    ("[1 NE 1.0000001]", 0.0),
    ("[1 NE 1.01]", 1.0),
    ("[2 GT 1]", 1.0), ("[1 GT 1]", 0.0), ("[1 GE 1.0000001]", 1.0),
    ("[1 LT 2]", 1.0), ("[2 LT 2]", 0.0), ("[1.0000001 LE 1]", 1.0),
    ("[1 + 1 EQ 2]", 1.0),                            # + before EQ
    ("[1 LT 2 AND 3 GT 4]", 0.0),                     # comparison before AND
    ("[1 OR 0 XOR 1]", 0.0),                          # ((1 OR 0) XOR 1)
    ("[0.5 AND -2]", 1.0), ("[0 OR 0]", 0.0), ("[2 XOR 0]", 1.0),
    ("[0.1 + 0.2]", 0.1 + 0.2),
    ("[1 1 . 5]", 11.5),                              # blanks do not matter outside comments
    ("[3 mod 2 ge 1 and 1]", 1.0),                   # lower case
])
def test_binary_operators_and_precedence(expression, expected):
    assert value(expression) == expected


@pytest.mark.parametrize("expression, expected", [
    ("ABS[-2.5]", 2.5), ("ACOS[0]", 90.0), ("ASIN[1]", 90.0), ("ATAN[1]/[1]", 45.0),
    ("ATAN[1]/[-1]", 135.0), ("ATAN[-1]/[0]", -90.0), ("COS[60]", 0.5), ("SIN[30]", 0.5),
    ("TAN[45]", 1.0), ("EXP[1]", math.e), ("LN[EXP[2]]", 2.0), ("SQRT[16]", 4.0),
    ("FIX[2.8]", 2.0), ("FIX[-2.8]", -3.0), ("FUP[2.8]", 3.0), ("FUP[-2.8]", -2.0),
    ("ROUND[2.5]", 3.0), ("ROUND[-2.5]", -3.0), ("ROUND[2.4999]", 2.0),
    ("[SQRT[9] + ABS[-1] * 2]", 5.0), ("sin[90]", 1.0),
])
def test_functions_in_degrees(expression, expected):
    assert value(expression) == pytest.approx(expected, abs=1e-12)


# ------------------------------------------------------------------ O-words

def test_subroutine_arguments_locals_and_return_values():
    program = """#1 = 100
#2 = 200
#3 = 300
o100 sub
  G0 X#1 Y#2 Z#3                 (#3 was not passed: the caller's value)
  #1 = 9                         (local to the call)
o100 endsub
o<twice> sub
  o<twice> return [#1 * 2]
  G0 X999                        (not reached)
o<twice> endsub
o<none> sub
o<none> endsub
o100 call [1] [2]
G0 X#1 Y#2 Z#3
o<twice> call [21]
G0 X#<_value> Y#<_value_returned>
o<none> call
G0 X#<_value> Y#<_value_returned>
M2"""
    assert texts(program) == ["G0 X1 Y2 Z300 (#3 was not passed: the caller's value)",
                              "G0 X100 Y200 Z300", "G0 X42 Y1",
                              "G0 X0 Y0", "M2"]


def test_endsub_value_computed_and_forward_call():
    program = """#1 = 5
o[#1 + 10] call [#1]
o<v> call
G0 X#<_value>
M2
o15 sub
  G0 X#1
o15 endsub [#1 + 1]
o<v> sub
o<v> endsub [3 * 4]"""
    out = expand(program)
    assert [b.text.strip() for b in out.blocks] == ["G0 X5", "G0 X12", "M2"]
    assert [b.lineno for b in out.blocks] == [7, 4, 5]


def test_recursion_and_the_depth_limit():
    factorial = """o<factorial> sub
o<fif> if [#1 EQ 0]
  o<factorial> return [1]
o<fif> else
  o<factorial> call [#1 - 1]
  o<factorial> return [#<_value> * #1]
o<fif> endif
o<factorial> endsub
o<factorial> call [#100]
G0 X#<_value>
M2"""
    assert texts(factorial, parameters={100: 5}) == ["G0 X120", "M2"]
    assert texts(factorial, parameters={100: 9}) == ["G0 X362880", "M2"]   # 10 calls deep
    e = error(factorial, parameters={100: 10})
    assert e.lineno == 5 and "deeper than 10" in e.reason
    e = error(factorial, parameters={100: 3}, max_depth=3)
    assert e.lineno == 5 and "deeper than 3" in e.reason


def test_if_elseif_else():
    program = """o1 sub
  o2 if [#1 GT 5]
    G0 X1
  o2 elseif [#1 LT 2]
    G0 X2
  o2 elseif [#1 EQ 3]
    G0 X3
  o2 else
    G0 X4
  o2 endif
o1 endsub
o1 call [6]
o1 call [0]
o1 call [3]
o1 call [4]
o3 if [1]
  G0 Y1
o3 endif
o4 if [0]
  G0 Y2
o4 endif
M2"""
    assert texts(program) == ["G0 X1", "G0 X2", "G0 X3", "G0 X4", "G0 Y1", "M2"]


def test_while_do_repeat_break_continue():
    program = """#1 = 0
o10 while [#1 LT 3]
  #1 = [#1 + 1]
  G0 X#1
o10 endwhile
o20 do
  G0 Y#1                       (runs once although the condition is false)
o20 while [#1 LT 0]
o30 repeat [2]
  G0 Z#1
o30 endrepeat
o31 repeat [0]
  G0 Z99
o31 endrepeat
#2 = 0
o40 while [1]
  #2 = [#2 + 1]
  o41 if [#2 EQ 2]
    o40 continue
  o41 endif
  o42 if [#2 GT 3]
    o40 break
  o42 endif
  G0 X[10 + #2]
o40 endwhile
#3 = 0
o50 do
  #3 = [#3 + 1]
  o51 if [#3 EQ 1]
    o50 continue               (to the while test)
  o51 endif
  G0 Y[10 + #3]
o50 while [#3 LT 3]
M2"""
    assert texts(program) == ["G0 X1", "G0 X2", "G0 X3",
                              "G0 Y3 (runs once although the condition is false)", "G0 Z3", "G0 Z3",
                              "G0 X11", "G0 X13", "G0 Y12", "G0 Y13", "M2"]


def test_loop_iteration_limit():
    e = error("#1=0\no7 while [1]\n#1=[#1+1]\no7 endwhile\nM2")
    assert e.lineno == 2 and "1000000 loop iterations" in e.reason
    e = error("o7 repeat [50]\no8 repeat [50]\no8 endrepeat\no7 endrepeat\nM2",
              max_iterations=1000)
    assert e.lineno == 2 and "more than 1000" in e.reason
    assert texts("o7 repeat [10]\no7 endrepeat\nM2", max_iterations=10) == ["M2"]


def test_subroutine_from_a_file_in_the_search_path(tmp_path):
    (tmp_path / "slot.ngc").write_text(
        "(slot.ngc)\no<slot> sub\n  G1 X[#1 + #2] F100\n  G1 X[#1 / #3]\no<slot> endsub\nM2\n")
    out = expand("o<SLOT> call [4] [2] [1]\nM2", "main.ngc", search_path=[tmp_path])
    path = str(tmp_path / "slot.ngc")
    assert out.blocks == [Block(3, "G1 X6 F100", path), Block(4, "G1 X4", path),
                          Block(2, "M2", "")]
    e = error("o<slot> call [4] [2] [0]\nM2", search_path=[tmp_path])
    assert e.lineno == 4 and e.source == path
    assert str(e).startswith(f"{path}: line 4: division by zero at '/#3]'")
    assert "called at line 1" in str(e)
    e = error("o<nothere> call\nM2", search_path=[tmp_path])
    assert "no such subroutine" in e.reason and "nothere.ngc" in e.reason
    (tmp_path / "wrong.ngc").write_text("o<other> sub\no<other> endsub\n")
    assert "does not define o<wrong> sub" in error("o<wrong> call\nM2",
                                                   search_path=[tmp_path]).reason


# ------------------------------------------------------------------ program flow, messages

def test_program_end_and_percent():
    # M2 inside a subroutine ends the program; nothing after it runs, even a bad line
    out = expand("o1 sub\nG0 X1\nM2\no1 endsub\no1 call\nG0 X[1/0]\nM30")
    assert [b.text for b in out.blocks] == ["G0 X1", "M2"] and out.ended
    out = expand("%\n#1=3\nG0 X#1\n%\nG0 X[1/0] (never read)\no9 if [1]\n", "p.ngc")
    assert [b.text for b in out.blocks] == ["%", "G0 X3", "%"] and out.ended
    assert out.line_count == 6 and out.opening == 1
    assert expand("\n  \n%1234\nG0 X1\n%\n").opening == 3
    assert expand("#1=2\n%\nM2").opening == 0
    assert not expand("G0 X1\n").ended


def test_block_delete():
    program = "G0 X1\n/G0 X2\n  / #1 = 5\nG0 Y#1\n/o1 if [1]\nM2"
    assert texts(program) == ["G0 X1", "G0 Y0", "M2"]
    assert texts(program.replace("/o1 if [1]", "o1 if [1]\no1 endif"), block_delete=False) == \
        ["G0 X1", "G0 X2", "G0 Y5", "M2"]


def test_messages():
    program = """#1 = 2.5
#<d> = 10
(MSG, plain #1 text)
#1 = 3.25 (DEBUG, one=#1 d=#<d> missing=#<nope> %d#1 %.2f#1 %f#1 %lf#1 50%)
G0 X#1 (PRINT,x is #1)
(DEBUG, first) (an ordinary comment last: the DEBUG is not active)
(note) ; debug, semicolon #<d>
(debug this is an ordinary comment)
#5599 = 0
(DEBUG, off)
(PRINT, still #<D>)
M2"""
    out = expand(program)
    assert [(m.kind, m.text, m.lineno) for m in out.messages] == [
        ("MSG", "plain #1 text", 3),
        ("DEBUG", "one=3.250000 d=10.000000 missing=###### 3 3.25 3.2500 3.250000 50%", 4),
        ("PRINT", "x is 3.250000", 5),
        ("DEBUG", "semicolon 10.000000", 7),
        ("PRINT", "still 10.000000", 11),
    ]
    assert "G0 X3.25 (PRINT,x is #1)" in [b.text for b in out.blocks]


# ------------------------------------------------------------------ errors

@pytest.mark.parametrize("program, lineno, words", [
    ("G0 X[1 + 2\nM2", 1, ["unbalanced '['", "'[1+2'"]),
    ("G0 X[1 + 2]]\nM2", 1, ["unexpected character", "']'"]),
    ("G0 X[1 + FOO[2]]\nM2", 1, ["unknown function 'FOO'"]),
    ("G0 X[SIN 30]\nM2", 1, ["expected '[' after SIN"]),
    ("G0 X[ATAN[1]]\nM2", 1, ["expected '/' after ATAN[y]"]),
    ("G0 X[1 +]\nM2", 1, ["expected a number"]),
    ("G0 X[1 2 3 4 5 6 #1]\nM2", 1, ["expected a binary operator"]),
    ("\nG0 X[1 / [2 - 2]]\nM2", 2, ["division by zero", "'/[2-2]]'"]),
    ("G0 X[1 MOD 0]\nM2", 1, ["MOD by zero"]),
    ("G0 X[-8 ** 0.5]\nM2", 1, ["negative number raised to a non-integer power"]),
    ("G0 X[10 ** 400]\nM2", 1, ["out of range"]),
    ("G0 X[SQRT[-1]]\nM2", 1, ["SQRT[-1]", "negative argument"]),
    ("G0 X[LN[0]]\nM2", 1, ["LN[0]"]),
    ("G0 X[ACOS[2]]\nM2", 1, ["ACOS[2]"]),
    ("G0 X[EXP[1000]]\nM2", 1, ["EXP[1000]"]),
    ("G0 X[EXISTS[#1]]\nM2", 1, ["EXISTS takes one named parameter"]),
    ("G0 X#<undefined>\nM2", 1, ["#<undefined> is not defined"]),
    ("G0 X#<_undefined>\nM2", 1, ["#<_undefined> is not defined"]),
    ("G0 X#<_x>\nM2", 1, ["#<_x> is LinuxCNC machine"]),
    ("#<_value> = 1\nM2", 1, ["read-only"]),
    ("G0 X#5420\nM2", 1, ["#5420 is machine state"]),
    ("#5221 = 1\nM2", 1, ["#5221 is a LinuxCNC system parameter"]),
    ("G0 X#6000\nM2", 1, ["out of range"]),
    ("G0 X#[1.5]\nM2", 1, ["parameter number 1.5 is not an integer"]),
    ("#1 5\nM2", 1, ["expected '=' in a parameter setting"]),
    ("G0 X#<abc\nM2", 1, ["named parameter without '>'"]),
    ("G0 X1 o100 call\nM2", 1, ["an O-word must be the first item"]),
    ("o100 call\nM2", 1, ["o100 call: no such subroutine"]),
    ("o100 endsub\nM2", 1, ["o100 endsub without o100 sub"]),
    ("o100 sub\no101 endsub\nM2", 2, ["o101 endsub without o101 sub"]),
    ("o100 sub\no1 if [1]\no100 endsub\nM2", 3, ["does not match the open o1 if (line 2)"]),
    ("o1 if [1]\nG0 X1\nM2", 1, ["o1 if has no o1 endif"]),
    ("o1 while [0]\nM2", 1, ["o1 while has no o1 endwhile"]),
    ("o1 do\nM2", 1, ["o1 do has no o1 while"]),
    ("o1 repeat [2]\nM2", 1, ["o1 repeat has no o1 endrepeat"]),
    ("o1 sub\nM2", 1, ["o1 sub has no o1 endsub"]),
    ("o1 if [1]\no2 endif\nM2", 2, ["o2 endif without o2 if"]),
    ("o1 if [1]\no1 else\no1 elseif [1]\no1 endif\nM2", 3, ["after o1 else"]),
    ("o2 else\nM2", 1, ["o2 else without o2 if"]),
    ("o1 while [1]\no2 break\no1 endwhile\nM2", 2, ["o2 break is not inside a o2 while"]),
    ("o1 repeat [1]\no1 break\no1 endrepeat\nM2", 2, ["not inside a o1 while or do"]),
    ("o1 return\nM2", 1, ["o1 return outside o1 sub"]),
    ("o1 sub\no2 return\no1 endsub\nM2", 2, ["o2 return outside o2 sub"]),
    ("o1 if [1]\no2 sub\no2 endsub\no1 endif\nM2", 2, ["definitions are not nested"]),
    ("o1 sub\no1 endsub\no1 sub\no1 endsub\nM2", 3, ["o1 is defined twice"]),
    ("o1 if\no1 endif\nM2", 1, ["if needs a condition"]),
    ("o1 if [1] G0 X1\no1 endif\nM2", 1, ["unexpected text after the O-word if"]),
    ("o1 frob\nM2", 1, ["unknown O-word keyword"]),
    ("o#1 if [1]\no1 endif\nM2", 1, ["computed O-word is supported with call only"]),
    ("o1 if [1] (DEBUG, x)\no1 endif\nM2", 1, ["message comment on an O-word line"]),
    ("o1 repeat [1.5]\no1 endrepeat\nM2", 1, ["count 1.5 is not an integer"]),
    ("o[-1] call\nM2", 1, ["not a non-negative integer"]),
    ("(LOGOPEN,file.txt)\nM2", 1, ["LOGOPEN comments write files"]),
    ("(LOGCLOSE)\nM2", 1, ["LOGCLOSE comments write files"]),
    ("G0 X#1 (unclosed\nM2", 1, ["comment '(' is not closed"]),
])
def test_errors_name_the_line_and_the_token(program, lineno, words):
    e = error(program)
    assert e.lineno == lineno, str(e)
    for word in words:
        assert word in str(e), str(e)
    assert str(e).startswith(f"line {lineno}: ")


def test_syntax_error_of_a_line_is_reported_when_it_runs():
    assert texts("o1 if [0]\nG0 X[1 +]\no1 endif\nM2") == ["M2"]
    assert error("o1 if [1]\nG0 X[1 +]\no1 endif\nM2").lineno == 2


# ------------------------------------------------------------------ whole programs

NC_FILES_STYLE = """%
(nc_files style: a pocket of concentric squares and a row of slots)
#<_feedrate> = 400
#<_depth> = -1.5
o<square> sub                   (#1 half side, #2 centre x, #3 centre y)
  G1 X[#2 - #1] Y[#3 - #1]
  G1 X[#2 + #1]
  G1 Y[#3 + #1]
  G1 X[#2 - #1]
  G1 Y[#3 - #1]
o<square> endsub
o<slot> sub                     (#1 x; a half-circle end when #2 is not zero)
  G0 X#1 Y0
  G1 Z#<_depth> F#<_feedrate>
  o<ends> if [#2]
    G1 Y10
    G3 X[#1 + 4] Y10 I2 J0
    G1 Y0
  o<ends> else
    G1 Y[10 / 2 ** 1]
  o<ends> endif
  G0 Z2
o<slot> endsub
G21 G90 G17 G91.1
G0 Z2
G0 X-10 Y-10
G1 Z#<_depth> F#<_feedrate>
#10 = 8
o100 while [#10 GT 0]
  o<square> call [#10] [0] [0]
  #10 = [#10 - 2.5]
o100 endwhile
G0 Z2
#<n> = 0
o200 repeat [3]
  o<slot> call [20 + #<n> * 8] [#<n> MOD 2 EQ 0]
  #<n> = [#<n> + 1]
o200 endrepeat
G0 X0 Y0
%
"""

HAND_EXPANDED = """%
(nc_files style: a pocket of concentric squares and a row of slots)
G21 G90 G17 G91.1
G0 Z2
G0 X-10 Y-10
G1 Z-1.5 F400
G1 X-8 Y-8
G1 X8
G1 Y8
G1 X-8
G1 Y-8
G1 X-5.5 Y-5.5
G1 X5.5
G1 Y5.5
G1 X-5.5
G1 Y-5.5
G1 X-3 Y-3
G1 X3
G1 Y3
G1 X-3
G1 Y-3
G1 X-0.5 Y-0.5
G1 X0.5
G1 Y0.5
G1 X-0.5
G1 Y-0.5
G0 Z2
G0 X20 Y0
G1 Z-1.5 F400
G1 Y10
G3 X24 Y10 I2 J0
G1 Y0
G0 Z2
G0 X28 Y0
G1 Z-1.5 F400
G1 Y5
G0 Z2
G0 X36 Y0
G1 Z-1.5 F400
G1 Y10
G3 X40 Y10 I2 J0
G1 Y0
G0 Z2
G0 X0 Y0
%
"""


def test_nc_files_style_program_equals_its_hand_expansion():
    out = expand(NC_FILES_STYLE, "pocket.ngc")
    assert [b.text.strip() for b in out.blocks] == HAND_EXPANDED.splitlines()
    assert out.ended and out.messages == []
    # hence the same path through the block parser
    moves = parse(out.text()).moves
    assert [(m.kind, m.start, m.end, m.center, m.cw, m.feed) for m in moves] == \
        [(m.kind, m.start, m.end, m.center, m.cw, m.feed) for m in parse(HAND_EXPANDED).moves]
    # each block keeps its original line: both slot arcs come from line 17
    assert [b.lineno for b in out.blocks if b.text.startswith("G3")] == [17, 17]


def test_bolt_circle_example():
    out = expand((EXAMPLES / "bolt_circle.ngc").read_text(), "bolt_circle.ngc")
    assert [(m.kind, m.text) for m in out.messages] == [("DEBUG", "6 holes on a 60 mm circle")]
    moves = parse(out.text()).moves
    arcs = [m for m in moves if m.kind == "arc"]
    assert len(arcs) == 6 and all(a.cw and a.start == a.end for a in arcs)
    for k, arc in enumerate(arcs):
        angle = math.radians(30 + 60 * k)
        assert arc.center == pytest.approx((30 * math.cos(angle), 30 * math.sin(angle)),
                                           abs=1e-12)
        assert math.dist(arc.start[:2], arc.center) == pytest.approx(4.0, abs=1e-12)
        assert arc.start[2] == -2 and arc.feed == 300
    assert moves[-1].end == (0.0, 0.0, 5.0)
    assert {b.lineno for b in out.blocks if b.text.startswith("G2 ")} == {10}


def test_blocks_stream_to_on_block_and_state_answers_system_parameters():
    """expand(on_block=, state=): each block reaches on_block before the next line runs, and
    a state object answers LinuxCNC's machine-state parameters (None: not tracked)."""
    seen = []

    class State:
        def numbered(self, n):
            return len(seen) * 10.0 if n == 5420 else None

        def named(self, name):
            return -1.0 if name == "_x" else None

    out = expand("G0 X1\nG0 X#5420\nG0 X[#<_x> + #5420]\nG0 Y#5221\nM2",
                 on_block=lambda block, expanded: seen.append(block.text), state=State())
    assert seen == ["G0 X1", "G0 X10", "G0 X19", "G0 Y0", "M2"]
    assert [b.text for b in out.blocks] == seen
    with pytest.raises(NgcError, match="line 1: #<_ccomp> is LinuxCNC machine"):
        expand("G0 X#<_ccomp>\nM2", state=State())
    # without a state the position is not tracked
    with pytest.raises(NgcError, match="#5420 is machine state"):
        expand("G0 X#5420\nM2")


# ------------------------------------------------------------------ program numbers

@pytest.mark.parametrize("head", [
    "O1000 (Example)\n",                        # LinuxCNC's o-code.adoc: "o1 (Example 1)"
    "%\nO08787 (HAAS PECK)\n(T1 D=6.35)\n",     # a Fanuc / Haas post's header
    "(header)\n\nN10 o12\n",
])
def test_program_number_as_first_block_is_accepted(head):
    """A bare O number as the main program's first block (after %, comments and
    blank lines) is its program number (LinuxCNC: Fanuc-style numbered programs,
    the optional main program block): no block, the program runs as without it.
    Until 2026-11-27 it was refused as an unknown O-word keyword, on a Haas post's
    output."""
    body = "G21 G90\nG0 X1 Y2\nM30\n"
    with_number = parse(expand(head + body).text()).moves
    assert [(m.kind, m.end) for m in with_number] == \
        [(m.kind, m.end) for m in parse(body).moves]


def test_program_number_elsewhere_is_an_error_naming_the_line(tmp_path):
    """A bare O number after the first block, or in a called file, would be a
    numbered subprogram (O100 ... M99, called by M98), which is not supported."""
    e = error("G21\nO100\nG0 X1\nM2")
    assert e.lineno == 2 and "program number is taken only as the main program's first" \
        in e.reason and "M98" in e.reason
    (tmp_path / "part.ngc").write_text("O7\no<part> sub\nG0 X1\no<part> endsub\nM2\n")
    e = error("o<part> call\nM2", search_path=[tmp_path])
    assert e.lineno == 1 and e.source.endswith("part.ngc")
    e = error("o<abc>\nG0 X1\nM2")              # a named O word still needs its keyword
    assert "unknown O-word keyword" in e.reason
