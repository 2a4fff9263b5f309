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
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..spec import encoding as enc
from ..spec import profile as pf
from ..spec.arc import arc_points, full_circle_stats
from ..spec.core import CoreModel, run_program
from ..spec.program import move_count, profiled, random_arc, random_line
from ..spec.stepgen import StepCfg, StepGenModel, StepInputs

CLOCK_HZ = 100e6            # the clock the step rate is quoted at
SEED = 1


BENCH_DIV = 4              # the bench core's profile tick, 2^4 clocks
ONE = 1 << 32               # a speed field of 1 BLU per clock


@dataclass
class BenchCore(CoreModel):
    """The core model with the bench's counters, and the naive-pacing baseline
    (``diag_weighting=False``: a diagonal arc move costs as much as an axis move,
    which is not the RTL).

    Counted per clock at the move queue's input: clocks with room in it and a
    segment running or starting (``stat_room``: a unit loads its pending segment
    at that edge, as the arc unit does one clock after an arc's last move when an
    arc follows) and the moves made into it (``stat_moves``).
    """

    diag_weighting: bool = True
    stat_moves: int = 0
    stat_room: int = 0

    def _peek(self, unit: str):
        steps, cls = super()._peek(unit)
        if cls == pf.CLASS_DIAG and not self.diag_weighting:
            cls = pf.CLASS_AXIS
        return steps, cls

    def _clock_units(self, head):
        room = len(self.moves) < self.move_depth
        running = self._running() is not None
        loading, move = super()._clock_units(head)
        if room and (running or loading is not None):
            self.stat_room += 1
        self.stat_moves += move is not None
        return loading, move


def run_core(cmds, step_cfg=None, diag_weighting=True, axes=3, div=BENCH_DIV):
    """Run commands through the core model with the queue kept full; returns
    (model, move times, positions after each move)."""
    m = BenchCore(axes, 32, 16, 16, div, 4, 2, step_cfg or [StepCfg(1, 1, 0, 0)] * axes,
                  diag_weighting=diag_weighting)
    run = run_program(m, cmds)
    return m, run.times, run.trace


def planned(cmds, v_cruise, accel, junction=None, div=BENCH_DIV):
    return profiled(cmds, 3, 32, div, v_cruise=v_cruise, accel=accel, junction=junction)


def moves_per_clock(min_moves: int):
    """Moves per clock at the move queue's input while it has room: moves made
    into it / clocks with room and a segment running or starting (the
    interpolators must not wait for anything but the queue; the clock in which the
    arc unit loads an arc behind an arc, or a unit a segment behind the other's,
    counts against them), on 300 segments at
    0.45 BLU per clock."""
    rng = random.Random(SEED)
    cmds = []
    while len(cmds) < 300:
        c = random_arc(rng, cont=True) if rng.random() < 0.5 \
            else random_line(rng, 3, cont=True, scale=60)
        if move_count(c, 3, 32) >= min_moves:
            cmds.append(c)
    fast = int(0.45 * ONE)
    m, _, _ = run_core(planned(cmds, fast, 1 << 33, junction=fast), [StepCfg(1, 0, 0, 0)] * 3)
    return m.stat_moves / m.stat_room, m


def path_speeds(times, trace, window: int):
    """Path speed (BLU per clock) over sliding windows of ``window`` moves, from the
    pins: the Euclidean length of the moves over the clocks they took; and the
    window's mid time."""
    p = np.asarray([(0, 0, 0)] + [t[:3] for t in trace], dtype=float)
    seg = np.sqrt((np.diff(p, axis=0) ** 2).sum(axis=1))
    cum = np.concatenate([[0.0], np.cumsum(seg)])
    t = np.asarray(times, dtype=float)
    n = len(t) - window
    v = (cum[window + 1:n + window + 1] - cum[1:n + 1]) / (t[window:] - t[:n])
    mid = 0.5 * (t[window:] + t[:n])
    return v, mid


def speed_ripple(weighted: bool, r: int = 1000, speed: float = 0.25, window: int = 64):
    """Path-speed variation along a full circle at constant planned speed: max / min
    - 1 of the speed over sliding windows of ``window`` moves, in percent, over the
    middle half of the circle (the ramps at its start and end excluded)."""
    cmd = enc.encode_arc(0, -r, 0, 0, 0)
    v = int(speed * ONE)
    _, times, trace = run_core(planned([cmd], v, (1 << 34) - 1),
                               [StepCfg(1, 0, 0, 0)] * 3, diag_weighting=weighted)
    speeds, _ = path_speeds(times, trace, window)
    q = len(speeds) // 4
    mid = speeds[q:3 * q]
    return 100 * (mid.max() / mid.min() - 1)


def max_accel_over_limit(seed: int = SEED, window: int = 1024):
    """The largest path acceleration measured from the pins over a program of
    random arcs and lines with planned profiles (random speeds 0.05..0.45 BLU per
    clock, random junction speeds, one acceleration), divided by the planned limit:
    the distance the pins moved in consecutive windows of ``window`` clocks (each
    move's Euclidean length, counted at its clock) gives the mean speed of each
    window, the difference of two consecutive ones over ``window`` the acceleration
    (the window's quantisation, one move of <= sqrt(3) BLU, is < 2 % of the limit).
    Returns (ratio, details)."""
    rng = random.Random(seed)
    cmds = [random_arc(rng, rmin=20, rmax=80) if rng.random() < 0.5
            else random_line(rng, 3, scale=150) for _ in range(60)]
    accel = 1 << 29                 # speed step per tick: 2^-9 BLU per clock
    prog = profiled(cmds, 3, 32, BENCH_DIV,
                    v_cruise=lambda k: int(rng.uniform(0.05, 0.45) * ONE), accel=accel, rng=rng)
    m, times, trace = run_core(prog, [StepCfg(1, 0, 0, 0)] * 3)
    p = np.asarray([(0, 0, 0)] + [t[:3] for t in trace], dtype=float)
    seg = np.sqrt((np.diff(p, axis=0) ** 2).sum(axis=1))
    cum = np.concatenate([[0.0], np.cumsum(seg)])
    t = np.asarray(times)
    edges = np.arange(t[0], t[-1] + window, window)
    dist = cum[np.searchsorted(t, edges, side="right")]     # distance moved before each edge
    v = np.diff(dist) / window
    a = np.abs(np.diff(v)) / window
    limit = accel / float(1 << pf.SPEED_FRAC) / float(1 << BENCH_DIV)   # BLU per clock^2
    quantum = 2 * math.sqrt(3) / window / window
    return float(a.max() / limit), {"moves": len(trace), "clocks": int(t[-1]),
                                    "limit_blu_per_clock2": limit, "window_clocks": window,
                                    "quantisation_over_limit": quantum / limit,
                                    "dry": m.outputs().dry}


def demo_time():
    """The demo part (examples/plate.ngc) on the shipped machine file, through the whole
    host pipeline and the model engine: (simulated seconds, that over the feed bound,
    details).  The feed bound is the sum over the compensated moves of length / feed
    (F for feed moves, the fastest the axes allow along the move for rapids): the time
    with infinite acceleration."""
    from ..cam.machine import load_default
    from ..cam.run import run_program
    repo = Path(__file__).resolve().parents[3]
    machine = load_default()
    t0 = time.time()
    res = run_program(str(repo / "examples" / "plate.ngc"), machine=machine)
    wall = time.time() - t0
    bound = 0.0
    for m in res.compensated:
        d = [e - s for s, e in zip(m.start, m.end)]
        if m.kind == "arc":
            a0 = math.atan2(m.start[1] - m.center[1], m.start[0] - m.center[0])
            a1 = math.atan2(m.end[1] - m.center[1], m.end[0] - m.center[0])
            sweep = (a0 - a1) if m.cw else (a1 - a0)
            sweep = sweep % (2 * math.pi) or 2 * math.pi
            r = math.hypot(m.start[0] - m.center[0], m.start[1] - m.center[1])
            length = math.hypot(r * sweep, d[2])
        else:
            length = math.sqrt(sum(x * x for x in d))
        if not length:
            continue
        if m.kind == "rapid":
            speed = min(a.max_velocity_mm_s / (abs(x) / length)
                        for a, x in zip(machine.axes, d) if x)
        else:
            speed = m.feed / 60.0
        bound += length / speed
    return res.seconds, res.seconds / bound, {"moves": len(res.lattice),
                                              "feed_bound_s": bound, "wall_s": round(wall, 1),
                                              "dry": res.execution.dry}


def max_step_rate(cfg: StepCfg, n: int = 200):
    """Steps per clock one axis sustains in one direction at these timings:
    (n - 1) step periods over the clocks from the first step to the last."""
    sg = StepGenModel()
    taken, cyc, first, last = 0, 0, None, None
    while taken < n:
        o = sg.outputs(cfg)
        req = int(o.ready_pos)
        if req:
            first = cyc if first is None else first
            last = cyc
        taken += req
        sg.clock(cfg, StepInputs(req=req, req_dir=1))
        cyc += 1
    return (n - 1) / (last - first)


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
    from ..cam.comp import compensate
    from ..cam.gcode import parse
    from ..cam.quant import quantise

    prog = parse(cam_program(blocks))
    t0 = time.perf_counter()
    res = compensate(prog.moves)
    quantise(res.moves)
    dt = time.perf_counter() - t0
    return len(prog.moves) / dt, len(res.skipped)


def chord_table():
    """Seed 002's grid: a = 0.01, 0.1, 1; b = 0; f = 0.02 .. 0.08 over x in
    [0, 10]: mean and worst chord length for both algorithms; mean |chord - f|
    for n = 1..10 substeps at a = 1, f = 0.08; time per step."""
    from ..curves.chords import chord_stats, parabola_chords

    rows = []
    for a in (0.01, 0.1, 1.0):
        for f in (0.02, 0.04, 0.06, 0.08):
            r = {"a": a, "f": f}
            for alg in (1, 2):
                mean, worst, _, _ = chord_stats(parabola_chords(a, 0.0, 0.0, 10.0, f, alg), f)
                r[f"alg{alg}_mean"], r[f"alg{alg}_worst"] = mean, worst
            rows.append(r)
    subs = []
    for n in range(1, 11):
        r = {"n": n}
        for alg in (1, 2):
            t0 = time.perf_counter()
            pts = parabola_chords(1.0, 0.0, 0.0, 10.0, 0.08, alg, n)
            dt = time.perf_counter() - t0
            r[f"alg{alg}_mean_err"] = chord_stats(pts, 0.08)[2]
            r[f"alg{alg}_us_per_period"] = dt / (len(pts) - 1) * 1e6
        subs.append(r)
    return rows, subs


def curve_comparison(tol: float = 0.01, f_td: float = 0.04, plot: str | None = "build/bench_curves.png"):
    """Ellipse 50 x 30, second quadrant: tri-arcs at ``tol`` vs. a polyline
    whose chords stay within ``tol`` vs. time-division chords of path length
    ``f_td`` (600 mm/min at a 4 ms period): segments and maximum deviation."""
    from ..curves import triarc

    a, b = 50.0, 30.0
    curve = triarc.ellipse(a, b, math.pi / 2, math.pi)
    t0 = time.perf_counter()
    arcs, groups = triarc.fit(curve, tol)
    t_fit = time.perf_counter() - t0
    dev_arcs, _ = triarc.verify(curve, arcs, tol)

    dense_t = np.linspace(curve.t0, curve.t1, 200001)
    dense = np.stack([a * np.cos(dense_t), b * np.sin(dense_t)], axis=1)
    seg_len = np.hypot(*np.diff(dense, axis=0).T)
    s_cum = np.concatenate([[0.0], np.cumsum(seg_len)])

    def poly_dev(idx):
        worst = 0.0
        for i, j in zip(idx, idx[1:]):
            p, q = dense[i], dense[j]
            d = q - p
            n = np.hypot(*d)
            pts = dense[i:j + 1]
            dist = np.abs(d[0] * (pts[:, 1] - p[1]) - d[1] * (pts[:, 0] - p[0])) / n
            worst = max(worst, float(dist.max()))
        return worst

    # polyline: greedy longest chords within tol
    idx, i = [0], 0
    n = len(dense) - 1
    while i < n:
        lo, hi = i + 1, n
        while lo < hi:
            mid = (lo + hi + 1) // 2
            if poly_dev([i, mid]) <= tol:
                lo = mid
            else:
                hi = mid - 1
        idx.append(lo)
        i = lo
    dev_poly = poly_dev(idx)
    # time-division: equal path length per period
    marks = np.arange(0.0, s_cum[-1], f_td)
    td_idx = sorted(set(np.searchsorted(s_cum, marks).tolist() + [n]))
    dev_td = poly_dev(td_idx)
    res = {
        "tolerance_mm": tol, "timediv_chord_mm": f_td,
        "triarc": {"segments": len(arcs), "groups": len(groups), "max_dev_mm": dev_arcs, "fit_s": t_fit},
        "polyline": {"segments": len(idx) - 1, "max_dev_mm": dev_poly},
        "timediv": {"segments": len(td_idx) - 1, "max_dev_mm": dev_td},
    }
    if plot:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        fig, axes = plt.subplots(1, 2, figsize=(11, 4.8))
        ax = axes[0]
        ax.plot(dense[:, 0], dense[:, 1], color="0.6", lw=3, label="ellipse 50 x 30, Q2")
        for k, arc in enumerate(arcs):
            p = arc.points(64)
            ax.plot(p[:, 0], p[:, 1], lw=1.4, color=f"C{k % 10}")
            ax.plot(*arc.start, "k.", ms=4)
        ax.set_aspect("equal")
        ax.set_title(f"tri-arc fit: {len(groups)} groups, {len(arcs)} arcs")
        ax.legend(fontsize=8)
        ax = axes[1]
        names = ["tri-arcs", f"polyline (<= {tol} mm)", f"time-division (f = {f_td} mm)"]
        segs = [len(arcs), len(idx) - 1, len(td_idx) - 1]
        devs = [dev_arcs * 1000, dev_poly * 1000, dev_td * 1000]
        bars = ax.bar(names, segs, color=["C0", "C1", "C2"])
        for bar, d in zip(bars, devs):
            ax.annotate(f"max dev {d:.2f} um", (bar.get_x() + bar.get_width() / 2, bar.get_height()),
                        ha="center", va="bottom", fontsize=8)
        ax.set_yscale("log")
        ax.set_ylabel("segments")
        ax.set_title("segments for the same quadrant")
        fig.tight_layout()
        Path(plot).parent.mkdir(parents=True, exist_ok=True)
        fig.savefig(plot, dpi=110)
        plt.close(fig)
    return res


BASELINE_RADII = list(range(1, 65)) + [100, 128, 200, 256, 500, 512, 1000, 1024, 2000, 2048]


def baseline_comparison():
    """Half-point vs point-by-point comparison vs DDA on full circles (CCW from
    (R, 0)): max radial error and moves per circle over R."""
    from .baselines import compare
    rows = compare(BASELINE_RADII, lambda r: np.array(arc_points(r, 0, r, 0, 0)))
    out = {}
    for key in ("half_point", "pbp", "dda", "dda_half"):
        big = [row for row in rows if row["r"] >= 64]
        out[key] = {
            "max_error_blu": round(max(row[key]["err"] for row in rows), 5),
            "moves_per_circle_over_r": round(float(np.mean([row[key]["moves"] / row["r"] for row in big])), 4),
            "all_close": all(row[key]["closes"] for row in rows),
        }
    return out, rows


def line_error(n: int = 2000, seed: int = SEED):
    """Max Euclidean distance of the line unit's lattice points from the ideal
    segment, over random 3-axis lines of up to 1000 BLU per axis."""
    from ..spec.line import line_steps
    rng = random.Random(seed)
    worst = 0.0
    for _ in range(n):
        d = np.array([rng.randint(-1000, 1000) for _ in range(3)], dtype=float)
        if not d.any():
            continue
        steps = np.array(line_steps([int(v) for v in d]), dtype=float)
        pts = np.cumsum(steps, axis=0)
        u = d / np.linalg.norm(d)
        perp = pts - np.outer(pts @ u, u)
        worst = max(worst, float(np.max(np.linalg.norm(perp, axis=1))))
    return worst


def synthesis_summary():
    """The rows of build/synth/report.json (make synth), if it exists."""
    path = Path("build/synth/report.json")
    if not path.exists():
        return None
    keep = ("module", "device", "lut4", "carry", "ff", "fmax_mhz", "fmax_of_ref")
    return [{k: r.get(k) for k in keep} for r in json.loads(path.read_text())]


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
    accel_ratio, accel_detail = max_accel_over_limit()
    try:
        demo_s, demo_ratio, demo_detail = demo_time()
    except ImportError as exc:      # the fast model is not there: the figures stay null
        print(f"demo time not measured: {exc}")
        demo_s = demo_ratio = demo_detail = None
    try:
        from ..spec.fastcore import measure_clocks_per_s
        model_cps = measure_clocks_per_s()
    except ImportError:             # the fast model is not there yet: the figure stays null
        model_cps = None
    step_cfg = StepCfg(1, 1, 0, 0)
    rate = max_step_rate(step_cfg)
    comp_bps, comp_skipped = comp_speed()
    chord_rows, chord_subs = chord_table()
    curves = curve_comparison()
    base, base_rows = baseline_comparison()
    line_err = line_error()
    from .simspeed import cocotb_speed, compiled_speed
    try:
        sim_cocotb = cocotb_speed()
    except Exception as exc:          # a figure we could not measure stays null
        print(f"cocotb simulation speed not measured: {exc}")
        sim_cocotb = None
    try:
        sim_compiled = compiled_speed()
    except Exception as exc:
        print(f"compiled simulation speed not measured: {exc}")
        sim_compiled = None
    synth = synthesis_summary()

    figures = {
        "moves_per_clock": round(mpc_long, 4),
        "moves_per_clock_short_segments": round(mpc_short, 4),
        "max_radial_error_blu": round(max_err, 5),
        "moves_per_circle_over_r": round(mpr, 4),
        "max_line_error_blu": round(line_err, 5),
        "baseline_pbp_max_error_blu": base["pbp"]["max_error_blu"],
        "baseline_pbp_moves_per_circle_over_r": base["pbp"]["moves_per_circle_over_r"],
        "baseline_dda_max_error_blu": base["dda"]["max_error_blu"],
        "baseline_dda_moves_per_circle_over_r": base["dda"]["moves_per_circle_over_r"],
        "baseline_dda_half_preset_max_error_blu": base["dda_half"]["max_error_blu"],
        "speed_ripple_pct": round(ripple, 3),
        "speed_ripple_pct_naive": round(ripple_naive, 2),
        "max_accel_over_limit": round(accel_ratio, 4),
        "model_clocks_per_s": model_cps and round(model_cps),
        "demo_time_s": demo_s and round(demo_s, 4),
        "demo_time_over_feed_bound": demo_ratio and round(demo_ratio, 4),
        "max_step_rate_hz_per_axis": rate * CLOCK_HZ,
        "sim_clocks_per_s_cocotb": sim_cocotb and sim_cocotb["clocks_per_s"],
        "sim_clocks_per_s_compiled": sim_compiled and sim_compiled["clocks_per_s"],
        "sim_clocks_per_cpu_s_compiled": sim_compiled and sim_compiled["clocks_per_cpu_s"],
        "comp_blocks_per_s": round(comp_bps),
    }
    notes = {
        "moves_per_clock": "300 random arcs and lines of >= 40 moves each at 0.45 BLU/clock, "
                           "queue kept full: moves made into the move queue / clocks it had "
                           "room with a segment running or starting (a unit loading)",
        "moves_per_clock_short_segments": "the same with segments of any length (>= 1 move)",
        "max_radial_error_blu": "full circles R = 1..2048, both directions",
        "moves_per_circle_over_r": "mean over R = 64..2048 (4*sqrt(2) = 5.657)",
        "speed_ripple_pct": "full circle R = 1000 planned at 0.25 BLU/clock: max/min - 1 of "
                            "the path speed over windows of 64 moves, middle half of the circle",
        "max_accel_over_limit": "60 random arcs and lines with planned profiles (DIV 4): largest "
                                "path acceleration from the pins (mean speeds over 1024-clock "
                                "windows) over the planned limit",
        "model_clocks_per_s": "spec.fastcore.measure_clocks_per_s (null: not available)",
        "demo_time_s": "examples/plate.ngc on examples/machine.toml (50 MHz, 1 um), whole host "
                       "pipeline, model engine: simulated seconds",
        "demo_time_over_feed_bound": "that over the sum of length / F (rapids: the axes' "
                                     "fastest along the move)",
        "speed_ripple_pct_naive": "same, every move costing the same time (no diagonal weighting)",
        "max_step_rate_hz_per_axis": f"steplen 1, stepspace 1 at {CLOCK_HZ / 1e6:.0f} MHz",
        "max_line_error_blu": "2000 random 3-axis lines up to 1000 BLU per axis: largest distance "
                              "of a visited lattice point from the ideal segment",
        "baseline_pbp_max_error_blu": "point-by-point comparison (model/halfpoint/flows/baselines.py), "
                                      f"full circles R = 1..64 and 10 radii up to 2048",
        "baseline_pbp_moves_per_circle_over_r": "mean over those radii >= 64 (axis moves only: 8)",
        "baseline_dda_max_error_blu": "DDA circle, remainders preset 0, quadrant by quadrant, same radii",
        "baseline_dda_moves_per_circle_over_r": "mean over those radii >= 64 (a diagonal counts once)",
        "baseline_dda_half_preset_max_error_blu": "DDA with remainders preset to half scale",
        "sim_clocks_per_s_cocotb": "core NA=3 W=32, cocotb mixed_program test, model compared every clock"
                                   + (f" ({sim_cocotb['clocks']} clocks in {sim_cocotb['seconds']} s)"
                                      if sim_cocotb else ""),
        "sim_clocks_per_s_compiled": "core NA=3 W=32, compiled Verilator harness "
                                     "(tb/halfpoint_core/speed_harness.cpp), every move's clock "
                                     "and positions checked against the model's precomputed "
                                     "moves; wall time of the simulation loop"
                                     + (f" ({sim_compiled['clocks']} clocks in "
                                        f"{sim_compiled['seconds']} s; build "
                                        f"{sim_compiled['options']})" if sim_compiled else ""),
        "sim_clocks_per_cpu_s_compiled": "the same over the loop's CPU time (a shared machine's "
                                         "load does not count)"
                                         + (f" ({sim_compiled['cpu_seconds']} s)"
                                            if sim_compiled else ""),
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
    out["parabola_chords"] = {"grid": chord_rows, "substeps": chord_subs}
    out["circle_baselines"] = {"summary": base, "per_radius": base_rows}
    out["simulation"] = {"cocotb": sim_cocotb, "compiled": sim_compiled}
    out["motion"] = {"max_accel": accel_detail, "demo": demo_detail}
    out["synthesis"] = synth
    out["ellipse_curves"] = curves
    out.update(figures)
    path = Path("build/bench.json")
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(json.dumps(out, indent=2) + "\n")
    print(f"{'figure':34s} {'value':>14s}  how")
    for k, v in figures.items():
        shown = "null" if v is None else (f"{v:.6g}" if isinstance(v, float) else str(v))
        print(f"{k:34s} {shown:>14s}  {notes.get(k, 'not measured yet')}")
    print("\nparabola chords (seed 002), b = 0, x in [0, 10]: mean / worst chord length")
    print(f"{'a':>5s} {'f':>5s}  {'alg 1 mean':>10s} {'worst':>9s}  {'alg 2 mean':>10s} {'worst':>9s}")
    for r in chord_rows:
        print(f"{r['a']:5g} {r['f']:5g}  {r['alg1_mean']:10.6f} {r['alg1_worst']:9.6f}  "
              f"{r['alg2_mean']:10.6f} {r['alg2_worst']:9.6f}")
    print("n substeps (a = 1, f = 0.08): mean |chord - f| and time per period")
    for r in chord_subs:
        print(f"  n={r['n']:2d}  alg 1 {r['alg1_mean_err']:.2e} ({r['alg1_us_per_period']:.1f} us)"
              f"  alg 2 {r['alg2_mean_err']:.2e} ({r['alg2_us_per_period']:.1f} us)")
    print("\nfull circles, R = 1..64 and 10 radii up to 2048:")
    print(f"  {'method':28s} {'max error BLU':>13s} {'moves/circle/R':>15s} {'all close':>9s}")
    for key, label in (("half_point", "half-point (this core)"), ("pbp", "point-by-point comparison"),
                       ("dda", "DDA, remainder preset 0"), ("dda_half", "DDA, remainder preset 1/2")):
        b = base[key]
        print(f"  {label:28s} {b['max_error_blu']:13.4f} {b['moves_per_circle_over_r']:15.4f} {str(b['all_close']):>9s}")
    if synth:
        print("\nsynthesis (build/synth/report.json, make synth):")
        for r in synth:
            fm = "n/a" if r["fmax_mhz"] is None else f"{r['fmax_mhz']:.1f} MHz"
            print(f"  {r['module']:15s} {r['device']:22s} LUT4 {r['lut4']:5d}  FF {r['ff']:5d}  Fmax {fm}")
    else:
        print("\nsynthesis: no build/synth/report.json (run make synth)")
    c = curves
    print(f"\nellipse 50 x 30, second quadrant, tolerance {c['tolerance_mm']} mm (plot build/bench_curves.png):")
    for key, label in (("triarc", "tri-arcs"), ("polyline", "polyline"), ("timediv", "time-division chords")):
        print(f"  {label:22s} {c[key]['segments']:6d} segments, max deviation {c[key]['max_dev_mm'] * 1000:.2f} um")
    print(f"wrote {path} ({out['seconds']} s)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
