# SPDX-License-Identifier: Apache-2.0
"""RS274NGC interpreter front end: runs a LinuxCNC program's parameters,
expressions and O-word control flow, and hands the executed blocks on as plain
G-code for the block parser (``halfpoint.cam.gcode``).

``expand(text, source)`` returns an ``Expanded``: the executed blocks in order,
each with its original line number (and file, for a subroutine read from a
file in ``search_path``), with every expression and parameter reference
replaced by its number, and the messages of ``(MSG,`` ``(DEBUG,`` and
``(PRINT,`` comments in order.

What it supports, with LinuxCNC's semantics (G-code overview and O codes
chapters of the LinuxCNC manual):

* Numbered parameters ``#1``..``#5000``: global, zero until set; ``#1``-``#30``
  hold a subroutine's arguments, are restored when it returns, and arguments
  not given keep the caller's values.  Named local ``#<name>`` (one scope per
  call, plus the main program's) and global ``#<_name>`` parameters; names are
  lower case with blanks removed; reading a named parameter that does not exist
  is an error; ``EXISTS[#<name>]``.  Indirection ``##2``, ``#[#1 + 1]``.
* Expressions ``[ ]`` with the binary operators in LinuxCNC's precedence
  (``**``; ``* / MOD``; ``+ -``; ``EQ NE GT GE LT LE``; ``AND OR XOR``), left
  to right within a group; ``EQ``/``NE``/``GE``/``LE`` with LinuxCNC's
  tolerance of 1e-6; ``MOD`` never negative; logical results 1 or 0.  Unary
  ``-`` and ``+`` before any value (binding tighter than ``**``, as LinuxCNC).
  Functions ``ABS ACOS ASIN ATAN[a]/[b] COS EXP FIX FUP ROUND LN SIN SQRT TAN
  EXISTS``, angles in degrees, ``ROUND`` half away from zero.
* Parameter settings take effect after the line is read: every value on the
  line uses the values from before it; settings apply in order (the last of
  two settings of one parameter wins), before the line's ``(DEBUG,``.
* O-words, numbered ``o100`` or named ``o<name>``: ``sub``/``endsub``,
  ``call`` with up to 30 arguments ``[..]`` (also ``o[expr] call``),
  ``return`` and ``endsub`` with an optional value (``#<_value>``,
  ``#<_value_returned>``, cleared by the next call), ``if``/``elseif``/
  ``else``/``endif``, ``while``/``endwhile``, ``do``/``while``, ``repeat``/
  ``endrepeat`` (the count an integer within 0.0001; zero or less runs
  nothing), ``break``/``continue`` (of a ``while`` or ``do`` loop).
  ``o<name> call`` of a subroutine not in the program reads ``name.ngc`` from
  ``search_path`` (LinuxCNC's SUBROUTINE_PATH), which must define it.
* Messages: the last comment of a line is active (LinuxCNC's rule): ``(MSG,``
  as written; ``(DEBUG,`` and ``(PRINT,`` with ``#n``/``#<name>`` replaced by
  the value (``%lf`` six decimals by default; ``%d``, ``%f``, ``%.Nf`` change
  it; ``######`` for a parameter that does not exist); ``#5599 = 0`` turns
  DEBUG off.  The text of a message is stripped of surrounding blanks.
* Block delete: a line starting with ``/`` is skipped when ``block_delete``
  is on (the default, as LinuxCNC); otherwise the ``/`` is removed.
* The program ends at an executed M2 or M30 (inside a subroutine too) or at
  the closing ``%``; nothing after a closing ``%`` is read.
* Predefined read-only parameters: ``#<_value>``, ``#<_value_returned>``,
  ``#<_call_level>``, ``#<_line>``.  Machine state comes from ``state`` when
  the caller gives one (``halfpoint.cam.gcode.parse`` does: the block parser
  runs each block as it is emitted, through ``on_block``, so a line reads the
  state the blocks before it left): G28/G30 positions ``#5161``-``#5169`` and
  ``#5181``-``#5189``, G92 ``#5210``-``#5219``, the coordinate system in use
  ``#5220`` and the systems' offsets ``#5221``-``#5390``, the tool ``#5400``
  and its offsets ``#5401``-``#5409``, the position ``#5420``-``#5428``, and
  the named ``#<_x>``, ``#<_abs_x>``, ``#<_metric>``, ``#<_current_tool>``...
  (``halfpoint.cam.gcode`` lists them), all in the program's current units.
  Without ``state`` the system range ``#5161``-``#5390`` reads 0 except
  ``#5220`` = 1 (G54, every offset zero).

Where this differs from LinuxCNC (the refusals are errors naming the line):

* Machine state the block parser does not track (probe results, pockets,
  overrides, INI and HAL values; without ``state`` also position, modal state
  and tool) is an error to read, and ``EXISTS`` of an INI or HAL name gives 0.
  Writing a numbered parameter above ``#5000`` (offsets, homes) is an error.
* ``MOD`` by zero is an error (LinuxCNC yields a NaN, then fails later).
* The whole file is checked for O-word structure before it runs (an
  ``o101 if`` without ``endif`` is an error even where it is not reached);
  a subroutine may be called before its definition in the file (LinuxCNC
  finds it by skipping ahead the same way).  Subroutine definitions must be
  at the top level of a file.  An O-word line may carry ordinary comments but
  no other words and no message (LinuxCNC leaves both undefined).
* ``(LOG,``, ``(LOGOPEN,``, ``(LOGAPPEND,``, ``(LOGCLOSE)``, ``(PROBEOPEN``,
  ``(PROBECLOSE)`` are refused (they write files).  Fanuc-style ``O100``
  programs with ``M98``/``M99`` are not supported; a bare ``O1000 (title)`` as
  the main program's first block (after ``%``, comments and blank lines) is
  its program number, as in LinuxCNC, and yields no block.
* Limits: subroutine calls nest at most ``max_depth`` deep (10, LinuxCNC's
  limit); at most ``max_iterations`` loop iterations run in the whole program
  (1 000 000; LinuxCNC has no limit), an error naming the loop's line.

Output text: a line without parameters, expressions or O-words passes through
unchanged (the block parser sees today's programs exactly as before; only a
``/`` is removed when block delete is off).  Other lines are rewritten as
their words, upper case, one space apart, each value written with ``repr``'s
shortest round-trip digits (never an exponent), then the line's comments as
written; parameter settings are removed, and a line left without words
yields no block.  O-word lines yield no block.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass, field
from decimal import Decimal
from pathlib import Path
from typing import Callable, Mapping, Sequence

from .gcode import GcodeError

MAX_DEPTH = 10                  # LinuxCNC's subroutine nesting limit
MAX_ITERATIONS = 1_000_000      # loop iterations in a whole program
TOLERANCE_EQUAL = 1e-6          # LinuxCNC's TOLERANCE_EQUAL for EQ NE GE LE
INTEGER_CLOSE = 1e-4            # "close enough to an integer" (parameter numbers)
USER_PARAMETERS = 5000          # #1..#5000 are read/write
NUM_PARAMETERS = 5602           # LinuxCNC's RS274NGC_MAX_PARAMETERS

# LinuxCNC's predefined named parameters (read-only); those in _SUPPORTED have values here
_PREDEFINED = set("""
_vmajor _vminor _line _motion_mode _plane _ccomp _metric _imperial _absolute _incremental
_inverse_time _units_per_minute _units_per_rev _coord_system _tool_offset _retract_r_plane
_retract_old_z _spindle_rpm_mode _spindle_css_mode _ijk_absolute_mode _lathe_diameter_mode
_lathe_radius_mode _spindle_on _spindle_cw _mist _flood _speed_override _feed_override
_adaptive_feed _feed_hold _feed _rpm _x _y _z _a _b _c _u _v _w _abs_x _abs_y _abs_z _abs_a
_abs_b _abs_c _abs_u _abs_v _abs_w _current_tool _current_pocket _selected_tool
_selected_pocket _value _value_returned _task _call_level _remap_level
""".split())
_SUPPORTED = {"_value", "_value_returned", "_call_level", "_line"}

_KEYWORDS = ("endsub", "endif", "endwhile", "endrepeat", "elseif", "else", "sub", "call",
             "return", "if", "while", "do", "repeat", "break", "continue")
_NEEDS_VALUE = {"if", "elseif", "while", "repeat"}
_MAY_VALUE = {"return", "endsub"}
_OPENERS = {"if": "endif", "while": "endwhile", "do": "while", "repeat": "endrepeat",
            "sub": "endsub"}

_BINARY = {  # operator -> precedence (5 binds tightest)
    "**": 5, "*": 4, "/": 4, "mod": 4, "+": 3, "-": 3,
    "eq": 2, "ne": 2, "gt": 2, "ge": 2, "lt": 2, "le": 2, "and": 1, "or": 1, "xor": 1,
}
_OPERATOR_ORDER = ("**", "*", "/", "+", "-", "mod", "eq", "ne", "gt", "ge", "lt", "le",
                   "and", "or", "xor")
_FUNCTIONS = {"abs", "acos", "asin", "atan", "cos", "exp", "exists", "fix", "fup", "ln",
              "round", "sin", "sqrt", "tan"}
_ACTIVE = re.compile(r"\s*(msg|debug|print|logopen|logappend|logclose|log|probeopen|"
                     r"probeclose)\b\s*(,?)", re.IGNORECASE)
_NUMBER = re.compile(r"\d+\.?\d*|\.\d+")


class NgcError(GcodeError):
    """An error in a program's parameters, expressions or control flow; names the
    line, the file when it is not the main program, and the offending token."""

    def __init__(self, lineno: int, reason: str, source: str = ""):
        super().__init__(lineno, reason)
        self.source = source
        if source:
            self.args = (f"{source}: line {lineno}: {reason}",)


@dataclass(frozen=True, slots=True)
class Block:
    """One executed block: its text for the block parser and where it came from."""

    lineno: int
    text: str
    source: str = ""             # "" for the main program, else the subroutine file


@dataclass(frozen=True, slots=True)
class Message:
    kind: str                    # "MSG", "DEBUG" or "PRINT"
    text: str
    lineno: int
    source: str = ""


@dataclass
class Expanded:
    blocks: list[Block] = field(default_factory=list)
    messages: list[Message] = field(default_factory=list)
    ended: bool = False          # an M2/M30 or the closing % was executed
    line_count: int = 0          # lines in the main program's text
    opening: int = 0             # line of the opening % (the first non-blank line), or 0

    def text(self) -> str:
        """The blocks' text, one a line (their line numbers are lost)."""
        return "".join(b.text + "\n" for b in self.blocks)


def format_number(value: float) -> str:
    """Shortest text that reads back as exactly ``value``, without an exponent."""
    text = repr(float(value))
    if "e" in text or "E" in text:
        text = format(Decimal(text), "f")
    if text.endswith(".0"):
        text = text[:-2]
    return text


# --------------------------------------------------------------------------- lines

@dataclass(eq=False)
class _Line:
    lineno: int
    source: str                  # "" for the main program
    raw: str
    kind: str = "plain"          # plain, code, oword, percent, blank
    text: str = ""               # the raw line without a block-delete "/"
    comments: list[str] = field(default_factory=list)
    active: tuple[str, str] | None = None
    items: list = field(default_factory=list)
    stops: bool = False          # a plain line with M2 or M30
    error: NgcError | None = None   # deferred until the line runs
    # O-word lines
    oname: str = ""
    oname_value: Callable | None = None
    keyword: str = ""
    args: list = field(default_factory=list)

    def fail(self, reason: str) -> NgcError:
        return NgcError(self.lineno, reason, self.source)

    @property
    def label(self) -> str:
        return f"{self.oname} {self.keyword}"


def _split_comments(text: str, line: _Line) -> tuple[str, list[str]]:
    """Code outside comments, and the comments as written (``(..)`` and ``;..``)."""
    code, comments, i = [], [], 0
    while i < len(text):
        ch = text[i]
        if ch == ";":
            comments.append(text[i:])
            break
        if ch == "(":
            j = text.find(")", i + 1)
            if j < 0:
                raise line.fail(f"comment '(' is not closed on this line: {text[i:i + 20]!r}")
            if "(" in text[i + 1:j]:
                raise line.fail(f"nested comments are not allowed: {text[i:j + 1]!r}")
            comments.append(text[i:j + 1])
            code.append(" ")
            i = j + 1
            continue
        if ch == ")":
            raise line.fail("')' without '('")
        code.append(ch)
        i += 1
    return "".join(code), comments


def _active_comment(comments: list[str], line: _Line) -> tuple[str, str] | None:
    if not comments:
        return None
    last = comments[-1]
    body = last[1:-1] if last.startswith("(") else last[1:]
    m = _ACTIVE.match(body)
    if not m:
        return None
    kind = m.group(1).upper()
    rest = body[m.end():]
    if kind not in ("MSG", "DEBUG", "PRINT"):
        if m.group(2) or kind == "PROBEOPEN" or not rest.strip():
            raise line.fail(f"{last!r}: LinuxCNC's {kind} comments write files; not supported")
        return None
    if not m.group(2):
        return None              # "(debug this)" is an ordinary comment
    return kind, rest


class _Reader:
    """Recursive-descent reader of one line's code, lower case without blanks,
    into closures ``f(interp) -> float``."""

    def __init__(self, code: str, line: _Line):
        self.s = code
        self.pos = 0
        self.line = line

    def fail(self, reason: str, at: int | None = None) -> NgcError:
        at = self.pos if at is None else at
        rest = self.s[at:at + 16]
        where = f" at {rest!r}" if rest else " at the end of the line"
        return self.line.fail(f"{reason}{where} (in {self.s!r})")

    def peek(self) -> str:
        return self.s[self.pos] if self.pos < len(self.s) else ""

    def expect(self, ch: str, what: str):
        if self.peek() != ch:
            raise self.fail(f"expected {ch!r} {what}")
        self.pos += 1

    # values
    def real_value(self) -> Callable:
        c = self.peek()
        nxt = self.s[self.pos + 1:self.pos + 2]
        if c == "[":
            return self.expression()
        if c == "#":
            return self.parameter()
        if c and c in "+-" and nxt and not (nxt.isdigit() or nxt == "."):
            self.pos += 1
            inner = self.real_value()
            return (lambda it: -inner(it)) if c == "-" else inner
        if c.isascii() and c.isalpha():
            return self.function()
        m = re.compile(r"[+-]?(?:\d+\.?\d*|\.\d+)").match(self.s, self.pos)
        if not m:
            raise self.fail("expected a number, parameter or expression")
        self.pos = m.end()
        value = float(m.group())
        return lambda it: value

    def expression(self) -> Callable:
        start = self.pos
        self.expect("[", "to open an expression")
        node = self.binary(1)
        if self.peek() != "]":
            if self.pos >= len(self.s):
                raise self.fail("unbalanced '[': no ']'", start)
            raise self.fail("expected a binary operator or ']'")
        self.pos += 1
        return node

    def operator(self) -> str | None:
        for op in _OPERATOR_ORDER:
            if self.s.startswith(op, self.pos):
                return op
        return None

    def binary(self, level: int) -> Callable:
        left = self.binary(level + 1) if level < 5 else self.real_value()
        while True:
            op = self.operator()
            if op is None or _BINARY[op] != level:
                return left
            at = self.pos
            self.pos += len(op)
            right = self.binary(level + 1) if level < 5 else self.real_value()
            left = _binary(op, left, right, self, at)

    def function(self) -> Callable:
        m = re.compile(r"[a-z]+").match(self.s, self.pos)
        name = m.group()
        if name not in _FUNCTIONS:
            raise self.fail(f"unknown function {name.upper()!r}")
        self.pos = m.end()
        if self.peek() != "[":
            raise self.fail(f"expected '[' after {name.upper()}")
        if name == "exists":
            self.pos += 1
            if not self.s.startswith("#<", self.pos):
                raise self.fail("EXISTS takes one named parameter, EXISTS[#<name>]")
            pname = self.name()
            self.expect("]", "to close EXISTS[")
            return lambda it: 1.0 if it.exists(pname) else 0.0
        arg = self.expression()
        if name == "atan":
            self.expect("/", "after ATAN[y] (ATAN[y]/[x])")
            if self.peek() != "[":
                raise self.fail("expected '[' after ATAN[y]/ (ATAN[y]/[x])")
            arg2 = self.expression()
            return lambda it: _check(math.degrees(math.atan2(arg(it), arg2(it))), self.line)
        return _unary(name, arg, self.line)

    def name(self) -> str:
        """``#<name>`` at pos -> the normalised name."""
        end = self.s.find(">", self.pos + 2)
        if end < 0:
            raise self.fail("named parameter without '>'")
        pname = self.s[self.pos + 2:end]
        if not pname:
            raise self.fail("empty parameter name")
        self.pos = end + 1
        return pname

    def parameter(self) -> Callable:
        """A parameter read: ``#<name>``, ``#n``, ``#[expr]``, ``##n``."""
        if self.s.startswith("#<", self.pos):
            pname = self.name()
            line = self.line
            return lambda it: it.get_named(pname, line)
        self.pos += 1
        index = self.real_value()
        line = self.line
        return lambda it: it.get_numbered(_index(index(it), line), line)

    def target(self) -> tuple[str, object]:
        """The left side of a parameter setting."""
        if self.s.startswith("#<", self.pos):
            return "named", self.name()
        self.pos += 1
        return "numbered", self.real_value()

    # a whole line
    def line_items(self) -> list:
        items = []
        while self.pos < len(self.s):
            c = self.peek()
            if c == "#":
                kind, what = self.target()
                self.expect("=", "in a parameter setting")
                items.append(("set", kind, what, self.real_value()))
            elif c == "n" and not items:
                m = re.compile(r"n(\d+(?:\.\d+)?)").match(self.s, self.pos)
                if not m:
                    raise self.fail("line number N needs an unsigned integer")
                items.append(("n", "N" + m.group(1)))
                self.pos = m.end()
            elif c == "o":
                raise self.fail("an O-word must be the first item on its line")
            elif c.isascii() and c.isalpha():
                self.pos += 1
                items.append(("word", c.upper(), self.real_value()))
            else:
                raise self.fail("unexpected character")
        return items

    def oword(self):
        """``o<name>|o123|o[expr] keyword [args]`` -> (name, value-closure, keyword, args)."""
        self.pos += 1
        name, value = "", None
        c = self.peek()
        if c == "<":
            end = self.s.find(">", self.pos)
            if end < 0 or end == self.pos + 1:
                raise self.fail("O-word name needs '<name>'")
            name = f"o<{self.s[self.pos + 1:end]}>"
            self.pos = end + 1
        elif c.isdigit():
            m = re.compile(r"\d+").match(self.s, self.pos)
            name = f"o{int(m.group())}"
            self.pos = m.end()
        elif c in "[#":
            value = self.real_value()
        else:
            raise self.fail("O-word needs a number, <name> or [expression]")
        keyword = next((k for k in _KEYWORDS if self.s.startswith(k, self.pos)), None)
        if keyword is None and name[1:].isdigit() and self.pos == len(self.s):
            # a number alone: a Fanuc-style program block (its use is checked by
            # _structure: the main program's number, as its first block)
            return name, value, "program", []
        if keyword is None:
            raise self.fail("unknown O-word keyword (sub, endsub, call, return, if, elseif, "
                            "else, endif, while, endwhile, do, repeat, endrepeat, break, "
                            "continue)")
        self.pos += len(keyword)
        if value is not None and keyword != "call":
            raise self.fail(f"a computed O-word is supported with call only, not {keyword}")
        args = []
        if keyword == "call":
            while self.peek() == "[":
                args.append(self.expression())
            if len(args) > 30:
                raise self.fail("a call takes at most 30 arguments")
        elif keyword in _NEEDS_VALUE:
            if self.peek() != "[":
                raise self.fail(f"{keyword} needs a condition or count in [ ]")
            args.append(self.expression())
        elif keyword in _MAY_VALUE and self.peek() == "[":
            args.append(self.expression())
        if self.pos < len(self.s):
            raise self.fail(f"unexpected text after the O-word {keyword}")
        return name, value, keyword, args


def _check(value: float, line: _Line) -> float:
    if math.isnan(value):
        raise line.fail("calculation resulted in 'not a number'")
    if math.isinf(value):
        raise line.fail("calculation resulted in infinity")
    return value


def _index(value: float, line: _Line) -> int:
    n = round(value)
    if abs(value - n) > INTEGER_CLOSE:
        raise line.fail(f"parameter number {format_number(value)} is not an integer")
    return n


def _binary(op: str, left: Callable, right: Callable, reader: _Reader, at: int) -> Callable:
    line = reader.line
    token = reader.s[at:at + 16]

    def divide(a, b):
        if b == 0.0:
            raise line.fail(f"division by zero at {token!r}")
        return a / b

    def modulo(a, b):
        if b == 0.0:
            raise line.fail(f"MOD by zero at {token!r}")
        r = math.fmod(a, b)
        return r + abs(b) if r < 0.0 else r

    def power(a, b):
        if a < 0.0 and math.floor(b) != b:
            raise line.fail(f"negative number raised to a non-integer power at {token!r}")
        try:
            return math.pow(a, b)
        except (OverflowError, ValueError):
            raise line.fail(f"calculation out of range at {token!r}") from None

    ops = {
        "**": power, "*": lambda a, b: a * b, "/": divide, "mod": modulo,
        "+": lambda a, b: a + b, "-": lambda a, b: a - b,
        "eq": lambda a, b: 1.0 if abs(a - b) < TOLERANCE_EQUAL else 0.0,
        "ne": lambda a, b: 1.0 if abs(a - b) >= TOLERANCE_EQUAL else 0.0,
        "gt": lambda a, b: 1.0 if a > b else 0.0,
        "ge": lambda a, b: 1.0 if a >= b or abs(a - b) < TOLERANCE_EQUAL else 0.0,
        "lt": lambda a, b: 1.0 if a < b else 0.0,
        "le": lambda a, b: 1.0 if a <= b or abs(a - b) < TOLERANCE_EQUAL else 0.0,
        "and": lambda a, b: 0.0 if a == 0.0 or b == 0.0 else 1.0,
        "or": lambda a, b: 1.0 if a != 0.0 or b != 0.0 else 0.0,
        "xor": lambda a, b: 1.0 if (a == 0.0) != (b == 0.0) else 0.0,
    }
    fn = ops[op]
    return lambda it: _check(fn(left(it), right(it)), line)


def _unary(name: str, arg: Callable, line: _Line) -> Callable:
    def domain(test, what):
        def f(x):
            if not test(x):
                raise line.fail(f"{what} ({name.upper()}[{format_number(x)}])")
            return x
        return f

    def rounded(x):
        return float(math.floor(x + 0.5) if x >= 0 else math.ceil(x - 0.5))

    def exp(x):
        try:
            return math.exp(x)
        except OverflowError:
            raise line.fail(f"EXP[{format_number(x)}] is out of range") from None

    unit = domain(lambda x: -1.0 <= x <= 1.0, "argument out of range -1..1")
    fns = {
        "abs": abs,
        "acos": lambda x: math.degrees(math.acos(unit(x))),
        "asin": lambda x: math.degrees(math.asin(unit(x))),
        "cos": lambda x: math.cos(math.radians(x)),
        "sin": lambda x: math.sin(math.radians(x)),
        "tan": lambda x: math.tan(math.radians(x)),
        "exp": exp,
        "fix": lambda x: float(math.floor(x)),
        "fup": lambda x: float(math.ceil(x)),
        "round": rounded,
        "ln": lambda x: math.log(domain(lambda v: v > 0.0, "zero or negative argument")(x)),
        "sqrt": lambda x: math.sqrt(domain(lambda v: v >= 0.0, "negative argument")(x)),
    }
    fn = fns[name]
    return lambda it: _check(fn(arg(it)), line)


def _lex(raw: str, lineno: int, source: str, block_delete: bool) -> _Line:
    """Read one line; syntax errors of lines that are not O-words are deferred."""
    line = _Line(lineno, source, raw)
    stripped = raw.strip()
    text = raw
    if stripped.startswith("/"):
        if block_delete:
            line.kind = "blank"
            return line
        text = raw.replace("/", "", 1)
    line.text = text
    if not text.strip():
        line.kind = "blank"
        return line
    if re.fullmatch(r"%\d*", text.strip()):
        line.kind = "percent"
        return line
    try:
        code, line.comments = _split_comments(text, line)
        squeezed = re.sub(r"\s+", "", code).lower()
        is_oword = re.match(r"(n\d+(\.\d+)?)?o", squeezed) is not None
        if is_oword:
            line.kind = "oword"
            reader = _Reader(re.sub(r"^n\d+(\.\d+)?", "", squeezed), line)
            line.oname, line.oname_value, line.keyword, line.args = reader.oword()
            if line.oname_value is not None:
                line.oname = "o[..]"
            if _active_comment(line.comments, line):
                raise line.fail("a message comment on an O-word line is not supported "
                                "(LinuxCNC leaves it undefined)")
            return line
        line.active = _active_comment(line.comments, line)
        if "#" in squeezed or "[" in squeezed or "o" in squeezed:
            line.kind = "code"
            line.items = _Reader(squeezed, line).line_items()
            return line
    except NgcError as exc:
        if line.kind == "oword":
            raise
        line.kind = "code"
        line.error = exc
        return line
    try:                          # plain: find M2/M30; the block parser reports bad text
        items = _Reader(squeezed, line).line_items()
        line.stops = any(i[0] == "word" and i[1] == "M" and round(i[2](None), 1) in (2, 30)
                         for i in items)
    except NgcError:
        line.stops = False
    return line


# --------------------------------------------------------------------------- structure

@dataclass(eq=False)
class _Open:
    kind: str
    name: str
    line: _Line
    body: list = field(default_factory=list)
    branches: list = field(default_factory=list)     # if: [(line, body)]
    else_body: list | None = None


@dataclass(eq=False)
class _Sub:
    name: str
    line: _Line
    body: list
    end: _Line


def _comment_only(line: _Line) -> bool:
    """A line of comments alone (no words, no settings)."""
    if line.kind != "plain":
        return False
    try:
        code, _ = _split_comments(line.text, line)
    except NgcError:
        return False
    return not code.strip()


def _structure(lines: list[_Line], subs: dict[str, _Sub]) -> list:
    """O-word structure of one file -> its top-level statements; subs registered."""
    top = _Open("top", "", lines[0] if lines else _Line(0, "", ""))
    stack = [top]

    def mismatch(line: _Line, expected: str):
        inner = stack[-1]
        if inner.kind == "top" or all(o.name != line.oname for o in stack[1:]):
            raise line.fail(f"{line.label} without {line.oname} {expected}")
        raise line.fail(f"{line.label} does not match the open {inner.name} {inner.kind} "
                        f"(line {inner.line.lineno})")

    before_code = True              # no block read yet but %, comments and blank lines
    for line in lines:
        if line.kind != "oword":
            if line.kind != "blank":
                stack[-1].body.append(("line", line))
                before_code = before_code and (line.kind == "percent" or _comment_only(line))
            continue
        kw, name, inner = line.keyword, line.oname, stack[-1]
        if kw == "program":
            # LinuxCNC's optional main program block, "o1 (Title)" (o-code.adoc,
            # Fanuc-style numbered programs): the program's number, no block.  A
            # numbered subprogram (O100 ... M99, called by M98) is not supported.
            if not (before_code and line.source == ""):
                raise line.fail(f"{name} without a keyword: a program number is taken only as "
                                "the main program's first block; numbered subprograms "
                                "(O100 ... M99, M98 calls) are not supported")
            before_code = False
            continue
        before_code = False
        if kw == "sub":
            if inner.kind != "top":
                raise line.fail(f"{line.label} inside {inner.name} {inner.kind} (line "
                                f"{inner.line.lineno}): subroutine definitions are not nested")
            if name in subs:
                raise line.fail(f"{name} is defined twice (line {subs[name].line.lineno} and "
                                f"line {line.lineno})")
            stack.append(_Open("sub", name, line))
        elif kw in ("if", "repeat", "do") or (kw == "while" and not (
                inner.kind == "do" and inner.name == name)):
            opened = _Open(kw, name, line)
            if kw == "if":
                opened.branches.append((line, opened.body))
            stack.append(opened)
        elif kw == "while":          # closes a do
            stack.pop()
            stack[-1].body.append(("do", inner.line, inner.body, line))
        elif kw in ("elseif", "else"):
            if inner.kind != "if" or inner.name != name:
                mismatch(line, "if")
            if inner.else_body is not None:
                raise line.fail(f"{line.label} after {name} else (line "
                                f"{inner.branches[-1][0].lineno})")
            inner.body = []
            if kw == "else":
                inner.else_body = inner.body
            inner.branches.append((line, inner.body))
        elif kw in ("endif", "endwhile", "endrepeat", "endsub"):
            opener = {"endif": "if", "endwhile": "while", "endrepeat": "repeat",
                      "endsub": "sub"}[kw]
            if inner.kind != opener or inner.name != name:
                mismatch(line, opener)
            stack.pop()
            if kw == "endsub":
                subs[name] = _Sub(name, inner.line, inner.body, line)
            elif kw == "endif":
                conds = [(ln, body) for ln, body in inner.branches if ln.keyword != "else"]
                stack[-1].body.append(("if", conds, inner.else_body))
            else:
                stack[-1].body.append((opener, inner.line, inner.body, line))
        elif kw in ("break", "continue"):
            loop = None
            for opened in reversed(stack):
                if opened.kind in ("sub", "top"):
                    break
                if opened.name == name:
                    loop = opened
                    break
            if loop is None or loop.kind not in ("while", "do"):
                raise line.fail(f"{line.label} is not inside a {name} while or do loop")
            stack[-1].body.append((kw, line))
        elif kw == "return":
            sub = next((o for o in stack if o.kind == "sub"), None)
            if sub is None or sub.name != name:
                raise line.fail(f"{line.label} outside {name} sub")
            stack[-1].body.append(("return", line))
        elif kw == "call":
            stack[-1].body.append(("call", line))
    if len(stack) > 1:
        inner = stack[-1]
        raise inner.line.fail(f"{inner.name} {inner.kind} has no {inner.name} "
                              f"{_OPENERS[inner.kind]}")
    return top.body


# --------------------------------------------------------------------------- running

class _End(Exception):
    pass


class _Break(Exception):
    def __init__(self, name):
        self.name = name


class _Continue(Exception):
    def __init__(self, name):
        self.name = name


class _Return(Exception):
    def __init__(self, value):
        self.value = value


@dataclass(eq=False)
class _Frame:
    sub: _Sub | None
    local: dict[str, float] = field(default_factory=dict)
    call_line: _Line | None = None


class _Interpreter:
    def __init__(self, source: str, block_delete: bool, search_path: Sequence,
                 max_depth: int, max_iterations: int, on_block=None, state=None):
        self.source = source
        self.on_block = on_block
        self.state = state
        self.block_delete = block_delete
        self.search_path = [Path(p) for p in search_path]
        self.max_depth = max_depth
        self.max_iterations = max_iterations
        self.iterations = 0
        self.numbered = [0.0] * (NUM_PARAMETERS + 1)
        self.numbered[5599] = 1.0      # DEBUG output on (LinuxCNC's default)
        self.globals: dict[str, float] = {}
        self.value = 0.0
        self.value_returned = 0.0
        self.frames = [_Frame(None)]
        self.subs: dict[str, _Sub] = {}
        self.files_read: set[str] = set()
        self.out = Expanded()
        self.opening = 0          # line number of the main program's opening %, or 0

    # parameters
    def get_numbered(self, n: int, line: _Line) -> float:
        if 1 <= n <= USER_PARAMETERS:
            return self.numbered[n]
        if self.state is not None:
            value = self.state.numbered(n)
            if value is not None:
                return float(value)
        if 5161 <= n <= 5390:
            return 1.0 if n == 5220 else 0.0
        if n == 5599:
            return self.numbered[n]
        if 1 <= n <= NUM_PARAMETERS:
            raise line.fail(f"parameter #{n} is machine state (position, tool, probe or "
                            f"input) that halfpoint does not provide")
        raise line.fail(f"parameter number #{n} is out of range (1..{NUM_PARAMETERS})")

    def set_numbered(self, n: int, value: float, line: _Line):
        if 1 <= n <= USER_PARAMETERS or n == 5599:
            self.numbered[n] = value
        elif 1 <= n <= NUM_PARAMETERS:
            raise line.fail(f"parameter #{n} is a LinuxCNC system parameter (offsets, homes, "
                            f"machine state); halfpoint does not model it, only #1..#"
                            f"{USER_PARAMETERS} may be set")
        else:
            raise line.fail(f"parameter number #{n} is out of range (1..{NUM_PARAMETERS})")

    def predefined(self, name: str, line: _Line) -> float | None:
        if name == "_value":
            return self.value
        if name == "_value_returned":
            return self.value_returned
        if name == "_call_level":
            return float(len(self.frames) - 1)
        if name == "_line":
            return float(line.lineno)
        return None

    def exists(self, name: str) -> bool:
        if name.startswith("_"):
            return name in self.globals or name in _PREDEFINED
        return name in self.frames[-1].local

    def get_named(self, name: str, line: _Line) -> float:
        if self.state is not None and name in _PREDEFINED and name not in _SUPPORTED:
            value = self.state.named(name)
            if value is not None:
                return float(value)
        if name in _SUPPORTED:
            return self.predefined(name, line)
        if name in _PREDEFINED or name.startswith(("_ini[", "_hal[")):
            raise line.fail(f"#<{name}> is LinuxCNC machine or configuration state that "
                            f"halfpoint's interpreter does not track")
        scope = self.globals if name.startswith("_") else self.frames[-1].local
        if name not in scope:
            raise line.fail(f"named parameter #<{name}> is not defined")
        return scope[name]

    def set_named(self, name: str, value: float, line: _Line):
        if name in _PREDEFINED or name.startswith(("_ini[", "_hal[")):
            raise line.fail(f"#<{name}> is a read-only predefined parameter")
        scope = self.globals if name.startswith("_") else self.frames[-1].local
        scope[name] = value

    # reading files
    def read_file(self, text: str, source: str, main: bool) -> list:
        lines = []
        raw_lines = text.splitlines()
        first = next((k for k, ln in enumerate(raw_lines) if ln.strip()), None)
        percent = (main and first is not None
                   and re.fullmatch(r"%\d*", raw_lines[first].strip()) is not None)
        for idx, raw in enumerate(raw_lines):
            line = _lex(raw, idx + 1, source, self.block_delete)
            if not main and line.kind == "percent":
                continue
            lines.append(line)
            if percent and idx != first and raw.strip() == "%":
                break            # nothing after the closing % is read
        if main:
            self.out.line_count = len(raw_lines)
            self.opening = self.out.opening = first + 1 if percent else 0
        return _structure(lines, self.subs)

    def find_sub(self, name: str, line: _Line) -> _Sub:
        if name in self.subs:
            return self.subs[name]
        stem = name[2:-1] if name.startswith("o<") else name[1:]
        for folder in self.search_path:
            path = folder / f"{stem.lower()}.ngc"
            if path.is_file() and str(path) not in self.files_read:
                self.files_read.add(str(path))
                self.read_file(path.read_text(encoding="utf-8"), str(path), main=False)
                if name not in self.subs:
                    raise line.fail(f"{path} does not define {name} sub")
                return self.subs[name]
        where = (f" nor {stem.lower()}.ngc in the search path"
                 f" ({', '.join(map(str, self.search_path))})" if self.search_path else "")
        raise line.fail(f"{name} call: no such subroutine in this program{where}")

    # running
    def iteration(self, body: list, line) -> bool:
        """One pass of a loop's body; False when a ``break`` of this loop ended it
        (a ``continue`` of this loop just ends the pass)."""
        try:
            self.run(body)
        except _Break as exc:
            if exc.name != line.oname:
                raise
            return False
        except _Continue as exc:
            if exc.name != line.oname:
                raise
        return True

    def run(self, body: list):
        for statement in body:
            kind = statement[0]
            if kind == "line":
                self.execute(statement[1])
            elif kind == "if":
                for cond_line, branch in statement[1]:
                    if self.condition(cond_line):
                        self.run(branch)
                        break
                else:
                    if statement[2] is not None:
                        self.run(statement[2])
            elif kind == "while":
                _, line, loop_body, _end = statement
                while self.condition(line):
                    self.count(line)
                    if not self.iteration(loop_body, line):
                        break
            elif kind == "do":
                _, line, loop_body, while_line = statement
                while True:
                    self.count(line)
                    if not self.iteration(loop_body, line) or not self.condition(while_line):
                        break
            elif kind == "repeat":
                _, line, loop_body, _end = statement
                count = self.evaluate(line.args[0], line)
                times = round(count)
                if abs(count - times) > INTEGER_CLOSE:
                    raise line.fail(f"{line.label} count {format_number(count)} is not an "
                                    f"integer")
                for _ in range(max(times, 0)):
                    self.count(line)
                    self.run(loop_body)
            elif kind == "break":
                raise _Break(statement[1].oname)
            elif kind == "continue":
                raise _Continue(statement[1].oname)
            elif kind == "return":
                line = statement[1]
                raise _Return(self.evaluate(line.args[0], line) if line.args else None)
            elif kind == "call":
                self.call(statement[1])

    def evaluate(self, fn: Callable, line: _Line) -> float:
        return fn(self)

    def condition(self, line: _Line) -> bool:
        return self.evaluate(line.args[0], line) != 0.0

    def count(self, line: _Line):
        self.iterations += 1
        if self.iterations > self.max_iterations:
            raise line.fail(f"{line.label}: more than {self.max_iterations} loop iterations in "
                            f"this program (the limit; a loop that never ends?)")

    def call(self, line: _Line):
        if line.oname_value is not None:
            n = self.evaluate(line.oname_value, line)
            number = round(n)
            if abs(n - number) > INTEGER_CLOSE or number < 0:
                raise line.fail(f"computed O-word number {format_number(n)} is not a "
                                f"non-negative integer")
            name = f"o{number}"
        else:
            name = line.oname
        args = [self.evaluate(a, line) for a in line.args]
        sub = self.find_sub(name, line)
        if len(self.frames) > self.max_depth:
            raise line.fail(f"{name} call: subroutine calls nested deeper than "
                            f"{self.max_depth} (the limit)")
        self.value, self.value_returned = 0.0, 0.0
        saved = self.numbered[1:31]
        for k, v in enumerate(args, start=1):
            self.numbered[k] = v
        self.frames.append(_Frame(sub, call_line=line))
        try:
            try:
                self.run(sub.body)
                end = sub.end
                result = self.evaluate(end.args[0], end) if end.args else None
            except _Return as ret:
                result = ret.value
        except NgcError as exc:
            if not getattr(exc, "_called_from", False):
                exc._called_from = True
                place = f" of {line.source}" if line.source else ""
                reason = f"{exc.reason} (in {name}, called at line {line.lineno}{place})"
                exc.reason = reason
                exc.args = ((f"{exc.source}: " if exc.source else "")
                            + f"line {exc.lineno}: {reason}",)
            raise
        finally:
            self.frames.pop()
            self.numbered[1:31] = saved
        self.value = 0.0 if result is None else result
        self.value_returned = 0.0 if result is None else 1.0

    def execute(self, line: _Line):
        if line.kind == "percent":
            self.emit(line, line.text.strip())
            if self.opening and line.lineno != self.opening and line.text.strip() == "%":
                raise _End
            return
        if line.error is not None:
            raise line.error
        if line.kind == "plain":
            self.emit(line, line.text)
            self.message(line)
            if line.stops:
                raise _End
            return
        parts, settings, stops = [], [], False
        for item in line.items:
            if item[0] == "n":
                parts.append(item[1])
            elif item[0] == "word":
                value = item[2](self)
                parts.append(item[1] + format_number(value))
                stops = stops or (item[1] == "M" and round(value, 1) in (2, 30))
            else:
                _, kind, what, fn = item
                target = _index(what(self), line) if kind == "numbered" else what
                settings.append((kind, target, fn(self)))
        for kind, target, value in settings:
            if kind == "numbered":
                self.set_numbered(target, value, line)
            else:
                self.set_named(target, value, line)
        if parts:
            self.emit(line, " ".join(parts + line.comments))
        self.message(line)
        if stops:
            raise _End

    def emit(self, line: _Line, text: str):
        block = Block(line.lineno, text, line.source)
        self.out.blocks.append(block)
        if self.on_block is not None:
            self.on_block(block, self.out)

    def message(self, line: _Line):
        if line.active is None:
            return
        kind, text = line.active
        if kind == "DEBUG" and self.numbered[5599] == 0.0:
            return
        if kind != "MSG":
            text = self.substitute(text, line)
        self.out.messages.append(Message(kind, text.strip(), line.lineno, line.source))

    def substitute(self, text: str, line: _Line) -> str:
        """LinuxCNC's comment parameters: ``#n`` and ``#<name>`` -> value."""
        out, i, decimals = [], 0, 6
        while i < len(text):
            ch = text[i]
            if ch == "%":
                m = re.compile(r"%(?:(d)|(lf)|(f)|\.(\d)f)").match(text, i)
                if m:
                    decimals = (0 if m.group(1) else 6 if m.group(2) else 4 if m.group(3)
                                else int(m.group(4)))
                    i = m.end()
                    continue
            elif ch == "#":
                value, end = None, None
                if text.startswith("#<", i) and text.find(">", i) > 0:
                    end = text.find(">", i) + 1
                    name = re.sub(r"\s+", "", text[i + 2:end - 1]).lower()
                    try:
                        value = self.get_named(name, line)
                    except NgcError:
                        value = None
                else:
                    m = re.compile(r"#(\d+)").match(text, i)
                    if m:
                        end = m.end()
                        try:
                            value = self.get_numbered(int(m.group(1)), line)
                        except NgcError:
                            value = None
                if end is not None:
                    out.append("######" if value is None else f"{value:.{decimals}f}")
                    i = end
                    continue
            out.append(ch)
            i += 1
        return "".join(out)


def expand(text: str, source: str = "", *, block_delete: bool = True,
           search_path: Sequence[str | Path] = (),
           parameters: Mapping[int | str, float] | None = None,
           max_depth: int = MAX_DEPTH, max_iterations: int = MAX_ITERATIONS,
           on_block: Callable[[Block, Expanded], None] | None = None,
           state=None) -> Expanded:
    """Run a LinuxCNC program's parameters, expressions and O-word control flow.

    ``text``: the program; ``source``: its file name (kept out of the main
    program's errors, which the caller names; a subroutine file's errors name
    it).  ``block_delete``: LinuxCNC's block delete switch (on: lines starting
    with ``/`` are skipped).  ``search_path``: folders searched for
    ``<name>.ngc`` when ``o<name> call`` names a subroutine the program does not
    define.  ``parameters``: initial values, numbered (int keys, 1..5000) or
    global named (``"_name"`` keys).  ``on_block(block, expanded)``: called with
    each block as it is executed (before the next line runs; ``expanded`` holds
    ``opening`` and ``line_count``); what it raises ends the run.  ``state``:
    the machine state behind LinuxCNC's system parameters, an object with
    ``numbered(n)`` and ``named(name)`` returning a value or None (not tracked).
    Returns the executed blocks and messages; raises ``NgcError`` (a
    ``GcodeError``) naming the line and the bad token.
    """
    interp = _Interpreter(source, block_delete, search_path, max_depth, max_iterations,
                          on_block, state)
    nowhere = _Line(0, "", "")
    for key, value in (parameters or {}).items():
        if isinstance(key, int):
            interp.set_numbered(key, float(value), nowhere)
        else:
            if not key.startswith("_"):
                raise ValueError(f"initial named parameters are global (#<_name>): {key!r}")
            interp.set_named(re.sub(r"\s+", "", key).lower(), float(value), nowhere)
    body = interp.read_file(text, "", main=True)
    try:
        interp.run(body)
    except _End:
        interp.out.ended = True
    except (_Break, _Continue, _Return):      # the structure check rules these out
        raise AssertionError("O-word control flow escaped its construct") from None
    return interp.out
