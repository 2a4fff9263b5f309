# SPDX-License-Identifier: Apache-2.0
"""``halfpoint compensate`` and ``halfpoint run``: G-code end to end.

run: parse (with the machine's stored positions) -> summary and travel check ->
cutter compensation -> quantisation -> ``cam.motion`` (the planner's speeds as a
PROFILE before every motion command, dwells as pauses) -> an executor (the core
model, or the Verilator-simulated RTL: ``halfpoint.sim.engines.executor``) ->
every move with its clock cycle.  ``RunResult`` has the lattice path, the cycles,
the flags and the maximum deviation of the lattice path from the compensated path;
``write_trace`` writes the trace CSV, ``plot_run`` the paths, ``plot_profile`` the
path speed against time.

The trace CSV: header ``cycle,x,y,z`` (one column per axis), first row the start
(cycle 0, the origin), then one row per move: the clock cycle of the edge that made
the move (cycle 0 is the first clock after reset) and the absolute position after
it, in BLU.
"""

from __future__ import annotations

import math
import sys
from dataclasses import dataclass, field, replace
from pathlib import Path

from ..spec import encoding as enc
from ..spec import profile as pf
from .comp import compensate, line_ranges, to_gcode
from .gcode import PLANE_AXES, Move, load_tool_table, parse
from .geom import Line, Spiral
from .items import output_settings, plan_items_compensated
from .machine import Machine, check_program, load_default
from .motion import Execution, MotionPlan, build_motion, core_config, max_clocks_for, run_model
from .planner import Dwell, Segment, estimate_time
from .quant import quantise
from .summary import Summary, check_travel, summarise


@dataclass
class RunResult:
    programmed: list[Move]
    compensated: list[Move]
    warnings: list[str]
    lattice: list[tuple[int, ...]]           # positions after every move (BLU)
    max_dev_mm: float
    blu: tuple
    messages: list = field(default_factory=list)   # the program's (MSG/(DEBUG/(PRINT output
    notes: tuple = ()                        # choices worth printing (tool table units)
    corrections: int = 0                     # correcting lines the quantiser inserted
    machine: Machine | None = None
    summary: Summary | None = None
    motion: MotionPlan | None = None
    execution: Execution | None = None
    holds: tuple = ()

    @property
    def cycles(self) -> list[int]:
        """Clock cycle of the edge that made each move."""
        return [c for c, _ in self.execution.moves]

    @property
    def seconds(self) -> float:
        """Simulated time of the run (its cycles at the machine's clock)."""
        return self.execution.cycles / self.machine.clock_hz


# the tool table used when none is named and no --radius is given
TOOL_TABLE_BESIDE = "tools.tbl"


def load_program(path: str, radius=None, tools_path=None, strict=False, window=5,
                 machine: Machine | None = None):
    """Parse (the stored G28 / G30 positions from ``machine``), summarise, check the
    travel and compensate: returns (program, compensation, summary)."""
    machine = machine or load_default()
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
                 search_path=(str(Path(path).resolve().parent),), positions=machine)
    if found:
        prog.notes.insert(0, f"tool table {found} (beside the program; --tools names another)")
    summary = summarise(prog, machine)
    check_travel(prog, machine)
    comp = compensate(prog.moves, window=window, strict=strict)
    return prog, comp, summary


def _element(m: Move):
    """The move as a plane element and the two axes of that plane: an arc in its own
    plane (G17 X Y, G18 Z X, G19 Y Z), a line in XY."""
    if m.kind == "arc":
        a0, a1, _ = PLANE_AXES[m.plane]
        # as it runs (and the quantiser measures it): LinuxCNC's spiral, the circular
        # arc when its end is on the start's circle
        return (Spiral.from_points(m.center, (m.start[a0], m.start[a1]),
                                   (m.end[a0], m.end[a1]), m.cw), (a0, a1))
    return Line(m.start[:2], m.end[:2]), (0, 1)


class EngineError(RuntimeError):
    """The core (model or RTL) did not run a planned program as the host planned it:
    still busy past the run's bound, a command rejected, or another number of moves.
    A program the host accepted should never get here: it is a defect to report."""


def plan_motion(prog, comp, machine: Machine, width: int = 32):
    """The compensated program ``comp`` of ``prog`` (``load_program``) as the core's
    command stream: its travel checked against the machine, quantised, and planned with
    its dwells and its spindle, laser and coolant changes; ``(q, MotionPlan)``.  What
    ``halfpoint run`` executes and ``halfpoint send`` sends."""
    check_program(machine, comp.moves)
    q = quantise(comp.moves, machine.blu, width)
    return q, build_motion(q, plan_items_compensated(prog, comp.moves, machine), machine,
                           width)


def run_program(path: str, execute=None, radius=None, tools_path=None, strict=False,
                machine: Machine | None = None, holds=(), window=5, width: int = 32,
                blu=None) -> RunResult:
    """``execute``: an executor ``(items, CoreConfig, holds, max_clocks=) -> Execution``
    (``cam.motion.run_model`` by default; ``halfpoint.sim.engines.executor("rtl")`` for
    the RTL).  ``machine``: the machine file (default ``machine.load_default()``);
    ``holds``: (A, B) cycle intervals with hold high.  ``blu``: (x, y, z) in mm to
    replace the machine's BLUs (a coarse lattice for short test runs)."""
    machine = machine or load_default()
    if blu is not None:
        machine = replace(machine, axes=tuple(replace(a, blu_mm=float(b))
                                              for a, b in zip(machine.axes, blu)))
    prog, comp, summary = load_program(path, radius, tools_path, strict, window, machine)
    q, motion = plan_motion(prog, comp, machine, width)
    blu = machine.blu
    holds = tuple((int(a), int(b)) for a, b in holds)
    # a bound against a hung run: three times the planned time, plus holds and pauses
    planned_s = estimate_time(motion.planned)
    limit = max_clocks_for(motion.items, holds,
                           10_000_000 + 3 * math.ceil(planned_s * machine.clock_hz))
    try:
        ex = (execute or run_model)(motion.items, core_config(machine, width), holds,
                                    max_clocks=limit)
    except RuntimeError as exc:     # an executor's "still busy", the RTL engine's failure
        raise EngineError(f"{exc} (the run's bound: three times the planned "
                          f"{planned_s:.3f} s, plus holds and dwells)") from exc
    if ex.errors:
        codes = ", ".join(f"{c} ({enc.ERR_TEXT.get(c, 'unknown')})" for c in ex.errors)
        raise EngineError(f"the core rejected a command the host planned: code {codes}")
    trace = [p for _, p in ex.moves]
    expected = sum(q.moves_per_cmd)
    if len(trace) != expected:
        raise EngineError(f"the core made {len(trace)} moves, the host predicted {expected}")
    dev = 0.0
    k = 0
    for m, n in zip(q.src, q.moves_per_cmd):
        el, (a0, a1) = _element(m)
        for p in trace[k:k + n]:
            dev = max(dev, el.distance((p[a0] * blu[a0], p[a1] * blu[a1])))
        k += n
    notes = tuple(prog.notes)
    if q.steep:
        notes += (f"{line_ranges(sorted(q.steep))}: helix steeper than the core's helix "
                  "mapper steps (one step of the normal axis per arc move): run as short "
                  "lines along the arc",)
    return RunResult(prog.moves, comp.moves, comp.warnings, trace, dev, tuple(blu),
                     prog.messages, notes, q.corrections, machine, summary,
                     motion, ex, holds)


def _path_points(moves: list[Move], steps=64):
    xs, ys = [], []
    for m in moves:
        el, (a0, a1) = _element(m)
        n = steps if m.kind == "arc" else 1
        for i in range(n + 1):
            p = list(m.start)
            p[a0], p[a1] = el.point(i / n)
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
    """The trace CSV (module docstring)."""
    names = "xyzabc"[:len(res.blu)]
    with open(out, "w", encoding="utf-8") as fh:
        fh.write("cycle," + ",".join(names) + "\n")
        fh.write("0," + ",".join("0" for _ in names) + "\n")
        for c, p in res.execution.moves:
            fh.write(f"{c}," + ",".join(str(v) for v in p) + "\n")


def move_costs(res: RunResult) -> list[float]:
    """Path length (mm) of every move as the core's profile stage counts it: a line
    iteration its line's length over its iterations (``line_cost``), an arc move its
    step (1 or sqrt(2) BLU)."""
    bx = res.blu[0]
    costs = []
    k = 0
    prev = (0,) * len(res.blu)
    for pc in res.motion.commands:
        if pc.kind == "line":
            c = pc.profile.line_cost * bx / (1 << pf.COST_FRAC)
            costs += [c] * pc.moves
            k += pc.moves
            prev = res.lattice[k - 1]
            continue
        for p in res.lattice[k:k + pc.moves]:
            costs.append(math.hypot(p[0] - prev[0], p[1] - prev[1]) * bx)
            prev = p
        k += pc.moves
    return costs


def measured_speeds(res: RunResult, bins: int = 400):
    """(bin start times s, path speed mm/s, per-axis speeds mm/s) from the trace: the
    path (``move_costs``) and each axis's distance moved in each bin of equal clocks,
    over the bin's time."""
    clock = res.machine.clock_hz
    total = max(res.execution.cycles, 1)
    width = max(total // bins, 1)
    nb = total // width + 1
    path = [0.0] * nb
    axes = [[0.0] * nb for _ in res.blu]
    prev = (0,) * len(res.blu)
    for (c, p), cost in zip(res.execution.moves, move_costs(res)):
        b = c // width
        path[b] += cost
        for k, (u, v, s) in enumerate(zip(prev, p, res.blu)):
            axes[k][b] += (v - u) * s
        prev = p
    dt = width / clock
    times = [b * dt for b in range(nb)]
    return times, [x / dt for x in path], [[x / dt for x in a] for a in axes]


def planned_speeds(res: RunResult):
    """(times s, planned path speed mm/s, speed limit mm/s) of the planner's profile,
    dwells at rest."""
    ts, vs, lims = [], [], []
    t = 0.0
    for item in res.motion.planned:
        if isinstance(item, Dwell):
            ts += [t, t + item.seconds]
            vs += [0.0, 0.0]
            lims += [math.nan, math.nan]
            t += item.seconds
            continue
        seg: Segment = item
        if seg.duration <= 0:
            continue
        n = 24
        for i in range(n + 1):
            ti = seg.duration * i / n
            ts.append(t + ti)
            vs.append(seg.speed_at(ti))
            lims.append(seg.v_limit)
        t += seg.duration
    return ts, vs, lims


def plot_profile(res: RunResult, out: str, title: str) -> None:
    """Path speed against time: measured from the trace, the planner's profile and
    the speed limits; the per-axis speeds below; hold intervals shaded."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (top, bottom) = plt.subplots(2, 1, figsize=(10, 7), sharex=True,
                                      gridspec_kw={"height_ratios": [3, 2]})
    tm, vm, va = measured_speeds(res)
    tp, vp, lim = planned_speeds(res)
    top.plot(tp, lim, "--", color="0.5", lw=0.9, label="speed limit (F, axes, arcs)")
    top.plot(tp, vp, "-", color="C1", lw=1.2, label="planned (planner, mm)")
    top.step(tm, vm, where="post", color="C0", lw=1.0, label="measured (core's moves)")
    clock = res.machine.clock_hz
    for a, b in res.holds:
        for ax in (top, bottom):
            ax.axvspan(a / clock, b / clock, color="C3", alpha=0.12, lw=0)
    top.set_ylabel("path speed (mm/s)")
    top.grid(True, lw=0.3)
    top.legend(loc="best", fontsize=8)
    top.set_title(title, fontsize=10)
    for k, name in enumerate("XYZABC"[:len(res.blu)]):
        bottom.step(tm, va[k], where="post", lw=0.9, label=name)
    bottom.set_ylabel("axis speed (mm/s)")
    bottom.set_xlabel("time (s)")
    bottom.grid(True, lw=0.3)
    bottom.legend(loc="best", fontsize=8)
    fig.tight_layout()
    fig.savefig(out, dpi=110)
    plt.close(fig)


def print_warnings(path: str, warnings) -> None:
    for w in warnings:
        print(f"halfpoint: {path}: warning: {w}", file=sys.stderr)


def print_messages(path: str, messages) -> None:
    """The program's (MSG, (DEBUG, and (PRINT, output, in program order, on stderr."""
    for m in messages:
        print(f"halfpoint: {m.source or path}: line {m.lineno}: {m.kind}: {m.text}",
              file=sys.stderr)


__all__ = ["load_program", "run_program", "plot_run", "plot_profile", "write_trace", "to_gcode",
           "print_warnings", "print_messages", "plan_items_compensated", "output_settings",
           "plan_motion", "RunResult", "EngineError"]
