# SPDX-License-Identifier: Apache-2.0
"""What a program does, before it runs (issue 14, item 4).

``summarise(program, machine)`` gives a ``Summary`` of a parsed program
(``halfpoint.cam.gcode.parse``): blocks, moves, tool changes, pauses and dwells,
the bounding box of the path per axis in machine mm, and the run time the
planner estimates (``halfpoint.cam.planner.plan`` / ``estimate_time`` with the
program's dwells; tool changes and pauses wait for the operator and are not
counted).  ``str(summary)`` is the printable text.

``check_travel(program, machine)`` raises ``GcodeError`` naming the first block
whose path leaves the machine's travel (``travel_min_mm`` / ``travel_max_mm``
per axis in the machine file; an axis without them is unlimited).

Both look at the programmed path in machine coordinates: arcs by their exact
extent (the quadrant points they sweep), helices with their linear axis.  The
path after cutter compensation lies up to the tool radius beside it, which is
not counted here.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace

from .gcode import (PLANE_AXES, Dwell, GcodeError, Move, Pause, ToolChange, arc_length,
                    arc_sweep)
from .items import plan_items_compensated
from .planner import estimate_time, plan

AXIS_NAMES = "XYZ"


def move_box(m: Move) -> tuple[list[float], list[float]]:
    """(lowest, highest) machine coordinate per axis reached by move ``m``."""
    lo = [min(a, b) for a, b in zip(m.start, m.end)]
    hi = [max(a, b) for a, b in zip(m.start, m.end)]
    if m.kind != "arc":
        return lo, hi
    a0, a1, _ = PLANE_AXES[m.plane]
    cx, cy = m.center
    radius = math.hypot(m.start[a0] - cx, m.start[a1] - cy)
    phi0 = math.atan2(m.start[a1] - cy, m.start[a0] - cx)
    sweep = arc_sweep(m)
    start, stop = sorted((phi0, phi0 + sweep))
    k = math.ceil(start / (math.pi / 2))
    while k * math.pi / 2 <= stop:
        q = k % 4                       # the quadrant point at k * 90 degrees
        x = cx + radius * (1, 0, -1, 0)[q]
        y = cy + radius * (0, 1, 0, -1)[q]
        lo[a0], hi[a0] = min(lo[a0], x), max(hi[a0], x)
        lo[a1], hi[a1] = min(lo[a1], y), max(hi[a1], y)
        k += 1
    return lo, hi


@dataclass
class Summary:
    blocks: int
    moves: dict                     # kind -> count ("rapid", "line", "arc", "helix")
    tool_changes: list = field(default_factory=list)    # (tool, line)
    pauses: list = field(default_factory=list)          # (reason, line)
    dwell_seconds: float = 0.0
    dwells: int = 0
    box: tuple | None = None        # ((x lo, x hi), (y lo, y hi), (z lo, z hi)) or None
    seconds: float = 0.0            # planned run time, dwells included
    ended: bool = True

    def __str__(self) -> str:
        n = sum(self.moves.values())
        plural = {"rapid": "rapids", "line": "lines", "arc": "arcs", "helix": "helices"}
        kinds = ", ".join(f"{v} {k if v == 1 else plural.get(k, k)}"
                          for k, v in self.moves.items() if v)
        out = [f"blocks: {self.blocks}, moves: {n}" + (f" ({kinds})" if kinds else "")]
        tools = ", ".join(f"T{t} (line {ln})" for t, ln in self.tool_changes) or "none"
        out.append(f"tool changes: {tools}")
        pauses = ", ".join(f"{r} (line {ln})" for r, ln in self.pauses) or "none"
        out.append(f"pauses: {pauses}")
        if self.dwells:
            out.append(f"dwells: {self.dwells}, {self.dwell_seconds:g} s in all")
        if self.box is None:
            out.append("bounding box: no motion")
        else:
            for name, (lo, hi) in zip(AXIS_NAMES, self.box):
                out.append(f"{name}: {lo:.3f} .. {hi:.3f} mm")
        minutes, sec = divmod(self.seconds, 60.0)
        when = f"{int(minutes)} min {sec:.1f} s" if minutes else f"{sec:.2f} s"
        out.append(f"estimated run time: {when} (planner; tool changes and pauses not "
                   f"counted)")
        if not self.ended:
            out.append("no M2 or M30: the program ends at the end of the file")
        return "\n".join(out)


def summarise(program, machine) -> Summary:
    """A ``Summary`` of a parsed program on ``machine`` (module docstring)."""
    moves = {"rapid": 0, "line": 0, "arc": 0, "helix": 0}
    lo = [math.inf] * 3
    hi = [-math.inf] * 3
    for m in program.moves:
        kind = m.kind
        if kind == "arc" and m.start[PLANE_AXES[m.plane][2]] != m.end[PLANE_AXES[m.plane][2]]:
            kind = "helix"
        moves[kind] = moves.get(kind, 0) + 1
        mlo, mhi = move_box(m)
        lo = [min(a, b) for a, b in zip(lo, mlo)]
        hi = [max(a, b) for a, b in zip(hi, mhi)]
    box = tuple(zip(lo, hi)) if program.moves else None
    dwells = [e for e in program.events if isinstance(e, Dwell)]
    # the items `halfpoint run` plans (its stops: dwells, output changes; in laser mode
    # not an S change alone), on the programmed moves
    seconds = estimate_time(plan(plan_items_compensated(program, program.moves, machine),
                                 machine))
    return Summary(
        blocks=program.blocks, moves=moves,
        tool_changes=[(e.tool, e.lineno) for e in program.events if isinstance(e, ToolChange)],
        pauses=[(e.reason, e.lineno) for e in program.events if isinstance(e, Pause)],
        dwell_seconds=sum(e.seconds for e in dwells), dwells=len(dwells), box=box,
        seconds=seconds, ended=program.ended)


def check_travel(program, machine) -> None:
    """Raise ``GcodeError`` naming the first block whose path leaves the machine's
    travel (``axis.<name>.travel_min_mm`` / ``travel_max_mm``)."""
    eps = 1e-9
    for m in program.moves:
        mlo, mhi = move_box(m)
        for k, axis in enumerate(machine.axes):
            name = AXIS_NAMES[k]
            if mlo[k] < axis.travel_min_mm - eps:
                raise GcodeError(m.lineno, f"this block leaves the machine's travel: {name} "
                                           f"reaches {mlo[k]:.4f} mm, below "
                                           f"axis.{axis.name}.travel_min_mm "
                                           f"{axis.travel_min_mm:g} mm")
            if mhi[k] > axis.travel_max_mm + eps:
                raise GcodeError(m.lineno, f"this block leaves the machine's travel: {name} "
                                           f"reaches {mhi[k]:.4f} mm, above "
                                           f"axis.{axis.name}.travel_max_mm "
                                           f"{axis.travel_max_mm:g} mm")
