# SPDX-License-Identifier: Apache-2.0
"""G-code front end: LinuxCNC's RS274NGC dialect for a 3-axis mill (X Y Z).

``parse(text, ...)`` returns a ``Program``: ``moves``, the motion blocks as
``Move`` objects in mm and absolute machine coordinates (what compensation,
the quantiser and the planner consume), and ``events``, everything else the
program asks for in program order (pauses, tool changes, dwells, spindle and
coolant), each placed before the move it precedes.

Supported (LinuxCNC's semantics; README "Dialect" lists every word):

* Motion: G0 G1 G2 G3, modal (axis words alone continue the motion mode);
  arcs in G17/G18/G19 with the plane's offsets (I J / I K / J K, centre form in
  G91.1 or G90.1, radius form R) and, as LinuxCNC, a zero offset word of the
  third axis accepted (FreeCAD's ``K0`` in G17); helical arcs (the axis normal
  to the plane moves linearly with the arc); ``P`` turns (P - 1 full circles
  before the programmed arc, each its own ``Move``).  G80 and the canned cycles G73
  G81 G82 G83 G85 G89 with G98/G99 and L repeats, expanded into moves and
  dwells as LinuxCNC's ``interp_cycles.cc`` (master) does, in exact-path mode:
  G98 returns to the initial level of the series of consecutive cycle blocks,
  G83 retracts to R between pecks, G73 backs off 0.010 inch, G85 feeds out to
  R, G89 feeds out to the clear level.
* Feed: F, G94 (units per minute) and G93 (inverse time: F on every feed
  move, converted to the move's mm/min from its length).
* Units and modes: G20 G21 (everything is converted to mm), G90 G91, G90.1
  G91.1, G17 G18 G19, G61 G61.1 G64 [P Q] (recorded on every move), G97.
* Coordinates: G54-G59, G59.1-G59.3, G10 L2 / L20 (P0 current, P1-P9), G92
  G92.1 G92.2 G92.3, G53 (machine coordinates for one G0/G1 block), G28 G30
  (through an optional intermediate point to the stored position) and G28.1
  G30.1 (store the current position).  Machine = program coordinate + the
  selected system's offset + the G92 offset + the tool length offset.
* Tools: T, M6 (a ``ToolChange`` event), G43 [H] (offsets from the tool
  table's X and Z columns), G43.1 (offsets from the block's axis words), G49;
  G40 G41 G42 (D = tool number; no D: the tool loaded by M6; D0 = radius 0)
  and G41.1 G42.1 (D = diameter).
* Program flow: M0, M1 (only with the optional-stop switch on), M2 M30 (a
  program without them ends at the end of the file, with a note), G4 P
  seconds, ``%`` demarcation, block delete (``halfpoint.cam.ngc``).
* Spindle and coolant: S, M3 M4 M5, M7 M8 M9 (events).

Refused with an error naming the line: lathe and threading codes (G7 G8 G33
G33.1 G76), polar coordinates (G15 G16, ``@`` ``^``), axes other than X Y Z,
and every other G or M code or word.

Conventions:
* The program starts at the machine origin with every offset zero, G54, G17,
  G21, G90, G91.1, G94, G64, G99, G40, G49 and G80; the stored G28/G30
  positions come from ``positions`` (the machine file), else the origin.
  Offsets set by the program (G10, G92, G28.1, G30.1) last for that program.
* The interpreter (``halfpoint.cam.ngc``) hands each block to the parser as it
  runs, so LinuxCNC's machine-state parameters (#5161-#5428, ``#<_x>``...,
  ``_Parser.numbered`` / ``named``) read what the blocks before them left.
* Arcs: the end point is checked with LinuxCNC's rule -- an error if the
  start and end radii differ by more than 0.5 mm, or by more than 0.005 mm and
  0.1 % of the radius.  The arc then runs as LinuxCNC runs it, about the
  programmed centre, its radius in proportion to the angle from the start's to
  the end's (``geom.Spiral``).  ``Move.center`` is in machine coordinates, in the
  plane's axis order (X Y for G17, Z X for G18, Y Z for G19).
* A feed rate must be set before the first G1/G2/G3 (after G93 -> G94 too).
"""

from __future__ import annotations

import math
import re
from dataclasses import KW_ONLY, dataclass, field

INCH = 25.4
# LinuxCNC's G83_RAPID_DELTA / G73 back-off: 0.010 inch (0.254 mm in G21)
PECK_BACKOFF_INCH = 0.010


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
    path_mode: str = "G64"         # "G61" exact path, "G61.1" exact stop, "G64" blending
    path_tolerance: float = 0.0    # G64 P in mm (0: no limit, as LinuxCNC)
    naive_tolerance: float = 0.0   # G64 Q in mm (naive CAM detector)


# --- events: what a program asks for between moves ------------------------------------------
# ``before`` is the index in Program.moves of the first move after the event
# (len(moves) for an event after the last move); ``lineno`` its line.

@dataclass
class Event:
    _: KW_ONLY
    lineno: int = 0
    before: int = 0


@dataclass
class Pause(Event):
    """M0 (``reason`` "M0"), M1 (``optional``): wait until resumed."""

    reason: str = "M0"
    optional: bool = False


@dataclass
class ToolChange(Event):
    """M6: a programmed pause while the operator puts ``tool`` in the spindle."""

    tool: int = 0


@dataclass
class Dwell(Event):
    """G4 P (and the dwell of G82/G89): a timed pause at rest.  ``seconds`` has the
    same name as ``halfpoint.cam.planner.Dwell``'s: ``planner.Dwell(e.seconds, e.lineno)``."""

    seconds: float = 0.0


@dataclass
class Spindle(Event):
    """M3 (cw) / M4 / M5 and S: the spindle (or laser) state from here on."""

    on: bool = False
    cw: bool = True
    speed: float = 0.0             # S: rpm, or laser power


@dataclass
class Coolant(Event):
    """M7 (mist) / M8 (flood) / M9 (both off): the coolant state from here on."""

    mist: bool = False
    flood: bool = False


@dataclass
class Program:
    """A parsed program: ``moves`` (motion only, in order), ``events`` (everything
    else in order, each with ``before`` = the index of the move it precedes)."""

    moves: list[Move] = field(default_factory=list)
    notes: list[str] = field(default_factory=list)     # choices worth printing (tool units)
    ended: bool = False            # M2/M30 or closing %
    messages: list = field(default_factory=list)   # (MSG, (DEBUG, (PRINT, in order (ngc.Message)
    events: list = field(default_factory=list)     # Pause, ToolChange, Dwell, Spindle, Coolant
    blocks: int = 0                # executed blocks that carried words


_WORD = re.compile(r"([A-Za-z])\s*([+-]?(?:\d+\.?\d*|\.\d+))")
_GROUPS = {
    "motion": {0, 1, 2, 3, 80, 73, 81, 82, 83, 85, 89},
    "non-modal": {4, 10, 28, 28.1, 30, 30.1, 53, 92, 92.1, 92.2, 92.3},
    "plane": {17, 18, 19},
    "units": {20, 21},
    "distance": {90, 91},
    "arc distance": {90.1, 91.1},
    "feed mode": {93, 94},
    "cutter compensation": {40, 41, 42, 41.1, 42.1},
    "tool length": {43, 43.1, 49},
    "coordinate system": {54, 55, 56, 57, 58, 59, 59.1, 59.2, 59.3},
    "path control": {61, 61.1, 64},
    "retract mode": {98, 99},
    "spindle speed mode": {97},
}
_G_SUPPORTED = set().union(*_GROUPS.values())
_GROUP_OF = {g: name for name, members in _GROUPS.items() for g in members}
_NO_GROUP = {name: None for name in _GROUPS}
_M_GROUPS = {"stopping": {0, 1, 2, 30}, "tool change": {6}, "spindle": {3, 4, 5},
             "coolant": {7, 8, 9}}
_M_SUPPORTED = set().union(*_M_GROUPS.values())
_CYCLES = {73, 81, 82, 83, 85, 89}
_COORD = [54, 55, 56, 57, 58, 59, 59.1, 59.2, 59.3]
_REFUSED_G = {
    7: "lathe diameter mode (G7) is not supported: halfpoint drives a mill",
    8: "lathe radius mode (G8) is not supported: halfpoint drives a mill",
    33: "spindle-synchronised motion (G33) is not supported",
    33.1: "rigid tapping (G33.1) is not supported",
    76: "threading (G76) is not supported",
    15: "polar coordinates (G15/G16) are not supported",
    16: "polar coordinates (G15/G16) are not supported",
    5: "splines (G5) are not supported", 5.1: "splines (G5.1) are not supported",
    5.2: "NURBS (G5.2) are not supported", 5.3: "NURBS (G5.3) are not supported",
    38.2: "probing (G38.x) is not supported", 38.3: "probing (G38.x) is not supported",
    38.4: "probing (G38.x) is not supported", 38.5: "probing (G38.x) is not supported",
    84: "canned cycle G84 (tapping) is not supported",
    86: "canned cycle G86 is not supported (G73 G81 G82 G83 G85 G89 are)",
    87: "canned cycle G87 is not supported (G73 G81 G82 G83 G85 G89 are)",
    88: "canned cycle G88 is not supported (G73 G81 G82 G83 G85 G89 are)",
    95: "feed per revolution (G95) is not supported", 96: "constant surface speed "
    "(G96) is not supported",
    43.2: "additive tool length offsets (G43.2) are not supported (G43, G43.1 are)",
    52: "local offsets (G52) are not supported (G92 is)",
}
_LETTERS = set("GMXYZIJKRFNDTPQLHS")
_OTHER_AXES = set("ABCUVW")
PLANE_AXES = {17: (0, 1, 2), 18: (2, 0, 1), 19: (1, 2, 0)}   # first, second, normal axis
_OFFSET_LETTERS = {17: "IJ", 18: "KI", 19: "JK"}


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
            if s[pos] in "@^":
                raise GcodeError(lineno, f"polar coordinates ('@' radius, '^' angle) are not "
                                         f"supported: {bad!r}")
            if s[pos] == "/":
                raise GcodeError(lineno, "block delete '/' is only allowed at the start of a line")
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
    mm`` or ``; units: inch``), else None: the values are then read in the
    program's units where they are used (G20 inch, G21 mm), which is what
    LinuxCNC does when the machine units match the program's.  ``offsets``:
    {tool number: (X, Z)} length offsets from the X and Z columns (0 if absent),
    used by G43."""

    units: str | None = None

    def __init__(self, *args, **kw):
        super().__init__(*args, **kw)
        self.offsets: dict[int, tuple[float, float]] = {}


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
        tnum = int(fields["T"])
        tools[tnum] = fields["D"] / 2 if "D" in fields else None
        tools.offsets[tnum] = (fields.get("X", 0.0), fields.get("Z", 0.0))
    return tools


def _table_scale(tools, scale: float, notes: list, what: str) -> float:
    """mm per table unit, with a note saying how the units were chosen."""
    units = getattr(tools, "units", None)
    if units is None:
        units = "inch" if scale == INCH else "mm"
        why = "the program's units at this line"
    else:
        why = "as the tool table states"
    note = f"tool table {what} read in {units} ({why})"
    if note not in notes:
        notes.append(note)
    return INCH if units == "inch" else 1.0


def _tool_radius(tools, tnum: int, scale: float, lineno: int, notes: list) -> float:
    """Radius in mm of tool ``tnum`` for G41/G42 (D0 and T0: radius zero)."""
    if tnum == 0:
        return 0.0
    if tnum not in tools:
        raise GcodeError(lineno, f"tool {tnum} is not in the tool table")
    r = tools[tnum]
    if r is None:
        raise GcodeError(lineno, f"tool {tnum} has no diameter (D) in the tool table")
    return r * _table_scale(tools, scale, notes, "diameters")


@dataclass
class MachineState:
    """What the machine knows before the program runs (LinuxCNC keeps these in its
    parameter file): the stored G28 / G30 positions in machine mm."""

    g28: tuple[float, float, float] = (0.0, 0.0, 0.0)
    g30: tuple[float, float, float] = (0.0, 0.0, 0.0)


def parse(text: str, tools: dict[int, float] | None = None,
          radius_override: float | None = None, *, source: str = "",
          block_delete: bool = True, search_path=(), positions=None,
          optional_stop: bool = False) -> Program:
    """Parse a program into absolute moves in mm and events (module docstring).

    The program's parameters, expressions and O-word control flow run first
    (``halfpoint.cam.ngc.expand``, LinuxCNC's rules); the blocks it executes are
    parsed here with their original line numbers.  ``block_delete``: skip lines
    starting with ``/`` (the LinuxCNC default); ``search_path``: folders holding
    ``name.ngc`` files for ``o<name> call``.  ``positions``: the stored G28 and
    G30 positions, a ``MachineState``, a mapping ``{"g28": (x, y, z), "g30":
    (x, y, z)}`` in machine mm, or a ``halfpoint.cam.machine.Machine`` (its
    ``[positions]``); default the machine origin.  ``optional_stop``: the
    optional-stop switch (M1 pauses only when it is on).
    """
    from .ngc import expand

    p = _Parser(tools or {}, radius_override, _positions(positions), optional_stop)

    def on_block(block, out):
        """Each block as the interpreter executes it, so that the next line's
        parameters see the state it leaves (positions, offsets, modes)."""
        lineno, raw = block.lineno, block.text
        # "%" opens a demarcated program; "%1234" (a Fanuc-style program number,
        # as in seed 004's tests) is read the same way, the number ignored
        if p.prog.ended or (out.opening and block.source == "" and lineno == out.opening):
            return
        if raw.strip() == "%":
            if out.opening:
                p.prog.ended = True
                return
            raise GcodeError(lineno, "'%' closes a program that did not open with '%'")
        if p.block(lineno, raw):
            p.prog.ended = True

    expanded = expand(text, source, block_delete=block_delete, search_path=search_path,
                      on_block=on_block, state=p)
    p.prog.messages = expanded.messages
    if not p.prog.ended:
        if expanded.opening:
            raise GcodeError(expanded.line_count, "program opened with '%' but has no closing '%'")
        p.prog.notes.append(f"no M2 or M30: the program ends at the end of the file (line "
                            f"{expanded.line_count}); LinuxCNC requires one")
    return p.prog


def _positions(positions) -> MachineState:
    if positions is None:
        return MachineState()
    if isinstance(positions, MachineState):
        return positions
    if hasattr(positions, "g28") and hasattr(positions, "g30"):
        return MachineState(tuple(positions.g28), tuple(positions.g30))
    state = MachineState()
    for key, value in dict(positions).items():
        if key not in ("g28", "g30"):
            raise ValueError(f"positions: unknown key {key!r} (g28, g30)")
        value = tuple(float(v) for v in value)
        if len(value) != 3:
            raise ValueError(f"positions: {key} needs three values (x, y, z)")
        setattr(state, key, value)
    return state


class _Parser:
    """The interpreter's modal state and one block at a time (LinuxCNC's order of
    execution within a block, G-code chapter "Order of Execution")."""

    def __init__(self, tools, radius_override, positions: MachineState, optional_stop):
        self.tools = tools
        self.radius_override = radius_override
        self.optional_stop = optional_stop
        self.prog = Program()
        self.pos = [0.0, 0.0, 0.0]          # machine coordinates, mm
        self.motion = None                  # 0 1 2 3, a cycle, 80 or None
        self.plane = 17
        self.scale = 1.0
        self.absolute = True
        self.arc_absolute = False
        self.inverse_time = False
        self.feed = 0.0
        self.comp, self.comp_r = "off", 0.0
        self.prepared = self.loaded = None  # tool selected by T, tool in the spindle (M6)
        self.coord = 0                      # index into _COORD (G54)
        self.systems = [[0.0, 0.0, 0.0] for _ in _COORD]
        self.g92 = [0.0, 0.0, 0.0]          # G92 offset in force
        self.g92_saved = [0.0, 0.0, 0.0]    # LinuxCNC's #5211-#5213 (G92.2 / G92.3)
        self.tlo = [0.0, 0.0, 0.0]          # tool length offset
        self.stored = {28: list(positions.g28), 30: list(positions.g30)}
        self.path_mode, self.path_p, self.path_q = "G64", 0.0, 0.0
        self.retract_r_plane = True         # G99 (LinuxCNC's start-up default)
        self.cycle_r = self.cycle_z = None  # sticky R, Z (program coordinates, mm)
        self.cycle_il = None                # initial level of the cycle series
        self.cycle_p = self.cycle_q = None
        self.spindle_on, self.spindle_cw, self.speed = False, True, 0.0
        self.mist = self.flood = False

    # LinuxCNC's parameters of machine state (read by halfpoint.cam.ngc), program units
    def numbered(self, n: int) -> float | None:
        s = self.scale
        if 5161 <= n <= 5169 or 5181 <= n <= 5189:
            a = (n - 5161) % 20
            return self.stored[28 if n < 5181 else 30][a] / s if a < 3 else 0.0
        if n == 5210:
            return 1.0 if any(self.g92) else 0.0
        if 5211 <= n <= 5219:
            return self.g92_saved[n - 5211] / s if n < 5214 else 0.0
        if n == 5220:
            return float(self.coord + 1)
        if 5221 <= n <= 5390:
            k, a = divmod(n - 5221, 20)
            if k < len(_COORD) and a <= 9:
                return self.systems[k][a] / s if a < 3 else 0.0
            return None
        if n == 5400:
            return float(self.loaded or 0)
        if 5401 <= n <= 5409:
            return self.tlo[n - 5401] / s if n < 5404 else 0.0
        if n == 5410:
            # the loaded tool's diameter (0 without a tool or a D in the table)
            r = self.tools.get(self.loaded) if self.loaded and self.tools else None
            if r is None:
                return 0.0
            return 2 * r * _table_scale(self.tools, s, self.prog.notes, "diameters") / s
        if 5411 <= n <= 5413:
            return 0.0          # front and back angle, orientation: lathe tools
        if 5420 <= n <= 5428:
            return self.program_pos()[n - 5420] / s if n < 5423 else 0.0
        return None

    def named(self, name: str) -> float | None:
        s = self.scale
        if name in ("_x", "_y", "_z"):
            return self.program_pos()["xyz".index(name[1])] / s
        if name in ("_abs_x", "_abs_y", "_abs_z"):
            return self.pos["xyz".index(name[-1])] / s
        if name in ("_a", "_b", "_c", "_u", "_v", "_w", "_abs_a", "_abs_b", "_abs_c",
                    "_abs_u", "_abs_v", "_abs_w", "_units_per_rev", "_spindle_css_mode"):
            return 0.0
        values = {
            "_current_tool": self.loaded or 0,
            "_selected_tool": -1 if self.prepared is None else self.prepared,
            "_metric": s == 1.0, "_imperial": s != 1.0,
            "_absolute": self.absolute, "_incremental": not self.absolute,
            "_inverse_time": self.inverse_time, "_units_per_minute": not self.inverse_time,
            "_feed": self.feed / s, "_rpm": self.speed,
            "_spindle_on": self.spindle_on, "_spindle_cw": self.spindle_cw,
            "_mist": self.mist, "_flood": self.flood, "_spindle_rpm_mode": 1,
            "_coord_system": round(_COORD[self.coord] * 10), "_plane": self.plane * 10,
            "_motion_mode": 10 * (80 if self.motion is None else self.motion),
            "_retract_r_plane": self.retract_r_plane,
            "_retract_old_z": not self.retract_r_plane,
            "_ijk_absolute_mode": self.arc_absolute,
        }
        return float(values[name]) if name in values else None

    # coordinates
    def offset(self, ax: int) -> float:
        return self.systems[self.coord][ax] + self.g92[ax] + self.tlo[ax]

    def program_pos(self) -> list[float]:
        return [self.pos[a] - self.offset(a) for a in range(3)]

    def event(self, ev: Event, lineno: int):
        ev.lineno, ev.before = lineno, len(self.prog.moves)
        self.prog.events.append(ev)

    def add_move(self, move: Move):
        move.path_mode, move.path_tolerance = self.path_mode, self.path_p
        move.naive_tolerance = self.path_q
        self.prog.moves.append(move)
        self.pos = list(move.end)

    def line_to(self, kind, end, lineno, feed=None, path_mode=None):
        m = Move(kind, tuple(self.pos), tuple(end), lineno,
                 0.0 if kind == "rapid" else (self.feed if feed is None else feed),
                 comp=self.comp, radius=self.comp_r)
        self.add_move(m)
        if path_mode is not None:
            m.path_mode, m.path_tolerance, m.naive_tolerance = path_mode, 0.0, 0.0

    # one block; True when it ends the program
    def block(self, lineno: int, raw: str) -> bool:
        words = _words(_strip_comments(raw, lineno), lineno)
        if not words:
            return False
        self.prog.blocks += 1
        gs, ms, vals = [], [], {}
        for letter, v in sorted(words, key=lambda w: w[0] not in "GM"):
            if letter in _OTHER_AXES:
                raise GcodeError(lineno, f"axis {letter} is not supported (halfpoint has X, Y "
                                         f"and Z): {letter}{v:g}")
            if letter not in _LETTERS:
                raise GcodeError(lineno, f"unsupported word {letter}{v:g}")
            if letter == "G":
                g = _gnum(v)
                if g in _REFUSED_G:
                    raise GcodeError(lineno, _REFUSED_G[g])
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
        group = dict(_NO_GROUP)
        for g in gs:
            name = _GROUP_OF[g]
            if group[name] is not None:
                raise GcodeError(lineno, f"two G codes of the {name} group on one line")
            group[name] = g
        if len(ms) > 1:
            for name, members in _M_GROUPS.items():
                found = [m for m in ms if m in members]
                if len(found) > 1 and not (name == "coolant" and sorted(found) == [7, 8]):
                    raise GcodeError(lineno, f"two M codes of the {name} group on one line")
        vals.pop("N", None)
        ln = lineno
        nonmodal = group["non-modal"]
        # 2-3: feed mode, F (units first: F is in the units this line selects)
        if group["units"] is not None:
            self.scale = INCH if group["units"] == 20 else 1.0
        if group["feed mode"] == 93:
            self.inverse_time = True
            self.feed = 0.0
        elif group["feed mode"] == 94:
            if self.inverse_time:
                self.feed = 0.0          # an inverse-time F is no feed rate
            self.inverse_time = False
        self.block_f = vals.pop("F", None)
        if self.block_f is not None:
            if self.block_f <= 0:
                raise GcodeError(ln, "feed rate F must be positive")
            if not self.inverse_time:
                self.feed = self.block_f * self.scale
        # 4: S
        if "S" in vals:
            s = vals.pop("S")
            if s < 0:
                raise GcodeError(ln, "spindle speed S must not be negative")
            self.speed = s
            if self.spindle_on and not any(m in (3, 4, 5) for m in ms):
                self.event(Spindle(on=True, cw=self.spindle_cw, speed=s), ln)
        # 5-6: T, M6
        if "T" in vals:
            if vals["T"] < 0 or vals["T"] != int(vals["T"]):
                raise GcodeError(ln, "tool number T must be a whole number >= 0")
            self.prepared = int(vals.pop("T"))
        if 6 in ms:
            if self.prepared is None:
                raise GcodeError(ln, "M6 without a tool selected by T")
            if self.comp != "off":
                raise GcodeError(ln, "tool change with cutter compensation on (G40 first)")
            self.loaded = self.prepared
            self.event(ToolChange(tool=self.loaded), ln)
        # 7-8: spindle, coolant
        for mc in ms:
            if mc in (3, 4):
                self.spindle_on, self.spindle_cw = True, mc == 3
                self.event(Spindle(on=True, cw=self.spindle_cw, speed=self.speed), ln)
            elif mc == 5:
                self.spindle_on = False
                self.event(Spindle(on=False, cw=self.spindle_cw, speed=self.speed), ln)
        if any(m in (7, 8, 9) for m in ms):
            if 9 in ms:
                self.mist = self.flood = False
            self.mist = self.mist or 7 in ms
            self.flood = self.flood or 8 in ms
            self.event(Coolant(mist=self.mist, flood=self.flood), ln)
        # 10: dwell
        if nonmodal == 4:
            if "P" not in vals:
                raise GcodeError(ln, "G4 needs P (seconds)")
            seconds = vals.pop("P")
            if seconds < 0:
                raise GcodeError(ln, "G4 dwell time P must not be negative")
            self.event(Dwell(seconds=seconds), ln)
        # 11-12: plane, units
        if group["plane"] is not None:
            self.plane = group["plane"]
        # 13: cutter compensation
        self.cutter_comp(group["cutter compensation"], vals, ln)
        # 14: tool length offset
        tl = group["tool length"]
        if tl == 43:
            h = vals.pop("H", None)
            if h is None:
                if self.loaded is None:
                    raise GcodeError(ln, "G43 without H needs a tool loaded with T.. M6")
                h = self.loaded
            if h < 0 or h != int(h):
                raise GcodeError(ln, "H must be a whole tool number >= 0")
            h = int(h)
            if h == 0:
                self.tlo = [0.0, 0.0, 0.0]
            else:
                offsets = getattr(self.tools, "offsets", {})
                if h not in self.tools and h not in offsets:
                    raise GcodeError(ln, f"G43 H{h}: tool {h} is not in the tool table")
                x, z = offsets.get(h, (0.0, 0.0))
                k = (_table_scale(self.tools, self.scale, self.prog.notes, "offsets")
                     if x or z else 1.0)
                self.tlo = [x * k, 0.0, z * k]
        elif tl == 43.1:
            given = {k: vals.pop(k) for k in "XYZ" if k in vals}
            if not given:
                raise GcodeError(ln, "G43.1 needs the offsets as axis words (e.g. Z-12.5)")
            self.tlo = [given.get(k, 0.0) * self.scale for k in "XYZ"]
        elif tl == 49:
            self.tlo = [0.0, 0.0, 0.0]
        # 15-18: coordinate system, path control, distance modes, retract mode
        if group["coordinate system"] is not None:
            if self.comp != "off":
                raise GcodeError(ln, "cannot change the coordinate system with cutter "
                                     "compensation on")
            self.coord = _COORD.index(group["coordinate system"])
        self.path_control(group["path control"], vals, ln)
        if group["distance"] is not None:
            self.absolute = group["distance"] == 90
        if group["arc distance"] is not None:
            self.arc_absolute = group["arc distance"] == 90.1
        if group["retract mode"] is not None:
            self.retract_r_plane = group["retract mode"] == 99
        # 19-20: the group-0 codes that use axis words, then motion
        mg = group["motion"]
        axis_users = {10, 28, 30, 92}
        if nonmodal in axis_users and mg is not None and mg != 80 and \
                any(k in vals for k in "XYZ"):
            raise GcodeError(ln, f"G{nonmodal} and G{mg} both use the axis words of this line")
        if nonmodal == 10:
            self.g10(vals, ln)
        elif nonmodal in (28, 30):
            self.home(nonmodal, vals, ln)
        elif nonmodal in (28.1, 30.1):
            if any(k in vals for k in "XYZ"):
                raise GcodeError(ln, f"G{nonmodal} takes no axis words (it stores the "
                                     f"current position)")
            self.stored[int(nonmodal)] = list(self.pos)
        elif nonmodal == 92:
            given = {a: vals.pop(k) for a, k in enumerate("XYZ") if k in vals}
            if not given:
                raise GcodeError(ln, "G92 needs at least one axis word")
            for a, v in given.items():
                self.g92[a] = (self.pos[a] - self.systems[self.coord][a] - self.tlo[a]
                               - v * self.scale)
            self.g92_saved = list(self.g92)
        elif nonmodal == 92.1:
            self.g92 = [0.0, 0.0, 0.0]
            self.g92_saved = [0.0, 0.0, 0.0]
        elif nonmodal == 92.2:
            self.g92 = [0.0, 0.0, 0.0]
        elif nonmodal == 92.3:
            self.g92 = list(self.g92_saved)
        if mg is not None:
            if mg == 80 and any(k in vals for k in "XYZ"):
                raise GcodeError(ln, "axis words with G80 (G80 cancels the canned cycle)")
            new_cycle = mg in _CYCLES and self.motion != mg
            self.motion = mg
            if mg not in _CYCLES:
                self.cycle_il = None
        else:
            new_cycle = False
        if nonmodal == 53 and self.motion not in (0, 1):
            raise GcodeError(ln, "G53 needs G0 or G1 in force")
        if nonmodal not in axis_users:
            has_axes = any(k in vals for k in "XYZ")
            if self.motion in _CYCLES:
                if has_axes or mg in _CYCLES:
                    self.cycle(self.motion, new_cycle, vals, ln)
                elif any(k in vals for k in "RQPL"):
                    raise GcodeError(ln, f"canned-cycle words without axis words or G"
                                         f"{self.motion}")
            elif has_axes or mg in (0, 1, 2, 3) or any(k in vals for k in "IJKR"):
                self.motion_block(nonmodal == 53, vals, ln)
        if vals:
            k = next(iter(vals))
            raise GcodeError(ln, f"unsupported word {k}{vals[k]:g} here: no code on this line "
                                 f"uses it")
        # 21: stops
        if 0 in ms:
            self.event(Pause(reason="M0"), ln)
        if 1 in ms and self.optional_stop:
            self.event(Pause(reason="M1", optional=True), ln)
        return 2 in ms or 30 in ms

    def cutter_comp(self, comp_g, vals, ln):
        if "D" in vals and comp_g not in (41, 42, 41.1, 42.1):
            raise GcodeError(ln, "D word without G41, G42, G41.1 or G42.1")
        if comp_g == 40:
            self.comp, self.comp_r = "off", 0.0
        elif comp_g is not None:
            if self.comp != "off":
                raise GcodeError(ln, "cutter compensation is already on (G40 first)")
            if self.plane != 17:
                raise GcodeError(ln, "cutter compensation is supported in G17 (XY) only")
            if comp_g in (41, 42):
                if self.radius_override is not None:
                    self.comp_r = self.radius_override
                elif "D" in vals:
                    self.comp_r = _tool_radius(self.tools, int(vals["D"]), self.scale, ln,
                                               self.prog.notes)
                elif self.loaded is not None:
                    # no D: the tool loaded by the last T.. M6 (LinuxCNC)
                    self.comp_r = _tool_radius(self.tools, self.loaded, self.scale, ln,
                                               self.prog.notes)
                else:
                    raise GcodeError(ln, f"G{comp_g} needs a D word (tool number), a tool "
                                         "loaded with T.. M6, or --radius")
            else:
                if "D" not in vals:
                    raise GcodeError(ln, f"G{comp_g} needs a D word (tool diameter)")
                if vals["D"] < 0:
                    raise GcodeError(ln, "tool diameter D must not be negative")
                self.comp_r = vals["D"] * self.scale / 2
            self.comp = "left" if comp_g in (41, 41.1) else "right"
        vals.pop("D", None)

    def path_control(self, pc, vals, ln):
        if pc is None:
            return
        if pc in (61, 61.1):
            self.path_mode, self.path_p, self.path_q = f"G{pc}", 0.0, 0.0
            return
        p = vals.pop("P", 0.0)
        q = vals.pop("Q", None)
        if p < 0 or (q is not None and q < 0):
            raise GcodeError(ln, "G64 P and Q must not be negative")
        self.path_mode = "G64"
        self.path_p = p * self.scale
        self.path_q = (p if q is None else q) * self.scale   # LinuxCNC: Q defaults to P

    def g10(self, vals, ln):
        if "L" not in vals:
            raise GcodeError(ln, "G10 needs L (L2 or L20)")
        lv = vals.pop("L")
        if lv not in (2, 20):
            what = "tool table" if lv in (1, 10, 11) else f"L{lv:g}"
            raise GcodeError(ln, f"G10 L{lv:g} ({what}) is not supported (G10 L2 and L20 are)")
        if "R" in vals:
            raise GcodeError(ln, "rotated coordinate systems (G10 L2 R) are not supported")
        if "P" not in vals:
            raise GcodeError(ln, f"G10 L{lv:g} needs P (0 current, 1-9 G54-G59.3)")
        pv = vals.pop("P")
        if pv != int(pv) or not 0 <= pv <= 9:
            raise GcodeError(ln, f"G10 L{lv:g} P must be 0-9, got P{pv:g}")
        idx = self.coord if pv == 0 else int(pv) - 1
        for a, k in enumerate("XYZ"):
            if k in vals:
                v = vals.pop(k) * self.scale
                if lv == 2:
                    self.systems[idx][a] = v
                else:   # L20: the current position becomes v in that system
                    self.systems[idx][a] = self.pos[a] - v - self.g92[a] - self.tlo[a]

    def home(self, g, vals, ln):
        if self.comp != "off":
            raise GcodeError(ln, f"G{g} with cutter compensation on (G40 first)")
        given = {a: vals.pop(k) for a, k in enumerate("XYZ") if k in vals}
        stored = self.stored[g]
        if not given:
            self.line_to("rapid", tuple(stored), ln)
            return
        mid = list(self.pos)
        for a, v in given.items():
            mid[a] = (v * self.scale + self.offset(a) if self.absolute
                      else self.pos[a] + v * self.scale)
        if mid != self.pos:                 # "G91 G28 Z0": no move to the intermediate point
            self.line_to("rapid", tuple(mid), ln)
        end = list(mid)
        for a in given:
            end[a] = stored[a]
        self.line_to("rapid", tuple(end), ln)

    def target(self, axes, machine: bool) -> list[float]:
        end = list(self.pos)
        for a, k in enumerate("XYZ"):
            if k in axes:
                v = axes[k] * self.scale
                if machine:
                    end[a] = v
                elif self.absolute:
                    end[a] = v + self.offset(a)
                else:
                    end[a] = self.pos[a] + v
        return end

    def motion_block(self, g53: bool, vals, ln):
        if self.motion is None or self.motion == 80:
            raise GcodeError(ln, "axis words without a motion mode (G0, G1, G2, G3)")
        axes = {k: vals.pop(k) for k in "XYZ" if k in vals}
        offs = {k: vals.pop(k) for k in "IJK" if k in vals}
        rword = vals.pop("R", None)
        if (offs or rword is not None) and self.motion not in (2, 3):
            raise GcodeError(ln, "I, J, K or R words outside an arc move")
        if g53 and self.comp != "off":
            raise GcodeError(ln, "G53 with cutter compensation on (G40 first)")
        end = self.target(axes, g53)
        feed = self.feed
        if self.motion in (1, 2, 3):
            if self.inverse_time:
                if self.block_f is None:
                    raise GcodeError(ln, "G93 (inverse time) needs F on every G1, G2, G3 block")
            elif feed <= 0:
                raise GcodeError(ln, "no feed rate set (F) for G1/G2/G3")
        if self.motion in (0, 1):
            if axes:
                if self.motion == 1 and self.inverse_time:
                    length = math.dist(self.pos, end)
                    feed = length * self.block_f if length > 0 else 1.0
                self.line_to("rapid" if self.motion == 0 else "line", end, ln, feed)
            return
        turns = vals.pop("P", 1.0)
        if turns != int(turns) or turns < 1:
            raise GcodeError(ln, f"arc turns P must be a whole number >= 1, got P{turns:g}")
        m = _arc(self.motion == 2, self.pos, end, offs, rword, self.plane, self.scale,
                 self.arc_absolute, feed, ln, self.comp, self.comp_r, self.offset)
        ap = PLANE_AXES[m.plane][2]
        if self.comp != "off" and (m.start[ap] != m.end[ap] or turns > 1):
            raise GcodeError(ln, "helical or multi-turn arcs with cutter compensation on are "
                                 "not supported")
        # P turns (LinuxCNC): P - 1 full circles, then the programmed arc; the axis
        # normal to the plane moves in proportion to the angle over all of them
        base = abs(arc_sweep(m))
        total = base + 2 * math.pi * (int(turns) - 1)
        pieces = []
        start = list(m.start)
        for _ in range(int(turns) - 1):
            stop = list(start)
            stop[ap] += (m.end[ap] - m.start[ap]) * 2 * math.pi / total
            pieces.append(Move("arc", tuple(start), tuple(stop), ln, feed, center=m.center,
                               cw=m.cw, plane=m.plane, comp=m.comp, radius=m.radius))
            start = stop
        m.start = tuple(start)
        pieces.append(m)
        if self.inverse_time:
            length = sum(arc_length(piece) for piece in pieces)
            for piece in pieces:
                piece.feed = length * self.block_f if length > 0 else 1.0
        for piece in pieces:
            self.add_move(piece)

    def cycle(self, g, new_cycle: bool, vals, ln):
        """Canned cycle ``g`` at this block (LinuxCNC ``convert_cycle_xy``)."""
        if self.inverse_time:
            raise GcodeError(ln, "cannot use inverse time feed (G93) with canned cycles")
        if self.comp != "off":
            raise GcodeError(ln, "cannot use canned cycles with cutter compensation on")
        if self.plane != 17:
            raise GcodeError(ln, f"canned cycles are supported in G17 only, not G{self.plane}")
        if self.feed <= 0:
            raise GcodeError(ln, f"no feed rate set (F) for G{g}")
        x = vals.pop("X", None)
        y = vals.pop("Y", None)
        z = vals.pop("Z", None)
        r = vals.pop("R", None)
        if new_cycle and z is None:
            raise GcodeError(ln, f"G{g} needs Z the first time (the bottom of the hole)")
        if new_cycle and r is None:
            raise GcodeError(ln, f"G{g} needs R the first time (the retract plane)")
        s = self.scale
        r = self.cycle_r if r is None else r * s
        z = self.cycle_z if z is None else z * s
        lv = vals.pop("L", 1.0)
        if lv != int(lv) or lv < 1:
            raise GcodeError(ln, f"L must be a whole number of repeats >= 1, got L{lv:g}")
        p = vals.pop("P", None)
        q = vals.pop("Q", None)
        if g in (82, 89):
            if p is None and (new_cycle or self.cycle_p is None):
                raise GcodeError(ln, f"G{g} needs P (the dwell in seconds)")
            p = self.cycle_p if p is None else p
            if p < 0:
                raise GcodeError(ln, f"G{g} dwell P must not be negative")
            self.cycle_p = p
        elif p is not None:
            raise GcodeError(ln, f"word P{p:g} is not used by G{g}")
        if g in (73, 83):
            if q is None and (new_cycle or self.cycle_q is None):
                raise GcodeError(ln, f"G{g} needs Q (the peck depth)")
            q = self.cycle_q if q is None else q * s
            if q <= 0:
                raise GcodeError(ln, f"G{g} peck depth Q must be positive")
            self.cycle_q = q
        elif q is not None:
            raise GcodeError(ln, f"word Q{q:g} is not used by G{g}")
        here = self.program_pos()
        current_z = here[2]
        # the initial level: Z where this series of consecutive cycle blocks began
        # (LinuxCNC's cycle_il; any other motion mode ends the series)
        if self.cycle_il is None:
            self.cycle_il = current_z
        old_z = self.cycle_il
        if self.absolute:
            inc_x = inc_y = 0.0
            aa = here[0] if x is None else x * s
            bb = here[1] if y is None else y * s
            rr, zz = r, z
        else:
            inc_x = 0.0 if x is None else x * s
            inc_y = 0.0 if y is None else y * s
            aa, bb = here[0], here[1]
            rr = r + old_z
            zz = rr + z
        if rr < zz:
            raise GcodeError(ln, f"the R plane ({rr:g} mm) is below the bottom Z ({zz:g} mm)")
        off = [self.offset(a) for a in range(3)]

        def go(kind, px, py, pz):
            end = (px + off[0], py + off[1], pz + off[2])
            if end != tuple(self.pos):      # LinuxCNC's no-op traverses are left out
                self.line_to(kind, end, ln, self.feed, "G61")

        if old_z < rr:                      # below the R plane: straight up to it first
            go("rapid", here[0], here[1], rr)
            old_z = current_z = rr
        clear = rr if self.retract_r_plane else old_z
        backoff = PECK_BACKOFF_INCH * INCH      # 0.254 mm in G21, 0.010 inch in G20
        for k in range(int(lv)):
            aa += inc_x
            bb += inc_y
            if k == 0 and current_z > rr:   # the first hole from where the tool is
                go("rapid", aa, bb, current_z)
                go("rapid", aa, bb, rr)
            else:                           # the others from the clear level
                go("rapid", aa, bb, clear)
                if clear > rr:
                    go("rapid", aa, bb, rr)
            if g in (73, 83):
                depth = rr - q
                while depth > zz:
                    go("line", aa, bb, depth)
                    if g == 83:             # out to the R plane
                        go("rapid", aa, bb, rr)
                    go("rapid", aa, bb, depth + backoff)
                    depth -= q
            go("line", aa, bb, zz)
            if g in (82, 89):
                self.event(Dwell(seconds=p), ln)
            if g == 85:                     # feed out to R, then up to the clear level
                go("line", aa, bb, rr)
                go("rapid", aa, bb, clear)
            else:                           # G89 feeds out to the clear level
                go("line" if g == 89 else "rapid", aa, bb, clear)
        self.cycle_r, self.cycle_z = r, z


def arc_length(m: Move) -> float:
    """Length of an arc ``Move`` along its (helical) path, mm."""
    a0, a1, ap = PLANE_AXES[m.plane]
    cx, cy = m.center
    radius = math.hypot(m.start[a0] - cx, m.start[a1] - cy)
    return math.hypot(radius * abs(arc_sweep(m)), m.end[ap] - m.start[ap])


FULL_TOL = 1e-9         # mm: an arc whose end is this close to its start is a full circle


def full_circle(m: Move) -> bool:
    """Is the arc a full circle: its end at its start in its plane (as G-code has it),
    or a rounding error away (a compensated circle's end comes from its angle)?"""
    a0, a1, _ = PLANE_AXES[m.plane]
    return math.hypot(m.end[a0] - m.start[a0], m.end[a1] - m.start[a1]) <= FULL_TOL


def arc_sweep(m: Move) -> float:
    """Signed swept angle of an arc ``Move`` (rad, CCW positive; a full circle 2 pi)."""
    a0, a1, _ = PLANE_AXES[m.plane]
    cx, cy = m.center
    phi0 = math.atan2(m.start[a1] - cy, m.start[a0] - cx)
    if full_circle(m):
        sweep = 2 * math.pi
    else:
        sweep = (math.atan2(m.end[a1] - cy, m.end[a0] - cx) - phi0) % (2 * math.pi)
        if m.cw:
            sweep = (2 * math.pi - sweep) % (2 * math.pi)
    return -sweep if m.cw else sweep


def _arc(cw, pos, end, offs, rword, plane, scale, arc_absolute, feed, lineno, comp, comp_r,
         offset=lambda a: 0.0):
    a0, a1, _ = PLANE_AXES[plane]
    off_letters = _OFFSET_LETTERS[plane]
    s = (pos[a0], pos[a1])
    e = (end[a0], end[a1])
    for letter in list(offs):
        if letter not in off_letters:
            if offs[letter] != 0:
                raise GcodeError(lineno, f"offset {letter} does not belong to plane G{plane} "
                                         f"(only a zero {letter} is accepted there)")
            del offs[letter]        # a zero word of the third axis, as LinuxCNC accepts
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
        if not offs:
            raise GcodeError(lineno, "arc without I/J/K offsets or R")
        o0 = offs.get(off_letters[0], 0.0) * scale
        o1 = offs.get(off_letters[1], 0.0) * scale
        c = ((o0 + offset(a0), o1 + offset(a1)) if arc_absolute
             else (s[0] + o0, s[1] + o1))
        r0 = math.hypot(s[0] - c[0], s[1] - c[1])
        r1 = math.hypot(e[0] - c[0], e[1] - c[1])
        if r0 < 1e-9:
            raise GcodeError(lineno, "arc radius is zero (centre at the start point)")
        diff = abs(r1 - r0)
        if diff > 0.5 or (diff > 0.005 and diff > 0.001 * r0):
            raise GcodeError(lineno, f"arc end point is not on the circle: radii {r0:.4f} and "
                                     f"{r1:.4f} mm differ by {diff:.4f} mm")
    return Move("arc", tuple(pos), tuple(end), lineno, feed, center=c, cw=cw, plane=plane,
                comp=comp, radius=comp_r)
