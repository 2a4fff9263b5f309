# SPDX-License-Identifier: Apache-2.0
"""Segment files (JSON lines) for ``halfpoint segments``, and running them.

One segment per line, numbers in BLU, relative to the current position (like
G91 with G91.1); blank lines and lines starting with ``#`` are skipped:

    {"op": "line", "delta": [dx, dy, dz]}
    {"op": "arc", "dir": "cw" | "ccw", "center": [i, j], "end": [ex, ey]}

Optional on either: ``"rate"``, path speed in BLU per clock (default 2.0;
the STEP/DIR timing then sets the pace).  Arcs are in the XY plane.  Every
error names the line and the reason; an arc the core would reject is an
error of the file, found before anything runs.
"""

from __future__ import annotations

import json
from dataclasses import dataclass

from ..spec import encoding as enc
from ..spec.arc import ERR_TEXT as ARC_ERR_TEXT
from ..spec.arc import validate

AXES = 3
WIDTH = 32
DEFAULT_RATE = 2.0


class SegmentError(ValueError):
    def __init__(self, lineno: int, reason: str):
        self.lineno = lineno
        super().__init__(f"line {lineno}: {reason}")


@dataclass
class Segment:
    lineno: int
    cmd: int          # encoded core command


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
        allowed = {"op", "rate"} | ({"delta"} if op == "line" else {"dir", "center", "end"})
        extra = sorted(set(obj) - allowed)
        rate = obj.get("rate", DEFAULT_RATE)
        if isinstance(rate, bool) or not isinstance(rate, (int, float)) or not 0 < rate < 256:
            raise SegmentError(lineno, '"rate" must be a number of BLU per clock in (0, 256)')
        rate_q = max(1, round(rate * enc.RATE_ONE))
        if op == "line":
            if extra:
                raise SegmentError(lineno, f"unknown key {extra[0]!r} for a line")
            d = _int_list(obj, "delta", 1, AXES, lineno)
            out.append(Segment(lineno, enc.encode_line(d + [0] * (AXES - len(d)), rate_q)))
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
            out.append(Segment(lineno, enc.encode_arc(cw, i, j, ex, ey, rate_q)))
        else:
            raise SegmentError(lineno, f'"op" must be "line" or "arc", got {op!r}')
    return out


def run_segments_model(cmds) -> list[tuple[int, ...]]:
    """Positions after every move, from the cycle-accurate core model."""
    from ..spec.core import CoreModel, run_program
    from ..spec.stepgen import StepCfg

    run = run_program(CoreModel(AXES, WIDTH, 16, 16, [StepCfg(1, 0, 0, 0)] * AXES), cmds)
    if run.errors:
        raise RuntimeError(f"the core rejected a command (codes {run.errors})")
    return run.trace
