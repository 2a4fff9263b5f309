# SPDX-License-Identifier: Apache-2.0
"""G-code front end: the LinuxCNC dialect subset a 2.5-axis mill needs.

Supported: G0 G1 G2 G3 (centre form I/J/K, radius form R, full circles in the
centre form), G17 G18 G19, G20 G21, G90 G91, G90.1 G91.1, G40 G41 G42 (D =
tool number; without D the tool loaded by T.. M6; D0 = radius zero) and
G41.1 G42.1 (D = diameter), G54, F, N, T and M6, comments ``( )`` and
``;``, ``%`` demarcation, M2 and M30.  Anything else is an error that names
the line and the reason, never silently ignored.

Conventions (documented in the README):
* Units: everything is converted to mm (G20 input is multiplied by 25.4).
* G54 is the only work offset and it is zero: program coordinates are machine
  coordinates, and the program starts at the origin.
* Arcs: the end point is checked with LinuxCNC's rule -- an error if the
  start and end radii differ by more than 0.5 mm, or by more than 0.005 mm and
  0.1 % of the radius.  The arc is then run about the programmed centre with
  the start radius.  Arcs in G17 may not move Z (no helices); G18/G19 arcs are
  parsed but the core interpolates arcs in XY only.
* A feed rate must be set before the first G1/G2/G3.
* ``%`` demarcation as in LinuxCNC; the opening line may carry a program
  number (``%1234``), which is ignored.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass, field

INCH = 25.4


class GcodeError(ValueError):
    def __init__(self, lineno: int, reason: str):
        self.lineno = lineno
        self.reason = reason
        super().__init__(f"line {lineno}: {reason}")


@dataclass(slots=True)
class Move:
    """One motion block, in mm, absolute machine coordinates."""

    kind: str                      # "rapid", "line" or "arc"
    start: tuple[float, float, float]
    end: tuple[float, float, float]
    lineno: int
    feed: float = 0.0              # mm/min (0 for rapids)
    center: tuple[float, float] | None = None   # in the arc's plane
    cw: bool = False
    plane: int = 17
    comp: str = "off"              # "off", "left" or "right" while this block was read
    radius: float = 0.0            # compensation radius in force


@dataclass
class Program:
    moves: list[Move] = field(default_factory=list)
    notes: list[str] = field(default_factory=list)     # choices worth printing (tool units)
    ended: bool = False            # M2/M30 or closing %
    messages: list = field(default_factory=list)   # (MSG, (DEBUG, (PRINT, in order (ngc.Message)


_WORD = re.compile(r"([A-Za-z])\s*([+-]?(?:\d+\.?\d*|\.\d+))")
_G_SUPPORTED = {0, 1, 2, 3, 17, 18, 19, 20, 21, 40, 41, 42, 41.1, 42.1, 54, 90, 91, 90.1, 91.1}
_M_SUPPORTED = {2, 6, 30}
_GROUPS = {
    "motion": {0, 1, 2, 3},
    "plane": {17, 18, 19},
    "units": {20, 21},
    "distance": {90, 91},
    "arcdist": {90.1, 91.1},
    "comp": {40, 41, 42, 41.1, 42.1},
    "coord": {54},
}
_LETTERS = set("GMXYZIJKRFNDT")


def _strip_comments(text: str, lineno: int) -> str:
    out = []
    i = 0
    while i < len(text):
        ch = text[i]
        if ch == ";":
            break
        if ch == "(":
            j = text.find(")", i + 1)
            if j < 0:
                raise GcodeError(lineno, "comment '(' is not closed on this line")
            if "(" in text[i + 1:j]:
                raise GcodeError(lineno, "nested comments are not allowed")
            i = j + 1
            out.append(" ")
            continue
        if ch == ")":
            raise GcodeError(lineno, "')' without '('")
        out.append(ch)
        i += 1
    return "".join(out)


def _words(line: str, lineno: int) -> list[tuple[str, float]]:
    words = []
    pos = 0
    s = line.strip()
    if "#" in s or "[" in s:
        raise GcodeError(lineno, "parameters and expressions are not supported")
    while pos < len(s):
        if s[pos].isspace():
            pos += 1
            continue
        m = _WORD.match(s, pos)
        if not m:
            bad = s[pos:pos + 12]
            if s[pos] in "#[":
                raise GcodeError(lineno, f"parameters and expressions are not supported: {bad!r}")
            if s[pos] == "/":
                raise GcodeError(lineno, "block delete '/' is not supported")
            raise GcodeError(lineno, f"cannot read {bad!r}")
        words.append((m.group(1).upper(), float(m.group(2))))
        pos = m.end()
    return words


def _gnum(v: float) -> float:
    r = round(v, 1)
    return int(r) if r == int(r) else r


class ToolTable(dict):
    """{tool number: radius in the table's units, or None without a diameter}.

    ``units``: "mm" or "inch" when the file says so (a comment ``; units:
    mm`` or ``; units: inch``), else None: the diameters are then read in the
    program's units where compensation uses them (G20 inch, G21 mm), which is
    what LinuxCNC does when the machine units match the program's."""

    units: str | None = None


def load_tool_table(text: str) -> ToolTable:
    """LinuxCNC tool table lines ``T<n> P<pocket> [X.. Z..] [D<diameter>] ;..``.

    ``;`` starts a comment.  A tool without D is kept (radius None) and is an
    error only if compensation uses it (LinuxCNC's stock sim.tbl has one)."""
    tools = ToolTable()
    for lineno, raw in enumerate(text.splitlines(), start=1):
        line, _, comment = raw.partition(";")
        unit = re.fullmatch(r"\s*units?\s*[:=]\s*(mm|inch|in)\s*", comment, re.IGNORECASE)
        if unit and not line.strip():
            tools.units = "mm" if unit.group(1).lower() == "mm" else "inch"
            continue
        line = line.strip()
        if not line:
            continue
        fields = {}
        for tok in line.split():
            m = re.fullmatch(r"([A-Za-z])([+-]?(?:\d+\.?\d*|\.\d+))", tok)
            if not m:
                raise GcodeError(lineno, f"tool table: cannot read {tok!r}")
            fields[m.group(1).upper()] = float(m.group(2))
        if "T" not in fields:
            raise GcodeError(lineno, "tool table: a tool line needs T")
        if "D" in fields and fields["D"] < 0:
            raise GcodeError(lineno, "tool table: negative diameter")
        tools[int(fields["T"])] = fields["D"] / 2 if "D" in fields else None
    return tools


def _tool_radius(tools, tnum: int, scale: float, lineno: int, notes: list) -> float:
    """Radius in mm of tool ``tnum`` for G41/G42 (D0 and T0: radius zero)."""
    if tnum == 0:
        return 0.0
    if tnum not in tools:
        raise GcodeError(lineno, f"tool {tnum} is not in the tool table")
    r = tools[tnum]
    if r is None:
        raise GcodeError(lineno, f"tool {tnum} has no diameter (D) in the tool table")
    units = getattr(tools, "units", None)
    if units is None:
        units = "inch" if scale == INCH else "mm"
        why = "the program's units at this line"
    else:
        why = "as the tool table states"
    note = f"tool table diameters read in {units} ({why})"
    if note not in notes:
        notes.append(note)
    return r * (INCH if units == "inch" else 1.0)


def parse(text: str, tools: dict[int, float] | None = None,
          radius_override: float | None = None, *, source: str = "",
          block_delete: bool = True, search_path=()) -> Program:
    """Parse a program into absolute moves in mm (see the module docstring).

    The program's parameters, expressions and O-word control flow run first
    (``halfpoint.cam.ngc.expand``, LinuxCNC's rules); the blocks it executes are
    parsed here with their original line numbers.  ``block_delete``: skip lines
    starting with ``/`` (the LinuxCNC default); ``search_path``: folders holding
    ``name.ngc`` files for ``o<name> call``.
    """
    from .ngc import expand

    tools = tools or {}
    prog = Program()
    pos = [0.0, 0.0, 0.0]
    motion = None
    plane = 17
    scale = 1.0
    absolute = True
    arc_absolute = False
    feed = 0.0
    comp, comp_r = "off", 0.0
    prepared = loaded = None            # tool selected by T, tool in the spindle (M6)
    expanded = expand(text, source, block_delete=block_delete, search_path=search_path)
    prog.messages = expanded.messages
    # "%" opens a demarcated program; "%1234" (a Fanuc-style program number,
    # as in seed 004's tests) is read the same way, the number ignored
    percent = expanded.opening != 0
    for block in expanded.blocks:
        lineno, raw = block.lineno, block.text
        stripped = raw.strip()
        if percent and block.source == "" and lineno == expanded.opening:
            continue
        if stripped == "%":
            if percent:
                prog.ended = True
                break
            raise GcodeError(lineno, "'%' closes a program that did not open with '%'")
        body = _strip_comments(raw, lineno)
        words = _words(body, lineno)
        if not words:
            continue
        gs, ms, vals = [], [], {}
        for letter, v in sorted(words, key=lambda w: w[0] not in "GM"):
            if letter not in _LETTERS:
                raise GcodeError(lineno, f"unsupported word {letter}{v:g}")
            if letter == "G":
                g = _gnum(v)
                if g not in _G_SUPPORTED:
                    raise GcodeError(lineno, f"unsupported G code G{g}")
                gs.append(g)
            elif letter == "M":
                mc = _gnum(v)
                if mc not in _M_SUPPORTED:
                    raise GcodeError(lineno, f"unsupported M code M{mc}")
                ms.append(mc)
            else:
                if letter in vals:
                    raise GcodeError(lineno, f"word {letter} appears twice")
                vals[letter] = v
        for name, members in _GROUPS.items():
            if sum(1 for g in gs if g in members) > 1:
                raise GcodeError(lineno, f"two G codes of the {name} group on one line")
        vals.pop("N", None)
        if "T" in vals:
            if vals["T"] < 0 or vals["T"] != int(vals["T"]):
                raise GcodeError(lineno, "tool number T must be a whole number >= 0")
            prepared = int(vals.pop("T"))
        if 6 in ms:
            if prepared is None:
                raise GcodeError(lineno, "M6 without a tool selected by T")
            if comp != "off":
                raise GcodeError(lineno, "tool change with cutter compensation on (G40 first)")
            loaded = prepared
        for g in gs:
            if g in (17, 18, 19):
                plane = g
            elif g == 20:
                scale = INCH
            elif g == 21:
                scale = 1.0
            elif g == 90:
                absolute = True
            elif g == 91:
                absolute = False
            elif g == 90.1:
                arc_absolute = True
            elif g == 91.1:
                arc_absolute = False
        if "F" in vals:
            if vals["F"] <= 0:
                raise GcodeError(lineno, "feed rate F must be positive")
            feed = vals.pop("F") * scale
        comp_g = next((g for g in gs if g in _GROUPS["comp"]), None)
        if "D" in vals and comp_g not in (41, 42, 41.1, 42.1):
            raise GcodeError(lineno, "D word without G41, G42, G41.1 or G42.1")
        if comp_g == 40:
            comp, comp_r = "off", 0.0
        elif comp_g is not None:
            if comp != "off":
                raise GcodeError(lineno, "cutter compensation is already on (G40 first)")
            if plane != 17:
                raise GcodeError(lineno, "cutter compensation is supported in G17 (XY) only")
            if comp_g in (41, 42):
                if radius_override is not None:
                    comp_r = radius_override
                elif "D" in vals:
                    comp_r = _tool_radius(tools, int(vals["D"]), scale, lineno, prog.notes)
                elif loaded is not None:
                    # no D: the tool loaded by the last T.. M6 (LinuxCNC)
                    comp_r = _tool_radius(tools, loaded, scale, lineno, prog.notes)
                else:
                    raise GcodeError(lineno, f"G{comp_g} needs a D word (tool number), a tool "
                                             "loaded with T.. M6, or --radius")
            else:
                if "D" not in vals:
                    raise GcodeError(lineno, f"G{comp_g} needs a D word (tool diameter)")
                if vals["D"] < 0:
                    raise GcodeError(lineno, "tool diameter D must not be negative")
                comp_r = vals["D"] * scale / 2
            comp = "left" if comp_g in (41, 41.1) else "right"
        vals.pop("D", None)
        mg = next((g for g in gs if g in _GROUPS["motion"]), None)
        if mg is not None:
            motion = mg
        axes = {k: vals.pop(k) for k in "XYZ" if k in vals}
        offs = {k: vals.pop(k) for k in "IJK" if k in vals}
        rword = vals.pop("R", None)
        if vals:
            raise GcodeError(lineno, f"unexpected word {next(iter(vals))}")
        if axes or mg is not None or offs or rword is not None:
            if motion is None:
                raise GcodeError(lineno, "axis words without a motion mode (G0, G1, G2, G3)")
            if (offs or rword is not None) and motion not in (2, 3):
                raise GcodeError(lineno, "I, J, K or R words outside an arc move")
            end = list(pos)
            for k, ax in zip("XYZ", range(3)):
                if k in axes:
                    end[ax] = axes[k] * scale if absolute else pos[ax] + axes[k] * scale
            if motion in (1, 2, 3) and feed <= 0:
                raise GcodeError(lineno, "no feed rate set (F) for G1/G2/G3")
            if motion in (0, 1):
                if axes:
                    prog.moves.append(Move("rapid" if motion == 0 else "line", tuple(pos), tuple(end),
                                           lineno, 0.0 if motion == 0 else feed, comp=comp, radius=comp_r))
            else:
                prog.moves.append(_arc(motion == 2, pos, end, offs, rword, plane, scale,
                                       arc_absolute, feed, lineno, comp, comp_r))
            pos = end
        if 2 in ms or 30 in ms:
            prog.ended = True
            break
    else:
        if percent:
            raise GcodeError(expanded.line_count, "program opened with '%' but has no closing '%'")
    if not prog.ended and not percent:
        raise GcodeError(expanded.line_count, "program has no M2 or M30 and is not demarcated with '%'")
    return prog


def _arc(cw, pos, end, offs, rword, plane, scale, arc_absolute, feed, lineno, comp, comp_r):
    a0, a1 = {17: (0, 1), 18: (2, 0), 19: (1, 2)}[plane]
    ax_perp = 3 - a0 - a1
    off_letters = {17: "IJ", 18: "KI", 19: "JK"}[plane]
    if abs(end[ax_perp] - pos[ax_perp]) > 1e-12:
        raise GcodeError(lineno, "helical arcs are not supported (the axis normal to the plane moves)")
    s = (pos[a0], pos[a1])
    e = (end[a0], end[a1])
    if rword is not None:
        if offs:
            raise GcodeError(lineno, "an arc has either I/J/K offsets or R, not both")
        r = rword * scale
        if abs(r) < 1e-12:
            raise GcodeError(lineno, "arc radius R is zero")
        dx, dy = e[0] - s[0], e[1] - s[1]
        d = math.hypot(dx, dy)
        if d < 1e-12:
            raise GcodeError(lineno, "a radius-format arc cannot be a full circle")
        if d > 2 * abs(r) + 1e-9:
            raise GcodeError(lineno, f"arc radius {abs(r):g} is too small for a chord of {d:g}")
        h = math.sqrt(max(r * r - d * d / 4, 0.0))
        mx, my = (s[0] + e[0]) / 2, (s[1] + e[1]) / 2
        # centre to the right of the chord for a short CW arc, left for CCW
        sign = (1 if cw else -1) * (1 if r > 0 else -1)
        c = (mx + sign * h * dy / d, my - sign * h * dx / d)
    else:
        for letter in offs:
            if letter not in off_letters:
                raise GcodeError(lineno, f"offset {letter} does not belong to plane G{plane}")
        if not offs:
            raise GcodeError(lineno, "arc without I/J/K offsets or R")
        o0 = offs.get(off_letters[0], 0.0) * scale
        o1 = offs.get(off_letters[1], 0.0) * scale
        c = (o0, o1) if arc_absolute else (s[0] + o0, s[1] + o1)
        r0 = math.hypot(s[0] - c[0], s[1] - c[1])
        r1 = math.hypot(e[0] - c[0], e[1] - c[1])
        if r0 < 1e-9:
            raise GcodeError(lineno, "arc radius is zero (centre at the start point)")
        diff = abs(r1 - r0)
        if diff > 0.5 or (diff > 0.005 and diff > 0.001 * r0):
            raise GcodeError(lineno, f"arc end point is not on the circle: radii {r0:.4f} and {r1:.4f} mm "
                                     f"differ by {diff:.4f} mm")
    return Move("arc", tuple(pos), tuple(end), lineno, feed, center=c, cw=cw, plane=plane,
                comp=comp, radius=comp_r)
