# SPDX-License-Identifier: Apache-2.0
"""``make soak``: random segments through the compiled Verilator harness, checked move
by move against the model (issue 17, item 3).

The segments (``random_segment``): arcs of every (start quadrant, end quadrant,
direction) and radius class (small 1..8 BLU, medium 8..40, large 40..250, a share of
them full circles; huge 10^3..10^8, short sweeps from near a quadrant boundary, so
the wide arithmetic and the quadrant changes run without 10^8 moves); lines moving
1..NA axes, short and long.  They are cut into batches (``make_batch``,
``--per-batch`` segments each); a batch is one job: profiles planned by
``spec.program.profiled`` over it (random cruise speeds, accelerations and junction
speeds, the batch starting and ending at rest), random STEP/DIR settings and
polarities, a random constant feed override, random feed-hold intervals, idle clocks
before it (the core at rest with tvalid low for a random number of clocks, then
reset) and random gaps in the stream while it runs (``random_stream_gaps``: tvalid
low for 1..20,000 clocks, short ones the queue hides, long ones that starve the core;
a beat offered and not yet taken stays offered, as AXI4-Stream requires).  Within a
batch the commands stream with back-pressure from tready, exactly as
``spec.fastcore.run_fast`` streams them with the same holds and gaps.

The model runs in ``--jobs`` worker processes; the main process writes every
``--chunk`` batches to a vector file and the harness (``flows.simspeed``) checks
them while the workers compute the next.  Every batch is reproducible from the seed
and its index (``batch_rng``); a failure prints the seed, the batch, the first
mismatch, the vector file and the command that runs that batch alone.  Prints the
segments, moves and clocks checked, the harness's clock rate and the wall time, and
how many segments of each class ran.
"""

from __future__ import annotations

import argparse
import math
import multiprocessing
import os
import random
import shlex
import subprocess
import sys
import time
from collections import Counter
from dataclasses import dataclass, field
from pathlib import Path

from ..sim.env import BUILD
from ..spec import encoding as enc
from ..spec import profile as pf
from ..spec.arc import lattice_point_near, quadrant, validate
from ..spec.program import profiled
from ..spec.stepgen import StepCfg
from .simspeed import (DEFAULT_BUILD, HARNESS_BUILDS, HARNESS_DIV, HARNESS_W, Batch, Expected,
                       batch_words, harness_binary, model_run, parse_harness, vector_end,
                       vector_header)

RADIUS_CLASSES = {"small": (1.0, 8.0), "medium": (8.0, 40.0), "large": (40.0, 250.0),
                  "huge": (1e3, 1e8)}
RADIUS_WEIGHTS = {"small": 0.42, "medium": 0.45, "large": 0.05, "huge": 0.08}
HUGE_SWEEP = (6, 60)        # a huge arc's length in BLU (a short sweep, often across an axis)
FULL_CIRCLE = 0.1           # share of small .. large arcs that are full circles
SPEEDS = (0.02, 0.6)        # cruise speeds, BLU per clock (uniform)
ACCELS = (1 << 30, 1 << 31, 1 << 32, 1 << 33)   # accelerations (field units), equally likely
LINE_SHARE = 0.5            # share of segments that are lines
LINE_SCALES = ((0.65, 12), (0.3, 60), (0.05, 400))    # (share, largest |delta|)


def batch_rng(seed: int, index: int, part: str = "") -> random.Random:
    """The random source of batch ``index`` of a soak with ``seed`` (of a part of it,
    drawn apart from the rest)."""
    return random.Random(f"halfpoint-soak:{seed}:{index}" + (f":{part}" if part else ""))


def _pick(rng: random.Random, weights: dict):
    return rng.choices(list(weights), weights=list(weights.values()))[0]


def random_arc_segment(rng: random.Random, cont: bool) -> tuple[int, tuple]:
    """An arc the validator accepts: radius class, direction, start and end quadrant
    drawn first (a huge arc: a short sweep from near a quadrant boundary, so it often
    crosses it); returns (command, class)."""
    rclass = _pick(rng, RADIUS_WEIGHTS)
    lo, hi = RADIUS_CLASSES[rclass]
    cw = rng.randint(0, 1)
    huge = rclass == "huge"
    full = not huge and rng.random() < FULL_CIRCLE
    q_start, q_end = rng.randrange(4), rng.randrange(4)
    while True:
        if huge:
            r = math.exp(rng.uniform(math.log(lo), math.log(hi)))
            sweep = rng.uniform(*HUGE_SWEEP) / r
            ts = q_start * math.pi / 2 + rng.uniform(-1.0, 1.0) * sweep
            te = ts - sweep if cw else ts + sweep
        else:
            r = rng.uniform(lo, hi)
            ts = (q_start + rng.random()) * math.pi / 2
            te = (q_end + rng.random()) * math.pi / 2
        xs, ys = round(r * math.cos(ts)), round(r * math.sin(ts))
        if xs == 0 and ys == 0:
            continue
        xe, ye = (xs, ys) if full else lattice_point_near(xs * xs + ys * ys, te)
        if huge:        # the short way round, in the arc's direction
            cross = xs * ye - ys * xe
            if (cross >= 0 if cw else cross <= 0) or xs * xe + ys * ye <= 0:
                continue
        if validate(xs, ys, xe, ye, HARNESS_W) == 0:
            break
    # the quadrants as the arc unit counts them (a point on an axis: the one entered)
    label = ("arc", "full" if full else
             f"q{quadrant(xs, ys, cw) + 1}-q{quadrant(xe, ye, cw) + 1}",
             "cw" if cw else "ccw", rclass)
    return enc.encode_arc(cw, -xs, -ys, xe - xs, ye - ys, cont), label


def random_line_segment(rng: random.Random, axes: int, cont: bool) -> tuple[int, tuple]:
    """A line moving 1..axes axes (the others 0); returns (command, class)."""
    n = rng.randint(1, axes)
    moving = rng.sample(range(axes), n)
    scale = rng.choices([s for _, s in LINE_SCALES], weights=[w for w, _ in LINE_SCALES])[0]
    deltas = [0] * axes
    for a in moving:
        while deltas[a] == 0:
            deltas[a] = rng.randint(-scale, scale)
    return enc.encode_line(deltas, cont), ("line", f"{n} axes")


def random_segment(rng: random.Random, axes: int, cont: bool = True):
    if rng.random() < LINE_SHARE:
        return random_line_segment(rng, axes, cont)
    return random_arc_segment(rng, cont)


def random_holds(rng: random.Random, horizon: int) -> list:
    """0..3 feed-hold intervals (50..3000 clocks) starting within ``horizon`` clocks,
    sorted, disjoint and apart."""
    holds = []
    for _ in range(rng.choice((0, 0, 1, 1, 2, 3))):
        a = rng.randrange(max(horizon, 1))
        holds.append((a, a + rng.randint(50, 3000)))
    return _apart(holds)


def _apart(intervals) -> list:
    """The intervals sorted, without each one that starts at or before the end of the
    one kept before it (so that they are disjoint and apart, as the harness needs)."""
    out = []
    for a, b in sorted(intervals):
        if out and a <= out[-1][1]:
            continue
        out.append((a, b))
    return out


def random_stream_gaps(rng: random.Random, horizon: int) -> list:
    """0..4 gaps in the command stream (tvalid low, 1..20,000 clocks) starting within
    ``horizon`` clocks, while the core moves: short ones the command queue hides, long
    ones that let it run dry (a gap after the last command changes nothing); sorted,
    disjoint and apart."""
    gaps = []
    for _ in range(rng.choice((0, 1, 1, 2, 3, 4))):
        a = rng.randrange(max(horizon, 1))
        gaps.append((a, a + rng.choice((1, 2, rng.randint(3, 40), rng.randint(41, 2000),
                                        rng.randint(2001, 20000)))))
    return _apart(gaps)


def make_batch(seed: int, index: int, axes: int, segments: int) -> tuple[Batch, Counter]:
    """Batch ``index`` of a soak: ``segments`` random segments with planned profiles,
    its STEP/DIR settings, override, holds, idle clocks and stream gaps; and its segment
    classes."""
    rng = batch_rng(seed, index)
    cmds, classes = [], Counter()
    for _ in range(segments):
        cmd, label = random_segment(rng, axes)
        cmds.append(cmd)
        classes[label] += 1
    speeds = [rng.uniform(*SPEEDS) for _ in cmds]
    accels = [rng.choice(ACCELS) for _ in cmds]
    prog = profiled(cmds, axes, HARNESS_W, HARNESS_DIV,
                    v_cruise=lambda k: int(speeds[k] * 2**pf.FIELD_SPEED_FRAC),
                    accel=lambda k: accels[k], rng=rng)
    cfg = [StepCfg(rng.randint(1, 3), rng.randint(1, 3), rng.randint(1, 4), rng.randint(1, 4),
                   rng.randint(0, 1), rng.randint(0, 1)) for _ in range(axes)]
    override = rng.choice((pf.OVERRIDE_ONE, pf.OVERRIDE_ONE, pf.OVERRIDE_ONE, 96, 64, 33))
    holds = random_holds(rng, 40 * segments * 20)
    gap = rng.choice((0, 1, 2, 5, 17, 100))
    # the stream gaps from a source of their own, so that the rest of a batch is
    # what the same seed gave before they were added
    # (starting in about the first third of a batch, while commands remain)
    stream_gaps = random_stream_gaps(batch_rng(seed, index, "stream gaps"),
                                     10 * segments * 20)
    return Batch(prog, axes, cfg, holds, override, gap, stream_gaps), classes


@dataclass
class Computed:
    index: int
    words: bytes                    # the batch in the vector file's format
    segments: int
    moves: int
    clocks: int
    classes: Counter = field(default_factory=Counter)
    seconds: float = 0.0            # the worker's CPU time on it (planning and model)


def compute(args) -> Computed:
    """A worker's job: build batch ``index`` and run the model on it."""
    seed, index, axes, segments, corrupt = args
    t0 = time.process_time()
    batch, classes = make_batch(seed, index, axes, segments)
    exp = model_run(batch)
    if corrupt is not None and exp.times:
        exp = corrupted(exp, corrupt)
    return Computed(index, batch_words(index, batch, exp).tobytes(), segments, len(exp.times),
                    exp.clocks, classes, time.process_time() - t0)


def corrupted(exp: Expected, move: int) -> Expected:
    """``exp`` with expected move ``move`` (modulo the count) one BLU off on axis 0:
    a deliberately wrong expectation the checker must reject."""
    k = move % len(exp.times)
    trace = list(exp.trace)
    trace[k] = (trace[k][0] + 1,) + tuple(trace[k][1:])
    return Expected(exp.times, trace, exp.errors, exp.clocks, exp.dry, exp.underrun)


@dataclass
class SoakResult:
    ok: bool
    segments: int = 0
    batches: int = 0
    moves: int = 0
    clocks: int = 0
    harness_seconds: float = 0.0
    wall_seconds: float = 0.0
    model_seconds: float = 0.0      # the workers' CPU time, summed (planning and model)
    harness_cpu_seconds: float = 0.0
    classes: Counter = field(default_factory=Counter)
    failure: str = ""
    failed_batch: int | None = None
    vectors: Path | None = None
    repro: str = ""
    first_batch: int = 0            # the batches run: first .. end - 1 of total
    end_batch: int = 0
    total_batches: int = 0


def repro_command(segments: int, seed: int, axes: int, per_batch: int, batch: int) -> str:
    return (f"{shlex.quote(sys.executable)} -m halfpoint.flows.soak --segments {segments} "
            f"--seed {seed} --axes {axes} --per-batch {per_batch} --only-batch {batch} --jobs 1")


def _check_chunk(path: Path, chunk: list, proc: subprocess.Popen, res: SoakResult,
                 segments: int, seed: int, axes: int, per_batch: int) -> bool:
    """Wait for the harness on one vector file; False (and ``res`` says why) on a
    mismatch, the file kept."""
    out, err = proc.communicate()
    verdict = parse_harness(subprocess.CompletedProcess(proc.args, proc.returncode, out, err))
    if not verdict.ok:
        res.ok = False
        res.failure = verdict.failure
        words = verdict.failure.split()
        res.failed_batch = int(words[2].rstrip(":")) if len(words) > 2 and \
            words[1] == "batch" else chunk[0].index
        res.vectors = path
        res.repro = repro_command(segments, seed, axes, per_batch, res.failed_batch)
        return False
    res.batches += verdict.batches
    res.moves += verdict.moves
    res.clocks += verdict.clocks
    res.harness_seconds += verdict.seconds
    res.harness_cpu_seconds += verdict.cpu_seconds
    for c in chunk:
        res.segments += c.segments
        res.classes.update(c.classes)
    path.unlink()
    return True


def soak(segments: int = 1_000_000, seed: int = 1, axes: int = 3, per_batch: int = 100,
         jobs: int = 2, chunk: int = 50, only_batch: int | None = None,
         corrupt: tuple[int, int] | None = None, out=None,
         build: str = DEFAULT_BUILD, batches: tuple[int, int] | None = None) -> SoakResult:
    """Run the soak; ``corrupt`` = (batch, move) alters that expected move (a check
    that the checker fails).  ``batches`` = (first, end) runs only the batches
    first .. end - 1 of the run's ceil(segments / per_batch): a long soak in parts,
    each part exactly those batches of the whole run (each batch depends only on the
    seed and its index), so parts that cover 0 .. N - 1 check what the whole run
    checks."""
    t0 = time.monotonic()
    binary, _ = harness_binary(axes, build)
    work = BUILD / "soak" / f"na{axes}_seed{seed}"
    work.mkdir(parents=True, exist_ok=True)
    nbatch = -(-segments // per_batch)
    if only_batch is not None:
        if not 0 <= only_batch < nbatch:
            raise ValueError(f"batch {only_batch} is not one of the {nbatch} batches")
        batches = (only_batch, only_batch + 1)
    first, end = batches if batches is not None else (0, nbatch)
    if not 0 <= first < end <= nbatch:
        raise ValueError(f"batches {first}:{end} are not a range of the "
                         f"{nbatch} batches (0:{nbatch})")
    indices = list(range(first, end))
    jobs_args = [(seed, i, axes, min(per_batch, segments - per_batch * i),
                  corrupt[1] if corrupt and corrupt[0] == i else None) for i in indices]
    total = sum(a[3] for a in jobs_args)
    res = SoakResult(True, first_batch=first, end_batch=end, total_batches=nbatch)
    pending = None              # (path, chunk, Popen) the harness is checking
    model_s = 0.0

    def flush(batch_list, n):
        path = work / f"chunk{n:06d}.vec"
        with open(path, "wb") as f:
            vector_header(axes).tofile(f)
            for c in batch_list:
                f.write(c.words)
            vector_end().tofile(f)
        return path, batch_list, subprocess.Popen([str(binary), str(path)],
                                                  stdout=subprocess.PIPE,
                                                  stderr=subprocess.PIPE, text=True)

    pool = multiprocessing.Pool(jobs) if jobs > 1 and len(jobs_args) > 1 else None
    try:
        it = pool.imap(compute, jobs_args) if pool else map(compute, jobs_args)
        buf, n, done = [], 0, 0
        last = time.monotonic()
        for c in it:
            buf.append(c)
            model_s += c.seconds
            done += c.segments
            if len(buf) >= chunk or done >= total:
                if pending and not _check_chunk(*pending, res, segments, seed, axes,
                                                per_batch):
                    break
                pending = flush(buf, n)
                buf, n = [], n + 1
                if out and time.monotonic() - last > 30:
                    last = time.monotonic()
                    print(f"  {done} segments computed, {res.segments} checked, "
                          f"{time.monotonic() - t0:.0f} s", file=out, flush=True)
        if res.ok and pending:
            _check_chunk(*pending, res, segments, seed, axes, per_batch)
    finally:
        if pool:
            pool.terminate()
            pool.join()
    res.wall_seconds = time.monotonic() - t0
    res.model_seconds = model_s
    return res


def report(res: SoakResult, seed: int, axes: int, out=None) -> None:
    out = out or sys.stdout
    if not res.ok:
        print(f"SOAK FAILED: seed {seed}, NA {axes}, batch {res.failed_batch}", file=out)
        print(f"  first mismatch: {res.failure}", file=out)
        print(f"  vectors: {res.vectors}", file=out)
        print(f"  reproduce: {res.repro}", file=out)
        return
    rate = res.clocks / res.harness_seconds if res.harness_seconds else float("nan")
    cpu_rate = res.clocks / res.harness_cpu_seconds if res.harness_cpu_seconds else float("nan")
    print(f"soak passed: {res.segments} segments in {res.batches} batches, seed {seed}, "
          f"NA {axes}, W {HARNESS_W}", file=out)
    if (res.first_batch, res.end_batch) != (0, res.total_batches):
        print(f"  part of a run: batches {res.first_batch} .. {res.end_batch - 1} of "
              f"0 .. {res.total_batches - 1}", file=out)
    print(f"  {res.moves} moves and {res.clocks} clocks checked; harness "
          f"{rate / 1e6:.2f} M clocks/s ({res.harness_seconds:.1f} s; "
          f"{cpu_rate / 1e6:.2f} M clocks per CPU second)", file=out)
    print(f"  wall {res.wall_seconds:.1f} s; model and planning {res.model_seconds:.1f} CPU s "
          f"over the workers", file=out)
    arcs = Counter()
    for label, n in res.classes.items():
        if label[0] == "arc":
            arcs[label[1]] += n
            arcs[label[3]] += n
    lines = Counter({label[1]: n for label, n in res.classes.items() if label[0] == "line"})
    pairs = sum(1 for k in arcs if k.startswith("q"))
    print(f"  arcs: {sum(n for k, n in arcs.items() if k in RADIUS_CLASSES)} "
          f"({', '.join(f'{k} {arcs[k]}' for k in RADIUS_CLASSES)}; full circles "
          f"{arcs['full']}; {pairs} of 16 quadrant pairs)", file=out)
    print(f"  lines: {sum(lines.values())} "
          f"({', '.join(f'{k} {n}' for k, n in sorted(lines.items()))})", file=out)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--segments", type=int, default=1_000_000)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--axes", type=int, default=3, help="the core's NA (2 .. 6)")
    ap.add_argument("--per-batch", type=int, default=100, help="segments per batch (job)")
    ap.add_argument("--jobs", type=int, default=int(os.environ.get("JOBS", 2)))
    ap.add_argument("--chunk", type=int, default=50, help="batches per harness run")
    ap.add_argument("--only-batch", type=int, help="run only this batch (reproduce a failure)")
    ap.add_argument("--batches", metavar="FIRST:END",
                    help="run only batches FIRST .. END-1 of the run (a long soak in parts)")
    ap.add_argument("--build", choices=sorted(HARNESS_BUILDS), default=DEFAULT_BUILD,
                    help="the harness's build variant (flows.simspeed)")
    ap.add_argument("--corrupt", type=int, nargs=2, metavar=("BATCH", "MOVE"),
                    help="alter one expected move (to see the checker fail)")
    a = ap.parse_args(argv)
    if not 2 <= a.axes <= 6:
        ap.error("--axes must be 2 .. 6 (arcs move X and Y)")
    if a.segments < 1 or a.per_batch < 1:
        ap.error("--segments and --per-batch must be positive")
    batches = None
    if a.batches is not None:
        try:
            first, end = (int(x) for x in a.batches.split(":"))
        except ValueError:
            ap.error(f"--batches {a.batches!r}: expected FIRST:END, two integers")
        batches = (first, end)
        if a.only_batch is not None:
            ap.error("--batches and --only-batch exclude each other")
    try:
        res = soak(a.segments, a.seed, a.axes, a.per_batch, a.jobs, a.chunk, a.only_batch,
                   tuple(a.corrupt) if a.corrupt else None, out=sys.stdout, build=a.build,
                   batches=batches)
    except ValueError as e:
        ap.error(str(e))
    report(res, a.seed, a.axes)
    return 0 if res.ok else 1


if __name__ == "__main__":
    sys.exit(main())
