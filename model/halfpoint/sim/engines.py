# SPDX-License-Identifier: Apache-2.0
"""The ``model`` and ``rtl`` engines of the command line.

``run_arcs``: arc commands through the arc unit; both engines return, for each
command, the lattice points from the start to the stop point inclusive, or the
reject code.  ``executor``: a command stream (commands and pauses, ``cam.motion``)
through the motion core with hold intervals, returning every move with its clock
cycle, the error codes and the flags (what ``halfpoint segments`` and ``halfpoint
run`` execute).  The ``rtl`` engines run the Verilator-built
modules through cocotb and report only what the RTL's outputs showed.
"""

from __future__ import annotations

import json
import os
import tempfile
from dataclasses import dataclass
from pathlib import Path

from ..spec.arc import ERR_RANGE, ArcRejected, arc_points
from ..spec.rules import fits

ENGINES = ("model", "rtl")


@dataclass
class ArcOutcome:
    cmd: tuple[int, int, int, int, int]    # (cw, xs, ys, xe, ye)
    points: list[tuple[int, int]]
    rejected: int = 0


def run_model(cmds, width: int = 32) -> list[ArcOutcome]:
    out = []
    for c in cmds:
        cw, xs, ys, xe, ye = c
        try:
            out.append(ArcOutcome(tuple(c), arc_points(xs, ys, xe, ye, cw, width)))
        except ArcRejected as exc:
            out.append(ArcOutcome(tuple(c), [(xs, ys)], exc.code))
    return out


def run_rtl(cmds, width: int = 32) -> list[ArcOutcome]:
    """Simulate the commands, back to back, on ``halfpoint_arc`` (Verilator)."""
    from .env import BUILD, rtl_sources, run_cocotb

    for c in cmds:
        for v in c[1:]:
            if not fits(v, width):
                raise ArcRejected(ERR_RANGE, f"{v} does not fit {width} bits")
    BUILD.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory(dir=BUILD) as tmp:
        out_file = Path(tmp) / "out.json"
        run_cocotb(
            toplevel="halfpoint_arc",
            sources=rtl_sources("halfpoint_arc"),
            test_module="halfpoint.sim.rtl_engine_arc",
            test_dir=Path(tmp),
            parameters={"W": width},
            build_name=f"engine_arc_w{width}",
            extra_env={
                "HP_CMDS": json.dumps([list(c) for c in cmds]),
                "HP_OUT": str(out_file),
                "COCOTB_LOG_LEVEL": os.environ.get("COCOTB_LOG_LEVEL", "WARNING"),
            },
            quiet=True,
        )
        data = json.loads(out_file.read_text(encoding="utf-8"))
    res = []
    for r in data["results"]:
        if not r["rejected"] and not r["finished"]:
            raise RuntimeError(f"RTL did not finish {r['cmd']}")
        res.append(ArcOutcome(tuple(r["cmd"]), [tuple(p) for p in r["points"]], r["rejected"]))
    return res


def run_arcs(cmds, engine: str = "model", width: int = 32) -> list[ArcOutcome]:
    if engine == "model":
        return run_model(cmds, width)
    if engine == "rtl":
        return run_rtl(cmds, width)
    raise ValueError(f"unknown engine {engine!r} (choose from {', '.join(ENGINES)})")


def run_core_rtl(items, config, holds=(), max_clocks: int | None = None):
    """The Verilator-built ``halfpoint_core`` as an executor (``cam.motion``'s
    interface): built with the config's NA, W, DEPTH, TW, DIV, MOVE_DEPTH and
    PROFILE_DEPTH, driven by ``cam.motion.Feeder`` (pauses, holds) from the cocotb
    module ``rtl_engine_core``, which reports only what the RTL's outputs showed."""
    from ..cam.motion import Execution, Pause, max_clocks_for
    from .design import design_sources
    from .env import BUILD, run_cocotb

    BUILD.mkdir(parents=True, exist_ok=True)
    params = {"NA": config.axes, "W": config.width, "DEPTH": config.depth, "TW": config.tw,
              "DIV": config.div, "MOVE_DEPTH": config.move_depth,
              "PROFILE_DEPTH": config.profile_depth}
    cfg = [vars(c) for c in config.step_cfg()]
    with tempfile.TemporaryDirectory(dir=BUILD) as tmp:
        cmd_file, out_file = Path(tmp) / "cmds.json", Path(tmp) / "out.json"
        cmd_file.write_text(json.dumps({
            "items": [{"pause": it.clocks, "seconds": it.seconds, "lineno": it.lineno}
                      if isinstance(it, Pause) else str(it) for it in items],
            "holds": [list(h) for h in holds], "cfg": cfg,
            "max_clocks": max_clocks or max_clocks_for(items, holds)}))
        run_cocotb(
            toplevel="halfpoint_core",
            sources=design_sources("halfpoint_core"),
            test_module="halfpoint.sim.rtl_engine_core",
            test_dir=Path(tmp),
            parameters=params,
            build_name="engine_core_" + "_".join(f"{k.lower()}{v}" for k, v in params.items()),
            extra_env={"HP_CMDS": str(cmd_file), "HP_OUT": str(out_file),
                       "COCOTB_LOG_LEVEL": os.environ.get("COCOTB_LOG_LEVEL", "WARNING")},
            quiet=True,
        )
        data = json.loads(out_file.read_text())
    if "failure" in data:
        raise RuntimeError(data["failure"])
    return Execution([(c, tuple(p)) for c, p in data["moves"]], data["errors"], data["dry"],
                     data["underrun"], data["cycles"])


def executor(engine: str):
    """``(items, CoreConfig, holds) -> Execution`` for an engine name (what
    ``halfpoint.cam.run.run_program`` and ``segments`` take)."""
    if engine == "model":
        from ..cam.motion import run_model
        return run_model
    if engine == "rtl":
        return run_core_rtl
    raise ValueError(f"unknown engine {engine!r} (choose from {', '.join(ENGINES)})")
