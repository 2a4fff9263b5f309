# SPDX-License-Identifier: Apache-2.0
"""Verilator simulation speed of the motion core, for ``make bench``.

* cocotb: the core's `mixed_program` cocotb test (every clock compared with
  the model, every pin edge checked) at NA=3, W=32; clocks per second of wall
  time, from the simulated time and the wall time in cocotb's results file.
* compiled: tb/halfpoint_core/speed_harness.cpp, a C++ harness built with
  Verilator (-O3), streaming a program generated here and checking every
  move's clock and positions against the model; clocks per second of the
  simulation loop.
"""

from __future__ import annotations

import random
import subprocess
import sys
import time
import xml.etree.ElementTree as ET
from pathlib import Path

from ..spec.core import CoreModel, run_program
from ..spec.program import profiled, random_arc, random_line
from ..sim.design import design_sources
from ..sim.env import BUILD, REPO, run_cocotb, setup_verilator_env
from ..spec.stepgen import StepCfg

CLK_NS = 10          # the cocotb benches' clock period


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


HARNESS_DIV = 4             # the harness core's profile tick, 2^4 clocks


def program(n: int = 300, seed: int = 1) -> list[int]:
    """Random arcs and lines with planned profiles (0.2..0.45 BLU per clock)."""
    rng = random.Random(seed)
    cmds = []
    for _ in range(n):
        if rng.random() < 0.5:
            cmds.append(random_arc(rng, cont=True))
        else:
            cmds.append(random_line(rng, 3, cont=True, scale=60))
    return profiled(cmds, 3, 32, HARNESS_DIV, v_cruise=lambda k: int(rng.uniform(0.2, 0.45) * 2**32),
                    accel=1 << 32, rng=rng)


def compiled_speed(repeats: int = 200, seed: int = 1) -> dict:
    """Clocks per second of the compiled harness (checked against the model)."""
    exe = setup_verilator_env()
    work = BUILD / "bench" / "speed_harness"
    work.mkdir(parents=True, exist_ok=True)
    cmds = program(seed=seed)
    m = CoreModel(3, 32, 16, 16, HARNESS_DIV, 4, 2, [StepCfg(1, 1, 1, 1)] * 3)
    run = run_program(m, cmds)
    vec = work / "vectors.txt"
    with vec.open("w") as f:
        f.write(f"{len(cmds)} {len(run.trace)}\n")
        for c in cmds:
            f.write(f"{c:064x}\n")
        for t, p in zip(run.times, run.trace):
            f.write(f"{t} {p[0]} {p[1]} {p[2]}\n")
    binary = work / "obj" / "Vhalfpoint_core"
    cmd = [str(exe), "--cc", "--exe", "--build", "-O3", "-j", "2", "--top-module", "halfpoint_core",
           "-GNA=3", "-GW=32", "-GDEPTH=16", "-GTW=16", f"-GDIV={HARNESS_DIV}", "-Wno-fatal", "-Mdir", str(work / "obj"),
           "-CFLAGS", "-O2", f"-I{REPO / 'rtl'}",
           str(REPO / "tb" / "halfpoint_core" / "speed_harness.cpp"),
           *(str(p) for p in design_sources("halfpoint_core"))]
    log = work / "build.log"
    t0 = time.monotonic()
    proc = subprocess.run(cmd, capture_output=True, text=True)
    log.write_text(proc.stdout + proc.stderr)
    if proc.returncode != 0 or not binary.exists():
        raise RuntimeError(f"Verilator build of the speed harness failed, see {log}")
    build_s = time.monotonic() - t0
    proc = subprocess.run([str(binary), str(vec), str(repeats)], capture_output=True, text=True)
    if proc.returncode != 0:
        raise RuntimeError(f"speed harness: {proc.stdout}{proc.stderr}")
    words = proc.stdout.split()
    vals = dict(zip(words[0::2], words[1::2]))
    clocks, secs = int(vals["clocks"]), float(vals["seconds"])
    return {"clocks": clocks, "seconds": round(secs, 3), "clocks_per_s": round(clocks / secs),
            "moves_checked": int(vals["moves"]), "build_s": round(build_s, 1)}


if __name__ == "__main__":
    print("compiled", compiled_speed())
    print("cocotb", cocotb_speed())
