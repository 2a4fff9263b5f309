# SPDX-License-Identifier: Apache-2.0
"""Text timing diagrams for the README, drawn from the cycle-accurate models.

    python -m halfpoint.flows.wavedoc
"""

from __future__ import annotations

from ..spec import encoding as enc
from ..spec.core import CoreInputs, CoreModel
from ..spec.stepgen import StepCfg, StepGenModel, StepInputs


def _row(name, vals, width=3):
    return f"{name:10s}" + "".join(f"{str(v):>{width}s}" for v in vals)


def _wave(name, bits):
    return f"{name:10s}" + "".join("  ‾" if b else "  _" for b in bits)


def segment_boundary() -> str:
    """An arc's last moves and the next line's first moves, queued ahead."""
    cfg = [StepCfg(1, 0, 0, 0)] * 3
    m = CoreModel(3, 32, 16, 16, cfg)
    m.clock(CoreInputs(rst=1))
    cmds = [enc.encode_arc(0, -6, 0, 0, 0, 2 * enc.RATE_ONE, cont=True),   # full circle R=6
            enc.encode_line([3, -2, 1], 2 * enc.RATE_ONE)]
    rows = []
    idx = 0
    for cyc in range(120):
        o = m.outputs()
        unit = "A" if m.arc.run is not None else "L" if m.line.run is not None else "-"
        rows.append((cyc, unit, o.move, o.pos, m.arc.out.done, m.line.out.done))
        inp = CoreInputs()
        if idx < len(cmds):
            inp = CoreInputs(tvalid=1, tdata=cmds[idx])
            if o.tready:
                idx += 1
        m.clock(inp)
    # window around the boundary
    b = next(k for k, r in enumerate(rows) if r[1] == "L")
    win = rows[b - 7:b + 7]
    lines = [
        _row("cycle", [r[0] for r in win]),
        _row("running", [r[1] for r in win]),
        _wave("move", [r[2] for r in win]),
        _row("pos x", [r[3][0] for r in win]),
        _row("pos y", [r[3][1] for r in win]),
        _row("pos z", [r[3][2] for r in win]),
    ]
    return "\n".join(lines)


def step_dir() -> str:
    """One axis: +, +, then - with steplen 2, stepspace 2, dirsetup 2, dirhold 1."""
    cfg = StepCfg(steplen=2, stepspace=2, dirsetup=2, dirhold=1)
    sg = StepGenModel()
    want = [1, 1, 0]
    taken = 0
    cols = []
    for cyc in range(17):
        o = sg.outputs(cfg)
        req = 0
        if taken < len(want):
            d = want[taken]
            if o.ready_pos if d else o.ready_neg:
                req = 1
        cols.append((cyc, o.step_pin, o.dir_pin, o.ready_pos, o.ready_neg, req,
                     ("+" if want[taken] else "-") if req else "."))
        sg.clock(cfg, StepInputs(req=req, req_dir=want[taken] if req else 0))
        taken += req
    return "\n".join([
        _row("cycle", [c[0] for c in cols]),
        _row("req", [c[6] for c in cols]),
        _wave("ready_pos", [c[3] for c in cols]),
        _wave("ready_neg", [c[4] for c in cols]),
        _wave("STEP", [c[1] for c in cols]),
        _wave("DIR", [c[2] for c in cols]),
    ])


if __name__ == "__main__":
    print("segment boundary\n" + segment_boundary())
    print("\nSTEP/DIR\n" + step_dir())
