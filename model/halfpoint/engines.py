# SPDX-License-Identifier: Apache-2.0
"""Run arc commands through the model or through the Verilator-simulated RTL.

Both engines return the same structure: for each command, the lattice points
from the start to the stop point inclusive, or the reject code.
"""

from __future__ import annotations

import json
import os
import tempfile
from dataclasses import dataclass
from pathlib import Path

from .arc import ArcRejected, arc_points, field_ok, ERR_RANGE

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
    from .sim import BUILD, rtl_sources, run_cocotb

    for c in cmds:
        for v in c[1:]:
            if not field_ok(v, width):
                raise ArcRejected(ERR_RANGE, f"{v} does not fit {width} bits")
    BUILD.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory(dir=BUILD) as tmp:
        out_file = Path(tmp) / "out.json"
        run_cocotb(
            toplevel="halfpoint_arc",
            sources=rtl_sources("halfpoint_arc"),
            test_module="halfpoint.rtl_engine",
            test_dir=Path(tmp),
            parameters={"W": width},
            build_name=f"engine_arc_w{width}",
            extra_env={
                "HP_W": width,
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
