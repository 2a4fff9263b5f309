# SPDX-License-Identifier: Apache-2.0
"""``make demo``: shipped arcs through the model and the Verilator-simulated RTL.

Prints one line per arc (moves, maximum radial error, stop point against the
programmed end) and writes ``arcs.png``: each lattice path over its true
circle, and the radial error along the path.  Then the G-code parts
(``run_gcode_demo``): a short part with a dwell and a feed hold through both engines
on the coarse simulation machine (``motion_profile.png``, ``motion_trace.csv``), and
``examples/plate.ngc`` on the shipped machine through the model (``plate.png``,
``plate_profile.png``).
"""

from __future__ import annotations

import math
import sys
from pathlib import Path

from ..spec.arc import lattice_point_near, radial_errors
from ..sim.engines import run_arcs
from ..sim.env import REPO


def demo_arcs() -> list[tuple[str, tuple[int, int, int, int, int]]]:
    """(label, (cw, xs, ys, xe, ye)) for the shipped examples."""
    arcs = [("full circle R=40, CCW", (0, 40, 0, 40, 0))]
    r2 = 17 * 17 + 23 * 23
    arcs.append(("CW, quadrant I to III", (1, 17, 23, *lattice_point_near(r2, math.radians(200)))))
    r2 = 31 * 31 + 12 * 12
    arcs.append(("CCW, IV to II, 2 crossings",
                 (0, 31, -12, *lattice_point_near(r2, math.radians(170)))))
    arcs.append(("full circle R=12.04, CW, off-axis", (1, -7, 10, -7, 10)))
    arcs.append(("CCW, near-full turn in one quadrant", (0, 20, 5, 20, 4)))
    return arcs


def run_demo(out_dir: str, engine: str = "both") -> int:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np

    arcs = demo_arcs()
    cmds = [c for _, c in arcs]
    engines = ["model", "rtl"] if engine == "both" else [engine]
    runs = {e: run_arcs(cmds, e) for e in engines}
    if len(engines) == 2:
        for a, b in zip(runs["model"], runs["rtl"]):
            if (a.points, a.rejected) != (b.points, b.rejected):
                print(f"halfpoint demo: model and RTL differ on {a.cmd}", file=sys.stderr)
                return 1
    res = runs[engines[-1]]
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)

    fig, axes = plt.subplots(2, len(arcs), figsize=(4 * len(arcs), 7.5),
                             gridspec_kw={"height_ratios": [3, 1]})
    print(f"{'arc':40s} {'moves':>6s} {'max|err|':>9s}  stop     end")
    for k, ((label, cmd), r) in enumerate(zip(arcs, res)):
        cw, xs, ys, xe, ye = cmd
        rad = math.hypot(xs, ys)
        pts = np.asarray(r.points)
        err = radial_errors(r.points, rad)
        print(f"{label:40s} {len(pts) - 1:6d} {np.abs(err).max():9.4f}  "
              f"{tuple(int(v) for v in pts[-1])!s:8s} {(xe, ye)}")
        ax = axes[0, k]
        t = np.linspace(0, 2 * np.pi, 721)
        ax.plot(rad * np.cos(t), rad * np.sin(t), color="0.6", lw=1, label="true circle")
        ax.plot(pts[:, 0], pts[:, 1], "-o", ms=2.5, lw=1, color="C0", label="lattice path")
        ax.plot([xs], [ys], "s", color="C2", label="start")
        ax.plot([xe], [ye], "x", color="C3", ms=9, label="programmed end")
        ax.set_aspect("equal")
        ax.set_title(label, fontsize=9)
        ax.grid(True, lw=0.3)
        if k == 0:
            ax.legend(fontsize=7, loc="upper left")
        ex = axes[1, k]
        ex.plot(err, lw=1)
        ex.axhline(0.5, color="C3", lw=0.8, ls="--")
        ex.axhline(-0.5, color="C3", lw=0.8, ls="--")
        ex.set_ylim(-0.6, 0.6)
        ex.set_xlabel("move")
        if k == 0:
            ex.set_ylabel("radial error (BLU)")
    fig.suptitle(f"halfpoint arc interpolator, engine: {' = '.join(engines)}")
    fig.tight_layout()
    png = out / "arcs.png"
    fig.savefig(png, dpi=110)
    print(f"engines: {', '.join(engines)}"
          + (" (identical lattice paths)" if len(engines) == 2 else ""))
    print(f"plot: {png}")
    return run_gcode_demo(out, engines)


# a short part for the engines' comparison: lines, arcs, a dwell, a rapid home, run on the
# coarse simulation machine with a feed hold in the middle
MOTION_PART = """(halfpoint demo: lines, arcs, a dwell, a feed hold; examples/machine_sim.toml)
G21 G90 G17 F600000
G1 X3
G2 X7 Y0 I2 J0
G4 P0.0002
G3 X7 Y4 I0 J2
G1 X0 Y4
G0 X0 Y0
M2
"""
MOTION_HOLDS = ((8000, 14000),)


def run_gcode_demo(out: Path, engines) -> int:
    """The G-code parts: a short part through the engines asked for (identical traces
    required) on the coarse simulation machine, then the shipped plate
    (``examples/plate.ngc``: cutter compensation with a notch the cutter cannot enter,
    arcs and lines) at its programmed feeds on the shipped machine, through the model
    (seconds of machine time: tens of millions of clocks, which the Verilator RTL driven
    clock by clock from Python cannot run in a demo)."""
    from ..cam import machine as mc
    from ..cam.run import plot_profile, plot_run, print_warnings, run_program, write_trace
    from ..sim.engines import executor

    root = REPO / "examples"
    sim = mc.load(root / "machine_sim.toml")
    part = out / "motion.ngc"
    part.write_text(MOTION_PART, encoding="utf-8")
    runs = {e: run_program(str(part), executor(e), machine=sim, holds=MOTION_HOLDS)
            for e in engines}
    res = runs[engines[-1]]
    if len(engines) == 2 and runs["model"].execution != runs["rtl"].execution:
        print("halfpoint demo: model and RTL differ on the motion part", file=sys.stderr)
        return 1
    write_trace(res, str(out / "motion_trace.csv"))
    png = out / "motion_profile.png"
    plot_profile(res, str(png), f"demo motion part, hold at cycles {MOTION_HOLDS[0][0]}.."
                 f"{MOTION_HOLDS[0][1]}, engine: {' = '.join(engines)}")
    print(f"\nmotion part ({part}, examples/machine_sim.toml): {len(res.lattice)} moves in "
          f"{res.execution.cycles} clocks ({res.seconds * 1e3:.3f} ms simulated), engines "
          f"{' = '.join(engines)}" + (" (identical traces)" if len(engines) == 2 else ""))
    print(f"profile: {png}")

    prog, tools = root / "plate.ngc", root / "tools.tbl"
    machine = mc.load(root / "machine.toml")
    res = run_program(str(prog), tools_path=str(tools), machine=machine)
    print_warnings("examples/plate.ngc", res.warnings)
    print(f"\nexamples/plate.ngc (G42, 6 mm cutter, examples/machine.toml, BLU "
          f"{res.blu[0]} mm): {len(res.lattice)} lattice moves, max deviation from the "
          f"compensated path {res.max_dev_mm * 1000:.2f} um, {res.seconds:.3f} s simulated "
          f"(planner estimate {res.summary.seconds:.3f} s; model)"
          + (", dry flag set" if res.execution.dry else "")
          + (", underrun flag set" if res.execution.underrun else ""))
    png = out / "plate.png"
    plot_run(res, str(png), "examples/plate.ngc, engine: model")
    print(f"plot: {png}")
    png = out / "plate_profile.png"
    plot_profile(res, str(png), "examples/plate.ngc on examples/machine.toml: path speed "
                 "(model)")
    print(f"profile: {png}")
    return 0
