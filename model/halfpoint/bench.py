# SPDX-License-Identifier: Apache-2.0
"""``make bench``: the performance figures the project can measure so far.

Every figure is computed here, in this run, from the cycle-accurate models
(which the cocotb tests hold equal to the RTL on every clock) or from the
numpy sweep of the arc model; a figure the project cannot measure yet is
written as null.  Prints a table and writes build/bench.json.
"""

from __future__ import annotations

import json
import math
import platform
import random
import sys
import time
from pathlib import Path

import numpy as np

from . import encoding as enc
from .arc import arc_points, full_circle_stats
from .core import CoreModel, run_program
from .program import random_arc, random_line
from .stepgen import StepCfg, StepGenModel, StepInputs

CLOCK_HZ = 100e6            # the clock the step rate is quoted at
SEED = 1


def run_core(cmds, rate_cfg=None, diag_weighting=True, axes=3):
    """Run commands through the core model with the queue kept full; returns
    (model, move times, positions after each move)."""
    m = CoreModel(axes, 32, 16, 16, rate_cfg or [StepCfg(1, 1, 0, 0)] * axes,
                  diag_weighting=diag_weighting)
    run = run_program(m, cmds)
    return m, run.times, run.trace


def moves_per_clock(min_moves: int):
    """Moves per clock in which the core was not held back by the feed rate or
    the STEP/DIR timing: moves / (moves + sequencing bubbles), counted from
    the first move on."""
    rng = random.Random(SEED)
    cmds = []
    while len(cmds) < 300:
        c = random_arc(rng, 2 * enc.RATE_ONE, cont=True) if rng.random() < 0.5 \
            else random_line(rng, 3, 2 * enc.RATE_ONE, cont=True, scale=60)
        d = enc.decode(c)
        if d["opcode"] == enc.OP_LINE:
            n = max(abs(v) for v in d["deltas"][:3])
        else:
            n = len(arc_points(-d["i"], -d["j"], d["x"] - d["i"], d["y"] - d["j"], d["cw"])) - 1
        if n >= min_moves:
            cmds.append(c)
    m, _, _ = run_core(cmds)
    return m.stat_moves / (m.stat_moves + m.stat_starved), m


def speed_ripple(weighted: bool, r: int = 1000, rate: float = 0.25, window: int = 64):
    """Path-speed variation along a full circle: max / min - 1 of the speed
    over sliding windows of `window` moves, in percent."""
    cmd = enc.encode_arc(0, -r, 0, 0, 0, int(rate * enc.RATE_ONE))
    _, times, trace = run_core([cmd], [StepCfg(1, 0, 0, 0)] * 3, diag_weighting=weighted)
    p = np.asarray([(0, 0)] + [t[:2] for t in trace], dtype=float)
    seg = np.hypot(*np.diff(p, axis=0).T)            # 1 or sqrt(2) per move
    t = np.asarray(times, dtype=float)
    speeds = [seg[k + 1:k + window + 1].sum() / (t[k + window] - t[k])
              for k in range(len(t) - window)]
    speeds = np.asarray(speeds)
    return 100 * (speeds.max() / speeds.min() - 1)


def max_step_rate(cfg: StepCfg, n: int = 200):
    """Steps per clock one axis sustains in one direction at these timings."""
    sg = StepGenModel()
    taken, cyc = 0, 0
    while taken < n:
        o = sg.outputs(cfg)
        req = int(o.ready_pos)
        taken += req
        sg.clock(cfg, StepInputs(req=req, req_dir=1))
        cyc += 1
    return n / cyc


def cam_program(blocks: int = 100_000, contours: int = 20, seed: int = SEED) -> str:
    """A CAM-style finishing program: closed contours of short G1 segments
    (about 0.05 mm) with CAM noise of +-0.5 um, each cut with G42 and a 2 mm
    cutter, entered and left through straight lead moves."""
    rng = random.Random(seed)
    per = blocks // contours
    out = ["G21 G90 G91.1 G17 F1200"]
    for c in range(contours):
        base = 30 + 0.5 * c
        pts = []
        for k in range(per):
            a = 2 * math.pi * k / per
            r = base + 1.5 * math.sin(6 * a) + rng.uniform(-0.0005, 0.0005)
            pts.append((r * math.cos(a), r * math.sin(a)))
        out.append(f"G0 X{base + 10:.4f} Y-5")
        out.append(f"G42.1 D2 G1 X{pts[0][0]:.4f} Y{pts[0][1]:.4f}")
        out += [f"X{x:.4f} Y{y:.4f}" for x, y in pts[1:] + pts[:1]]
        out.append(f"G40 G1 X{base + 10:.4f} Y5")
    out.append("M2")
    return "\n".join(out) + "\n"


def comp_speed(blocks: int = 100_000):
    """Blocks per second of cutter compensation plus quantisation (parsing
    excluded), one core."""
    from .comp import compensate
    from .gcode import parse
    from .quant import quantise

    prog = parse(cam_program(blocks))
    t0 = time.perf_counter()
    res = compensate(prog.moves)
    quantise(res.moves)
    dt = time.perf_counter() - t0
    return len(prog.moves) / dt, len(res.skipped)


def main() -> int:
    t0 = time.time()
    radii = np.arange(1, 2049)
    mv0, err0 = full_circle_stats(radii, 0)
    mv1, err1 = full_circle_stats(radii, 1)
    max_err = float(max(err0.max(), err1.max()))
    big = radii >= 64
    mpr = float(np.mean(np.concatenate([mv0[big] / radii[big], mv1[big] / radii[big]])))

    mpc_long, m_long = moves_per_clock(40)
    mpc_short, m_short = moves_per_clock(1)
    ripple = speed_ripple(True)
    ripple_naive = speed_ripple(False)
    step_cfg = StepCfg(1, 1, 0, 0)
    rate = max_step_rate(step_cfg)
    comp_bps, comp_skipped = comp_speed()

    figures = {
        "moves_per_clock": round(mpc_long, 4),
        "moves_per_clock_short_segments": round(mpc_short, 4),
        "max_radial_error_blu": round(max_err, 5),
        "moves_per_circle_over_r": round(mpr, 4),
        "baseline_pbp_max_error_blu": None,
        "baseline_dda_max_error_blu": None,
        "speed_ripple_pct": round(ripple, 3),
        "speed_ripple_pct_naive": round(ripple_naive, 2),
        "max_step_rate_hz_per_axis": rate * CLOCK_HZ,
        "sim_clocks_per_s_cocotb": None,
        "sim_clocks_per_s_compiled": None,
        "comp_blocks_per_s": round(comp_bps),
    }
    notes = {
        "moves_per_clock": "300 random arcs and lines of >= 40 moves each, queue kept full, "
                           "moves / (moves + clocks with work waiting and no segment running)",
        "moves_per_clock_short_segments": "the same with segments of any length (>= 1 move)",
        "max_radial_error_blu": "full circles R = 1..2048, both directions",
        "moves_per_circle_over_r": "mean over R = 64..2048 (4*sqrt(2) = 5.657)",
        "speed_ripple_pct": "full circle R = 1000 at 0.25 BLU/clock: max/min - 1 of the "
                            "path speed over windows of 64 moves",
        "speed_ripple_pct_naive": "same, every move costing the same time (no diagonal weighting)",
        "max_step_rate_hz_per_axis": f"steplen 1, stepspace 1 at {CLOCK_HZ / 1e6:.0f} MHz",
        "comp_blocks_per_s": "G42 compensation + quantisation of a 100,000-block CAM-style program "
                             f"(20 noisy contours of 0.05 mm segments; {comp_skipped} blocks skipped), "
                             "one core, parsing excluded",
    }
    out = {
        "figures": figures,
        "notes": notes,
        "source": "cycle-accurate models (held equal to the RTL clock by clock by the cocotb tests)",
        "python": platform.python_version(),
        "seed": SEED,
        "seconds": round(time.time() - t0, 1),
    }
    out.update(figures)
    path = Path("build/bench.json")
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(json.dumps(out, indent=2) + "\n")
    print(f"{'figure':34s} {'value':>14s}  how")
    for k, v in figures.items():
        shown = "null" if v is None else (f"{v:.6g}" if isinstance(v, float) else str(v))
        print(f"{k:34s} {shown:>14s}  {notes.get(k, 'not measured yet')}")
    print(f"wrote {path} ({out['seconds']} s)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
