# SPDX-License-Identifier: Apache-2.0
"""The machine file: a machine's units, limits and STEP/DIR timing, in TOML.

```toml
clock_hz = 50_000_000              # the core's clock
[axis.x]                           # also [axis.y] and [axis.z]; all three are required
blu_mm = 0.001                     # one lattice step (basic length unit)
max_velocity_mm_s = 100.0
max_accel_mm_s2 = 1000.0
steplen_ns = 2000                  # optional STEP/DIR timing, defaults in TIMING_DEFAULTS_NS
stepspace_ns = 2000
dirsetup_ns = 5000
dirhold_ns = 5000
[planner]
junction_deviation_mm = 0.01
```

Every key in the example above without a ``_ns`` suffix is required; the four
timing keys are optional per axis.  Also optional:

* per axis ``travel_min_mm`` / ``travel_max_mm``: the axis's travel in machine
  coordinates (absent: unlimited on that side); ``halfpoint.cam.summary.check_travel``
  refuses a program that leaves it.  ``travel_min_mm`` must be below ``travel_max_mm``.
* ``[positions]`` ``g28 = [x, y, z]`` and ``g30 = [x, y, z]``: the stored G28 and G30
  positions in machine mm (LinuxCNC keeps them in parameters #5161-#5163 and
  #5181-#5183); default the machine origin.  ``halfpoint.cam.gcode.parse`` takes them
  with ``positions=machine``.
* ``[spindle]`` ``max_speed`` (S of a 100 % PWM duty, default 1000: grbl's ``$30``),
  ``min_speed`` (default 0, grbl's ``$31``: a non-zero S below it runs at it;
  ``min_speed`` < ``max_speed``), ``laser_mode`` (default false, grbl's ``$32``: the
  PWM is off at rest and during G0, and under M4 it follows the path speed over
  the programmed feed, so the power per length stays constant).  The duty of S is
  ``clamp(S, min_speed, max_speed) / max_speed`` (S 0: 0 %).  A bad file raises
  ``MachineError`` whose
message starts with the dotted key (``axis.x.max_accel_mm_s2: must be > 0``):
an unknown key anywhere, a missing required value, a wrong type (``true`` is
not a number; ``clock_hz`` must be a whole number), a limit <= 0, a negative
time or junction deviation, a time that does not fit the core's timing
registers, and an axis speed above the STEP rate its timing allows.

STEP/DIR timing (README, "The step generator", LinuxCNC / hostmot2 meanings)
is given in ns and turned into clock ticks, always rounded *up*, so the pins
are never faster than asked:

* ``steplen``   STEP active for exactly max(ticks, 1) clocks;
* ``stepspace`` STEP inactive for at least max(ticks, 1) clocks between steps;
* ``dirsetup``  DIR changes at least this many clocks before STEP goes active;
* ``dirhold``   DIR changes at least this many clocks after STEP went inactive.

``steplen`` and ``stepspace`` are at least 1 tick (what the generator does with
0 anyway); ``dirsetup`` and ``dirhold`` may be 0.  The fastest STEP rate of an
axis is clock_hz / (steplen + stepspace ticks) steps per second, so
``max_velocity_mm_s / blu_mm`` must not exceed it.  Every tick count must fit
the core's timing width (``TIMING_WIDTH`` bits, the RTL's default ``TW``).

Ranges the machine file accepts include clocks of 10-200 MHz, BLUs of
0.1-10 um, speeds of 0.1-500 mm/s and accelerations of 10-50,000 mm/s^2 (each
on its own: a fast axis on a fine BLU still needs a STEP rate the clock and
timing can give).

``check_program(machine, moves)`` checks a machine against a program: the two
axes of every arc's plane (X Y in G17, Z X in G18, Y Z in G19) must share the
BLU (arcs are circles on the lattice).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from fractions import Fraction
from importlib.resources import files
from pathlib import Path

try:
    import tomllib
except ModuleNotFoundError:          # Python 3.10
    import tomli as tomllib

AXES = ("x", "y", "z")
TIMING_KEYS = ("steplen_ns", "stepspace_ns", "dirsetup_ns", "dirhold_ns")
# defaults in ns: generous enough for common microstepping drives (2 us pulses,
# 5 us direction setup and hold); at 50 MHz 100 + 100 ticks, 250 kHz STEP rate
TIMING_DEFAULTS_NS = {"steplen_ns": 2000, "stepspace_ns": 2000,
                      "dirsetup_ns": 5000, "dirhold_ns": 5000}
AXIS_REQUIRED = ("blu_mm", "max_velocity_mm_s", "max_accel_mm_s2")
TRAVEL_KEYS = ("travel_min_mm", "travel_max_mm")
POSITION_KEYS = ("g28", "g30")
PLANNER_REQUIRED = ("junction_deviation_mm",)
SPINDLE_KEYS = ("max_speed", "min_speed", "laser_mode")
# the core's STEP/DIR timing registers are TW bits wide (rtl/halfpoint_core.v, default 16)
TIMING_WIDTH = 16


class MachineError(ValueError):
    """A bad machine file or a machine that cannot run a program; ``key`` is the dotted key."""

    def __init__(self, key: str, reason: str, source: str = ""):
        self.key = key
        self.reason = reason
        self.source = source
        where = f"{source}: " if source else ""
        super().__init__(f"{where}{key}: {reason}")


@dataclass(frozen=True)
class StepTiming:
    """STEP/DIR timing of one axis in clock ticks (what the core's cfg_* inputs take)."""

    steplen: int
    stepspace: int
    dirsetup: int
    dirhold: int


@dataclass(frozen=True)
class Axis:
    name: str
    blu_mm: float
    max_velocity_mm_s: float
    max_accel_mm_s2: float
    timing: StepTiming
    timing_ns: dict
    travel_min_mm: float = -math.inf     # machine coordinates; -inf / inf: unlimited
    travel_max_mm: float = math.inf

    def max_step_rate(self, clock_hz: int) -> float:
        """Fastest STEP rate the timing allows, steps per second."""
        return clock_hz / (max(self.timing.steplen, 1) + max(self.timing.stepspace, 1))


@dataclass(frozen=True)
class Machine:
    clock_hz: int
    axes: tuple          # (Axis x, Axis y, Axis z)
    junction_deviation_mm: float
    source: str = ""
    g28: tuple = (0.0, 0.0, 0.0)        # stored G28 / G30 positions, machine mm
    g30: tuple = (0.0, 0.0, 0.0)
    spindle_max: float = 1000.0         # S of a 100 % PWM duty
    spindle_min: float = 0.0            # a non-zero S below it runs at it
    laser_mode: bool = False            # grbl's $32

    def axis(self, name: str) -> Axis:
        return self.axes[AXES.index(name)]

    @property
    def blu(self) -> tuple:
        return tuple(a.blu_mm for a in self.axes)

    @property
    def max_velocity(self) -> tuple:
        return tuple(a.max_velocity_mm_s for a in self.axes)

    @property
    def max_accel(self) -> tuple:
        return tuple(a.max_accel_mm_s2 for a in self.axes)


def ns_to_ticks(ns, clock_hz: int, minimum: int = 0) -> int:
    """Clock ticks covering at least ``ns`` nanoseconds at ``clock_hz``: rounded up
    exactly (no float error), and at least ``minimum``."""
    ticks = math.ceil(Fraction(ns) * Fraction(clock_hz) / 10**9)
    return max(ticks, minimum)


def _number(value, key: str, source: str) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise MachineError(key, f"must be a number, got {type(value).__name__} {value!r}", source)
    if not math.isfinite(value):
        raise MachineError(key, f"must be finite, got {value!r}", source)
    return value


def _positive(value, key: str, source: str) -> float:
    v = _number(value, key, source)
    if v <= 0:
        raise MachineError(key, f"must be > 0, got {v!r}", source)
    return float(v)


def _table(value, key: str, source: str) -> dict:
    if not isinstance(value, dict):
        raise MachineError(key, f"must be a table ([{key}]), got {type(value).__name__}", source)
    return value


def _unknown(table: dict, allowed, prefix: str, source: str) -> None:
    for k in table:
        if k not in allowed:
            key = f"{prefix}{k}"
            raise MachineError(key, f"unknown key (allowed here: {', '.join(allowed)})", source)


def _missing(table: dict, required, prefix: str, source: str) -> None:
    for k in required:
        if k not in table:
            raise MachineError(f"{prefix}{k}", "missing required value", source)


def from_dict(data: dict, source: str = "") -> Machine:
    """Check a parsed machine file and build the ``Machine`` (see the module docstring)."""
    _table(data, "machine file", source)
    _unknown(data, ("clock_hz", "axis", "planner", "positions", "spindle"), "", source)
    _missing(data, ("clock_hz", "axis", "planner"), "", source)
    clock = _number(data["clock_hz"], "clock_hz", source)
    if isinstance(clock, float):
        if not clock.is_integer():
            raise MachineError("clock_hz", f"must be a whole number of Hz, got {clock!r}", source)
        clock = int(clock)
    if clock <= 0:
        raise MachineError("clock_hz", f"must be > 0, got {clock!r}", source)

    axes_t = _table(data["axis"], "axis", source)
    _unknown(axes_t, AXES, "axis.", source)
    _missing(axes_t, AXES, "axis.", source)
    axes = []
    for name in AXES:
        prefix = f"axis.{name}."
        t = _table(axes_t[name], f"axis.{name}", source)
        _unknown(t, AXIS_REQUIRED + TIMING_KEYS + TRAVEL_KEYS, prefix, source)
        _missing(t, AXIS_REQUIRED, prefix, source)
        blu = _positive(t["blu_mm"], prefix + "blu_mm", source)
        vmax = _positive(t["max_velocity_mm_s"], prefix + "max_velocity_mm_s", source)
        amax = _positive(t["max_accel_mm_s2"], prefix + "max_accel_mm_s2", source)
        ns, ticks = {}, {}
        for k in TIMING_KEYS:
            v = _number(t.get(k, TIMING_DEFAULTS_NS[k]), prefix + k, source)
            if v < 0:
                raise MachineError(prefix + k, f"must be >= 0 ns, got {v!r}", source)
            ns[k] = v
            minimum = 1 if k in ("steplen_ns", "stepspace_ns") else 0
            n = ns_to_ticks(v, clock, minimum)
            if n >= 1 << TIMING_WIDTH:
                raise MachineError(prefix + k, f"{v!r} ns is {n} ticks at {clock} Hz, more than "
                                   f"the core's {TIMING_WIDTH}-bit timing registers hold "
                                   f"({(1 << TIMING_WIDTH) - 1})", source)
            ticks[k[:-3]] = n
        timing = StepTiming(**ticks)
        lo = float(_number(t["travel_min_mm"], prefix + "travel_min_mm", source)
                   if "travel_min_mm" in t else -math.inf)
        hi = float(_number(t["travel_max_mm"], prefix + "travel_max_mm", source)
                   if "travel_max_mm" in t else math.inf)
        if lo >= hi:
            raise MachineError(prefix + "travel_max_mm", f"must be above travel_min_mm "
                               f"({lo!r}), got {hi!r}", source)
        axis = Axis(name, blu, vmax, amax, timing, ns, lo, hi)
        rate = axis.max_step_rate(clock)
        need = vmax / blu
        if need > rate:
            raise MachineError(
                prefix + "max_velocity_mm_s",
                f"{vmax:g} mm/s at blu_mm {blu:g} needs {need:.6g} steps/s, but the STEP timing "
                f"allows at most {rate:.6g} (clock_hz / (steplen + stepspace) = {clock} / "
                f"({timing.steplen} + {timing.stepspace}) ticks); lower the speed or the "
                f"timing, or use a coarser BLU", source)
        axes.append(axis)

    planner = _table(data["planner"], "planner", source)
    _unknown(planner, PLANNER_REQUIRED, "planner.", source)
    _missing(planner, PLANNER_REQUIRED, "planner.", source)
    jd = _number(planner["junction_deviation_mm"], "planner.junction_deviation_mm", source)
    if jd < 0:
        raise MachineError("planner.junction_deviation_mm",
                           f"must be >= 0 (0 stops at every corner), got {jd!r}", source)
    positions = {}
    if "positions" in data:
        pos_t = _table(data["positions"], "positions", source)
        _unknown(pos_t, POSITION_KEYS, "positions.", source)
        for k, v in pos_t.items():
            key = f"positions.{k}"
            if not isinstance(v, list) or len(v) != 3:
                raise MachineError(key, f"must be an array of three numbers [x, y, z] in mm, "
                                   f"got {v!r}", source)
            positions[k] = tuple(float(_number(c, key, source)) for c in v)
    spindle = {}
    if "spindle" in data:
        sp_t = _table(data["spindle"], "spindle", source)
        _unknown(sp_t, SPINDLE_KEYS, "spindle.", source)
        if "max_speed" in sp_t:
            spindle["spindle_max"] = _positive(sp_t["max_speed"], "spindle.max_speed", source)
        if "min_speed" in sp_t:
            lo = float(_number(sp_t["min_speed"], "spindle.min_speed", source))
            if lo < 0:
                raise MachineError("spindle.min_speed", f"must be >= 0, got {lo!r}", source)
            spindle["spindle_min"] = lo
        if spindle.get("spindle_min", 0.0) >= spindle.get("spindle_max", 1000.0):
            raise MachineError("spindle.min_speed", "must be below spindle.max_speed "
                               f"({spindle.get('spindle_max', 1000.0)!r})", source)
        if "laser_mode" in sp_t:
            if not isinstance(sp_t["laser_mode"], bool):
                raise MachineError("spindle.laser_mode", "must be true or false, got "
                                   f"{sp_t['laser_mode']!r}", source)
            spindle["laser_mode"] = sp_t["laser_mode"]
    return Machine(clock, tuple(axes), float(jd), source, **positions, **spindle)


def loads(text: str, source: str = "") -> Machine:
    """Read a machine file from its text; ``source`` names it in errors."""
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as e:
        raise MachineError("machine file", f"not valid TOML: {e}", source) from None
    return from_dict(data, source)


def load(path) -> Machine:
    """Read a machine file."""
    p = Path(path)
    try:
        text = p.read_text(encoding="utf-8")
    except OSError as e:
        raise MachineError("machine file", f"cannot read: {e.strerror or e}", str(p)) from None
    return loads(text, str(p))


def load_default() -> Machine:
    """The example machine shipped inside the package (``halfpoint/data/machine.toml``,
    the same file as ``examples/machine.toml``): what ``halfpoint run`` uses when no
    machine file is given."""
    text = files("halfpoint").joinpath("data", "machine.toml").read_text(encoding="utf-8")
    return loads(text, "halfpoint/data/machine.toml (the example machine)")


def check_program(machine: Machine, moves) -> None:
    """Can ``machine`` run ``moves`` (``halfpoint.cam.gcode.Move``)?  The two axes of
    every arc's plane (X Y in G17, Z X in G18, Y Z in G19) must share the BLU: arcs
    are circles on the lattice."""
    from .gcode import PLANE_AXES

    names = AXES
    for m in moves:
        if getattr(m, "kind", None) != "arc":
            continue
        a0, a1, _ = PLANE_AXES[m.plane]
        b0, b1 = machine.axes[a0].blu_mm, machine.axes[a1].blu_mm
        if b0 != b1:
            raise MachineError(
                f"axis.{names[a1]}.blu_mm",
                f"{b1:g} differs from axis.{names[a0]}.blu_mm {b0:g}, and the program has "
                f"arcs in G{m.plane} (first on line {m.lineno}): an arc needs the two axes "
                f"of its plane to share the BLU",
                machine.source)
