# SPDX-License-Identifier: Apache-2.0
"""``halfpoint compensate`` and ``halfpoint run``: G-code end to end.

run: parse -> cutter compensation -> quantisation -> the motion core (the
model, or any executor of encoded commands such as the Verilator-simulated RTL) -> lattice path; prints the maximum deviation of the
lattice path from the compensated path, optionally writes a plot and a CSV
trace.  The core runs at a simulation feed of 2 BLU per clock (the STEP
timing paces it); the programmed F values are kept in the compensated
G-code.
"""

from __future__ import annotations

import math
import sys
from dataclasses import dataclass, field
from pathlib import Path

from .comp import compensate, to_gcode
from .gcode import Move, load_tool_table, parse
from .geom import Arc, Line
from .quant import DEFAULT_BLU, quantise
from .segments import run_segments_model


@dataclass
class RunResult:
    programmed: list[Move]
    compensated: list[Move]
    warnings: list[str]
    lattice: list[tuple[int, int, int]]      # positions after every move (BLU)
    max_dev_mm: float
    blu: tuple[float, float, float]
    messages: list = field(default_factory=list)   # the program's (MSG/(DEBUG/(PRINT output
    notes: tuple = ()                        # choices worth printing (tool table units)
    corrections: int = 0                     # correcting lines the quantiser inserted


# the tool table used when none is named and no --radius is given
TOOL_TABLE_BESIDE = "tools.tbl"


def load_program(path: str, radius=None, tools_path=None, strict=False, window=5):
    with open(path, encoding="utf-8") as fh:
        text = fh.read()
    tools = {}
    found = None
    if tools_path is None and radius is None:
        # no table named: the one beside the program, as a LinuxCNC configuration keeps
        # its tool table beside its INI file
        beside = Path(path).resolve().parent / TOOL_TABLE_BESIDE
        if beside.is_file():
            tools_path = found = str(beside)
    if tools_path:
        with open(tools_path, encoding="utf-8") as fh:
            tools = load_tool_table(fh.read())
    # o<name> call finds name.ngc beside the program, as LinuxCNC's SUBROUTINE_PATH would
    prog = parse(text, tools=tools, radius_override=radius, source=path,
                 search_path=(str(Path(path).resolve().parent),))
    if found:
        prog.notes.insert(0, f"tool table {found} (beside the program; --tools names another)")
    comp = compensate(prog.moves, window=window, strict=strict)
    return prog, comp


def _element(m: Move):
    if m.kind == "arc":
        return Arc.from_points(m.center, m.start[:2], m.end[:2], m.cw)
    return Line(m.start[:2], m.end[:2])


def run_program(path: str, execute=run_segments_model, radius=None, tools_path=None,
                strict=False, blu=(DEFAULT_BLU,) * 3, window=5) -> RunResult:
    """``execute``: encoded commands -> positions after every move (the core
    model by default; ``halfpoint.sim.engines.core_runner("rtl")`` for the RTL)."""
    prog, comp = load_program(path, radius, tools_path, strict, window)
    q = quantise(comp.moves, blu)
    trace = execute(q.cmds)
    expected = sum(q.moves_per_cmd)
    if len(trace) != expected:
        raise RuntimeError(f"the core made {len(trace)} moves, the host predicted {expected}")
    dev = 0.0
    k = 0
    for m, n in zip(q.src, q.moves_per_cmd):
        el = _element(m)
        for p in trace[k:k + n]:
            dev = max(dev, el.distance((p[0] * blu[0], p[1] * blu[1])))
        k += n
    return RunResult(prog.moves, comp.moves, comp.warnings, trace, dev, tuple(blu),
                     prog.messages, tuple(prog.notes), q.corrections)


def _path_points(moves: list[Move], steps=64):
    xs, ys = [], []
    for m in moves:
        el = _element(m)
        n = steps if m.kind == "arc" else 1
        for i in range(n + 1):
            p = el.point(i / n)
            xs.append(p[0])
            ys.append(p[1])
        xs.append(math.nan)
        ys.append(math.nan)
    return xs, ys


def plot_run(res: RunResult, out: str, title: str, zoom=None) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(8, 8))
    feed = [m for m in res.programmed if m.kind != "rapid"]
    px, py = _path_points(feed)
    ax.plot(px, py, "--", color="0.45", lw=1.0, label="programmed path")
    lx = [p[0] * res.blu[0] for p in res.lattice]
    ly = [p[1] * res.blu[1] for p in res.lattice]
    ax.plot(lx, ly, "-", color="C0", lw=4, alpha=0.35, label="lattice path of the core")
    cx, cy = _path_points([m for m in res.compensated if m.kind != "rapid"])
    ax.plot(cx, cy, "-", color="C3", lw=0.8, label="compensated tool path")
    ax.set_aspect("equal")
    if zoom:
        ax.set_xlim(zoom[0], zoom[1])
        ax.set_ylim(zoom[2], zoom[3])
    ax.grid(True, lw=0.3)
    ax.legend(loc="best", fontsize=8)
    ax.set_title(title, fontsize=10)
    ax.set_xlabel("X (mm)")
    ax.set_ylabel("Y (mm)")
    fig.tight_layout()
    fig.savefig(out, dpi=120)
    plt.close(fig)


def write_trace(res: RunResult, out: str) -> None:
    with open(out, "w", encoding="utf-8") as fh:
        fh.write("move,x_blu,y_blu,z_blu,x_mm,y_mm,z_mm\n")
        for k, p in enumerate(res.lattice, start=1):
            fh.write(f"{k},{p[0]},{p[1]},{p[2]},{p[0] * res.blu[0]:.6f},"
                     f"{p[1] * res.blu[1]:.6f},{p[2] * res.blu[2]:.6f}\n")


def print_warnings(path: str, warnings) -> None:
    for w in warnings:
        print(f"halfpoint: {path}: warning: {w}", file=sys.stderr)


def print_messages(path: str, messages) -> None:
    """The program's (MSG, (DEBUG, and (PRINT, output, in program order, on stderr."""
    for m in messages:
        print(f"halfpoint: {m.source or path}: line {m.lineno}: {m.kind}: {m.text}",
              file=sys.stderr)


__all__ = ["load_program", "run_program", "plot_run", "write_trace", "to_gcode", "print_warnings",
           "print_messages"]
