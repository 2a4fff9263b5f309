# SPDX-License-Identifier: Apache-2.0
"""Verilator simulation speed of the motion core (``make bench``), and the compiled
harness that ``make soak`` checks with.

* cocotb: the core's `mixed_program` cocotb test (every clock compared with
  the model, every pin edge checked) at NA=3, W=32; clocks per second of wall
  time, from the simulated time and the wall time in cocotb's results file.
* compiled: tb/halfpoint_core/speed_harness.cpp, a C++ harness built with
  Verilator; the model (``spec.fastcore.run_fast``) runs each job first and the
  harness gets its expected moves as vectors (``Batch`` / ``write_vectors``): it
  only drives the inputs and compares every move strobe's clock and positions,
  the error codes, the run's length and the final dry / underrun flags.  Clocks
  per second of the harness's simulation loop (reading the file and building
  excluded).

``HARNESS_BUILDS`` are the build variants ``compiled_variants`` compares (the
bench reports ``DEFAULT_BUILD``, the fastest measured).
"""

from __future__ import annotations

import fcntl
import hashlib
import random
import shutil
import subprocess
import sys
import time
import xml.etree.ElementTree as ET
from array import array
from dataclasses import dataclass, field
from pathlib import Path

from ..sim.design import design_sources
from ..sim.env import BUILD, REPO, run_cocotb, setup_verilator_env
from ..spec import encoding as enc
from ..spec.fastcore import run_fast
from ..spec.profile import OVERRIDE_ONE
from ..spec.program import profiled, random_arc, random_line
from ..spec.rules import wrap
from ..spec.stepgen import StepCfg

CLK_NS = 10          # the cocotb benches' clock period

HARNESS_W = 32              # the harness reads positions as signed 32-bit words
HARNESS_TW = 16             # STEP/DIR timer width the harness packs settings into
HARNESS_DEPTH = 16          # command queue depth
HARNESS_DIV = 4             # the harness core's profile tick, 2^4 clocks
HARNESS_MOVE_DEPTH = 4      # the core's default move and profile queue depths
HARNESS_PROFILE_DEPTH = 2
MAGIC = 0x314B414F53504848  # "HHPSOAK1", the vector file's first word
HARNESS_SOURCE = REPO / "tb" / "halfpoint_core" / "speed_harness.cpp"

# Build variants: name -> (Verilator options, C++ compiler flags, profile-guided).  A
# profile-guided build is built instrumented, run on a training program (``program``
# with TRAIN_SEED, not the measured seed) and built again with the profile.
XFAST = ["-O3", "--x-assign", "fast", "--x-initial", "fast", "--no-timing"]
HARNESS_BUILDS = {
    "O3": (["-O3"], "-O2", False),
    "O3-xfast": (XFAST, "-O3", False),
    "O3-xfast-native": (XFAST, "-O3 -march=native", False),
    "O3-xfast-pgo": (XFAST, "-O3", True),
    "quick": (XFAST[1:], "-O1", False),     # the quickest to build: make test's soak
}
DEFAULT_BUILD = "O3-xfast-pgo"
TRAIN_SEED = 7


def cocotb_speed(seed: int = 1) -> dict:
    """Clocks per second of the core's cocotb test with per-clock checking."""
    tb = REPO / "tb" / "halfpoint_core"
    if str(tb) not in sys.path:
        sys.path.insert(0, str(tb))          # the runner hands sys.path to the simulator
    name = "core_na3_w32_d16_speed"
    results = run_cocotb(
        toplevel="halfpoint_core",
        sources=design_sources("halfpoint_core"),
        test_module="core_cocotb",
        test_dir=BUILD / "sim" / name / "run",
        parameters={"NA": 3, "W": 32, "DEPTH": 16, "TW": 16, "DIV": HARNESS_DIV},
        build_name=name,
        extra_env={"HP_SEED": seed},
        testcase="mixed_program",
        quiet=True,
    )
    case = ET.parse(results).getroot().find(".//testcase")
    props = {p.get("name"): p.get("value") for p in case.iter("property")}
    if props.get("sim_time_unit") != "ns":
        raise RuntimeError(f"unexpected simulation time unit in {results}")
    sim_ns = float(props["sim_time_duration"])
    wall = float(case.get("time"))
    clocks = sim_ns / CLK_NS
    return {"clocks": int(clocks), "seconds": round(wall, 3), "clocks_per_s": round(clocks / wall)}


# --- the compiled harness ---------------------------------------------------------------------

@dataclass
class Batch:
    """One job for the harness: run from reset after ``gap`` idle clocks (tvalid low)."""

    cmds: list                      # encoded commands
    axes: int = 3
    cfg: list = field(default_factory=list)     # StepCfg per axis (default: all 1)
    holds: list = field(default_factory=list)   # (A, B): hold high in A <= clock < B
    override: int = OVERRIDE_ONE    # the feed override, constant
    gap: int = 0                    # idle clocks before the batch's reset
    # (A, B): tvalid low in A <= clock < B while the batch runs (a beat offered
    # and not yet taken stays offered, as AXI4-Stream requires)
    stream_gaps: list = field(default_factory=list)

    def settings(self) -> list:
        return self.cfg or [StepCfg() for _ in range(self.axes)]


@dataclass
class Expected:
    """What the model saw on a batch (``run_fast``'s result, reduced)."""

    times: list
    trace: list
    errors: list
    clocks: int
    dry: int
    underrun: int


def model_run(batch: Batch) -> Expected:
    """The model's run of a batch (``spec.fastcore.run_fast``)."""
    run = run_fast(batch.cmds, batch.axes, HARNESS_W, HARNESS_DEPTH, HARNESS_TW, HARNESS_DIV,
                   HARNESS_MOVE_DEPTH, HARNESS_PROFILE_DEPTH, batch.settings(),
                   holds=batch.holds, override=batch.override, gaps=batch.stream_gaps)
    return Expected(run.times, run.trace, run.errors, run.clocks, run.dry, run.underrun)


def check_intervals(intervals, what: str = "hold") -> list:
    """Hold intervals or stream gaps as the harness needs them: sorted, each
    non-empty, disjoint and not touching (the harness switches hold, or tvalid, at
    the interval edges only)."""
    out = sorted((int(a), int(b)) for a, b in intervals)
    for (a, b), nxt in zip(out, out[1:] + [None]):
        if not 0 <= a < b or (nxt is not None and nxt[0] <= b):
            raise ValueError(f"{what} intervals must be non-empty, disjoint and apart: {out}")
    return out


def batch_words(batch_id: int, batch: Batch, exp: Expected) -> array:
    """One batch of the vector file (format: the harness's header comment)."""
    mask = (1 << 64) - 1
    holds = check_intervals(batch.holds)
    gaps = check_intervals(batch.stream_gaps, "stream gap")
    w = array("Q", [batch_id, len(batch.cmds), len(exp.times), len(exp.errors), len(holds),
                    len(gaps), exp.clocks, exp.dry, exp.underrun, batch.override, batch.gap])
    cfg = batch.settings()
    if len(cfg) != batch.axes:
        raise ValueError(f"{len(cfg)} STEP/DIR settings for {batch.axes} axes")
    for c in cfg:
        w.extend((c.steplen, c.stepspace, c.dirsetup, c.dirhold, c.step_inv, c.dir_inv))
    for cmd in batch.cmds:
        w.extend((cmd >> (64 * k)) & mask for k in range(enc.CMD_BITS // 64))
    for a, b in holds:
        w.extend((a, b))
    for a, b in gaps:
        w.extend((a, b))
    for t, p in zip(exp.times, exp.trace):
        w.append(t)
        w.extend(wrap(v, HARNESS_W) & mask for v in p)
    w.extend(exp.errors)
    return w


def vector_header(axes: int) -> array:
    return array("Q", [MAGIC, axes])


def vector_end() -> array:
    return array("Q", [(1 << 64) - 1])


def write_vectors(path: Path, axes: int, batches) -> None:
    """A vector file of ``batches``: (batch id, Batch, Expected) triples."""
    with open(path, "wb") as f:
        vector_header(axes).tofile(f)
        for batch_id, batch, exp in batches:
            batch_words(batch_id, batch, exp).tofile(f)
        vector_end().tofile(f)


def _verilate(work: Path, axes: int, vopts, cflags: str, ldflags: str = "") -> None:
    exe = setup_verilator_env()
    cmd = [str(exe), "--cc", "--exe", "--build", *vopts, "-j", "2",
           "--top-module", "halfpoint_core",
           f"-GNA={axes}", f"-GW={HARNESS_W}", f"-GDEPTH={HARNESS_DEPTH}", f"-GTW={HARNESS_TW}",
           f"-GDIV={HARNESS_DIV}", "-Wno-fatal", "-Mdir", str(work / "obj"),
           "-CFLAGS", f"{cflags} -DHP_NA={axes}", f"-I{REPO / 'rtl'}",
           *(["-LDFLAGS", ldflags] if ldflags else []),
           str(HARNESS_SOURCE), *(str(p) for p in design_sources("halfpoint_core"))]
    log = work / "build.log"
    proc = subprocess.run(cmd, capture_output=True, text=True)
    with log.open("a") as f:
        f.write(" ".join(cmd) + "\n" + proc.stdout + proc.stderr)
    if proc.returncode != 0 or not (work / "obj" / "Vhalfpoint_core").exists():
        raise RuntimeError(f"Verilator build of the harness failed, see {log}")


def harness_binary(axes: int = 3, build: str = DEFAULT_BUILD) -> tuple[Path, float]:
    """The harness for NA=``axes`` built with ``HARNESS_BUILDS[build]`` (rebuilt when
    the harness, the RTL or the options change); returns (executable, build seconds,
    0 when it was up to date)."""
    vopts, cflags, pgo = HARNESS_BUILDS[build]
    key = hashlib.sha256()
    for p in [HARNESS_SOURCE, *(Path(p) for p in design_sources("halfpoint_core"))]:
        key.update(p.read_bytes())
    key.update(repr((axes, vopts, cflags, pgo, TRAIN_SEED)).encode())
    work = BUILD / "harness" / f"na{axes}_{build}"
    # one build at a time per harness: pytest-xdist workers (make test) and the soak's
    # processes may ask for the same one at once, and a second build deletes the first's
    # work directory under it
    work.parent.mkdir(parents=True, exist_ok=True)
    with open(work.parent / f"na{axes}_{build}.lock", "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        try:
            return _harness_build(work, axes, build, key.hexdigest())
        finally:
            fcntl.flock(lock, fcntl.LOCK_UN)


def _harness_build(work: Path, axes: int, build: str, digest: str) -> tuple[Path, float]:
    """harness_binary's build, under its lock."""
    vopts, cflags, pgo = HARNESS_BUILDS[build]
    obj = work / "obj"
    binary = obj / "Vhalfpoint_core"
    stamp = work / "stamp"
    if binary.exists() and stamp.exists() and stamp.read_text() == digest:
        return binary, 0.0
    if work.exists():
        shutil.rmtree(work)
    work.mkdir(parents=True)
    t0 = time.monotonic()
    if pgo:
        gen = "-fprofile-generate -fprofile-update=single"
        _verilate(work, axes, vopts, f"{cflags} {gen}", gen)
        batch = Batch(program(seed=TRAIN_SEED, axes=axes), axes)
        train = work / "train.vec"
        write_vectors(train, axes, [(0, batch, model_run(batch))])
        res = run_harness(binary, train)
        if not res.ok:
            raise RuntimeError(f"harness training run: {res.failure}")
        for f in obj.iterdir():             # keep the profiles (*.gcda), rebuild the rest
            if f.suffix in (".o", ".a") or f == binary:
                f.unlink()
        _verilate(work, axes, vopts,
                  f"{cflags} -fprofile-use -fprofile-correction -Wno-missing-profile")
    else:
        _verilate(work, axes, vopts, cflags)
    stamp.write_text(digest)
    return binary, time.monotonic() - t0


@dataclass
class HarnessResult:
    ok: bool
    batches: int = 0
    clocks: int = 0
    seconds: float = 0.0           # the simulation loop's wall time
    moves: int = 0
    cpu_seconds: float = 0.0        # ... and its CPU time
    failure: str = ""               # the harness's FAIL line


def parse_harness(proc: subprocess.CompletedProcess) -> HarnessResult:
    """The harness's verdict from its output."""
    out = proc.stdout.strip()
    if proc.returncode == 1 and "FAIL" in out:
        return HarnessResult(False, failure=out.splitlines()[-1])
    if proc.returncode != 0:
        raise RuntimeError(f"harness exited {proc.returncode}: {out} {proc.stderr.strip()}")
    words = out.split()
    vals = dict(zip(words[0::2], words[1::2]))
    return HarnessResult(True, int(vals["batches"]), int(vals["clocks"]), float(vals["seconds"]),
                         int(vals["moves"]), float(vals["cpu_seconds"]))


def run_harness(binary: Path, vectors: Path, repeats: int = 1) -> HarnessResult:
    return parse_harness(subprocess.run([str(binary), str(vectors), str(repeats)],
                                        capture_output=True, text=True))


# --- the bench figure -------------------------------------------------------------------------

def program(n: int = 300, seed: int = 1, axes: int = 3) -> list[int]:
    """Random arcs and lines with planned profiles (0.2..0.45 BLU per clock)."""
    rng = random.Random(seed)
    cmds = []
    for _ in range(n):
        if rng.random() < 0.5:
            cmds.append(random_arc(rng, cont=True))
        else:
            cmds.append(random_line(rng, axes, cont=True, scale=60))
    return profiled(cmds, axes, 32, HARNESS_DIV,
                    v_cruise=lambda k: int(rng.uniform(0.2, 0.45) * 2**32),
                    accel=1 << 32, rng=rng)


def compiled_speed(repeats: int = 200, seed: int = 1, build: str = DEFAULT_BUILD) -> dict:
    """Clocks per second of the compiled harness (NA=3, W=32; checked against the model)."""
    binary, build_s = harness_binary(3, build)
    batch = Batch(program(seed=seed), 3)
    vec = BUILD / "harness" / f"bench_seed{seed}.vec"
    write_vectors(vec, 3, [(0, batch, model_run(batch))])
    res = run_harness(binary, vec, repeats)
    if not res.ok:
        raise RuntimeError(f"speed harness: {res.failure}")
    return {"clocks": res.clocks, "seconds": round(res.seconds, 3),
            "clocks_per_s": round(res.clocks / res.seconds),
            "cpu_seconds": round(res.cpu_seconds, 3),
            "clocks_per_cpu_s": round(res.clocks / res.cpu_seconds),
            "options": " ".join(HARNESS_BUILDS[build][0]) + " / " + HARNESS_BUILDS[build][1]
            + (" / profile-guided" if HARNESS_BUILDS[build][2] else ""),
            "moves_checked": res.moves, "build_s": round(build_s, 1), "build": build}


def compiled_variants(repeats: int = 200, seed: int = 1) -> dict:
    """``compiled_speed`` of every build variant."""
    return {name: compiled_speed(repeats, seed, name) for name in HARNESS_BUILDS}


if __name__ == "__main__":
    if "--variants" in sys.argv:
        for name, res in compiled_variants().items():
            print(name, res)
    else:
        print("compiled", compiled_speed())
        print("cocotb", cocotb_speed())
