# SPDX-License-Identifier: Apache-2.0
"""Segment files (JSON lines) for ``halfpoint segments``, and running them.

One segment per line, numbers in BLU, relative to the current position (like
G91 with G91.1); blank lines and lines starting with ``#`` are skipped:

    {"op": "line", "delta": [dx, dy, dz]}
    {"op": "arc", "dir": "cw" | "ccw", "center": [i, j], "end": [ex, ey]}

Optional on either: ``"speed"``, the cruise path speed in BLU of X per clock,
0 < speed < 1 (default ``DEFAULT_SPEED``, 0.25), and ``"accel"``, the path
acceleration in BLU per clock^2, 0 < accel < 2^-12 (default ``DEFAULT_ACCEL``: from
rest to the default speed in 8 ticks).  The profile stage's tick is 2^``DIV`` clocks
(DIV = 8).  Junctions are planned at the smaller of the two segments' speeds, the file
starts and ends at rest, and ``spec.profile.plan_integer`` lowers every junction a
segment cannot reach or leave (its backward and forward passes) and gives each
PROFILE its bit-exact distances.  Arcs are in the XY plane.  Every error names the
line and the reason; an arc the core would reject is an error of the file, found
before anything runs.
"""

from __future__ import annotations

import json
import math
from dataclasses import astuple, dataclass

from ..spec import encoding as enc
from ..spec import profile as pf
from ..spec.arc import ERR_TEXT as ARC_ERR_TEXT
from ..spec.arc import validate
from ..spec.core import decode_for_core
from ..spec.program import line_cost, profiled, segment_moves
from ..spec.stepgen import StepCfg
from .motion import CoreConfig, run_model

AXES = 3
WIDTH = 32
DIV = 8                          # profile tick: 256 clocks
DEFAULT_SPEED = 0.25             # BLU per clock
DEFAULT_ACCEL = DEFAULT_SPEED / (8 << DIV)      # BLU per clock^2
MAX_ACCEL = 2.0 ** -12           # a speed step per tick < 2^-4 BLU per clock
# the core the segment files run on: STEP one clock high, no gap, no DIR setup or hold
CONFIG = CoreConfig(AXES, WIDTH, DIV, tuple(StepCfg(1, 0, 0, 0) for _ in range(AXES)))


class SegmentError(ValueError):
    def __init__(self, lineno: int, reason: str):
        self.lineno = lineno
        super().__init__(f"line {lineno}: {reason}")


@dataclass
class Segment:
    lineno: int
    cmd: int          # encoded core command (no CONT)
    speed: int        # cruise speed, field units (BLU per clock x 2^32)
    accel: int        # speed step per tick (BLU per clock x 2^38)


def _int_list(obj, key, n_min, n_max, lineno):
    v = obj.get(key)
    if not isinstance(v, list) or not n_min <= len(v) <= n_max:
        raise SegmentError(lineno, f'"{key}" must be a list of {n_min}..{n_max} integers')
    for x in v:
        if isinstance(x, bool) or not isinstance(x, int):
            raise SegmentError(lineno, f'"{key}" must hold integers (BLU), got {x!r}')
        if not -(1 << (WIDTH - 1)) <= x < (1 << (WIDTH - 1)):
            raise SegmentError(lineno, f'"{key}" value {x} does not fit {WIDTH} bits')
    return v


def _number(obj, key, default, top, lineno, what):
    v = obj.get(key, default)
    if isinstance(v, bool) or not isinstance(v, (int, float)) or not 0 < v < top \
            or not math.isfinite(v):
        raise SegmentError(lineno, f'"{key}" must be a number of {what} in (0, {top:g}), '
                                   f'got {v!r}')
    return v


def parse_segments(text: str) -> list[Segment]:
    out = []
    for lineno, raw in enumerate(text.splitlines(), start=1):
        line = raw.strip()
        if not line or line.startswith("#"):
            continue
        try:
            obj = json.loads(line)
        except json.JSONDecodeError as exc:
            raise SegmentError(lineno, f"not valid JSON ({exc.msg})") from None
        if not isinstance(obj, dict):
            raise SegmentError(lineno, "a segment must be a JSON object")
        op = obj.get("op")
        if "rate" in obj:
            raise SegmentError(lineno, '"rate" is gone: give "speed" (BLU per clock, < 1) '
                                       'and optionally "accel" (BLU per clock^2)')
        allowed = {"op", "speed", "accel"} | ({"delta"} if op == "line"
                                               else {"dir", "center", "end"})
        extra = sorted(set(obj) - allowed)
        speed = _number(obj, "speed", DEFAULT_SPEED, 1, lineno, "BLU per clock")
        accel = _number(obj, "accel", DEFAULT_ACCEL, MAX_ACCEL, lineno, "BLU per clock^2")
        v = math.floor(speed * (1 << pf.FIELD_SPEED_FRAC))
        a = round(accel * (1 << DIV) * (1 << pf.SPEED_FRAC))
        if v == 0:
            raise SegmentError(lineno, f'"speed" {speed!r} is below the field\'s LSB 2^-32')
        if a == 0:
            raise SegmentError(lineno, f'"accel" {accel!r} rounds to 0 (LSB 2^-38 BLU per '
                                       f'clock per tick of 2^{DIV} clocks)')
        if op == "line":
            if extra:
                raise SegmentError(lineno, f"unknown key {extra[0]!r} for a line")
            d = _int_list(obj, "delta", 1, AXES, lineno)
            if not any(d):
                raise SegmentError(lineno, "a line must move (all deltas are 0)")
            out.append(Segment(lineno, enc.encode_line(d + [0] * (AXES - len(d))), v, a))
        elif op == "arc":
            if extra:
                raise SegmentError(lineno, f"unknown key {extra[0]!r} for an arc")
            if obj.get("dir") not in ("cw", "ccw"):
                raise SegmentError(lineno, '"dir" must be "cw" or "ccw"')
            i, j = _int_list(obj, "center", 2, 2, lineno)
            ex, ey = _int_list(obj, "end", 2, 2, lineno)
            cw = int(obj["dir"] == "cw")
            code = validate(-i, -j, ex - i, ey - j, WIDTH)
            if code:
                raise SegmentError(lineno, f"arc rejected: {ARC_ERR_TEXT[code]}")
            out.append(Segment(lineno, enc.encode_arc(cw, i, j, ex, ey), v, a))
        else:
            raise SegmentError(lineno, f'"op" must be "line" or "arc", got {op!r}')
    return out


def segment_items(segs: list[Segment]) -> list[int]:
    """The command stream of a segment file: a PROFILE before every segment (module
    docstring), CONT on every segment but the last."""
    lengths, lcs = [], []
    for sg in segs:
        dec = decode_for_core(sg.cmd, AXES, WIDTH)
        steps, classes = segment_moves(dec, WIDTH, AXES)
        lc = line_cost(dec[1]) if dec[0] == "line" else 0
        prm = pf.ProfileParams(1, 0, 1, lc)
        lengths.append(sum(pf.move_cost(c, prm) for c in classes))
        lcs.append(lc)
    n = len(segs)
    vc = [sg.speed for sg in segs]
    exits = [min(vc[k], vc[k + 1]) if k < n - 1 else 0 for k in range(n)]
    plans = pf.plan_integer(lengths, vc, exits, [sg.accel for sg in segs], DIV, lcs)
    out = []
    for k, (sg, p) in enumerate(zip(segs, plans)):
        out.append(enc.encode_profile(*astuple(p)))
        out.append(sg.cmd | enc.FLAG_CONT if k < n - 1 else sg.cmd)
    return out


def run_segments_model(cmds) -> list[tuple[int, ...]]:
    """Positions after every move of bare motion commands (no PROFILEs: each gets one
    at ``DEFAULT_SPEED`` and ``DEFAULT_ACCEL``, junctions at full speed where
    ``plan_integer`` allows), from the core model."""
    v = math.floor(DEFAULT_SPEED * (1 << pf.FIELD_SPEED_FRAC))
    a = round(DEFAULT_ACCEL * (1 << DIV) * (1 << pf.SPEED_FRAC))
    items = profiled(list(cmds), AXES, WIDTH, DIV, v, a, junction=v)
    run = run_model(items, CONFIG)
    if run.errors:
        raise RuntimeError(f"the core rejected a command (codes {run.errors})")
    return [p for _, p in run.moves]
