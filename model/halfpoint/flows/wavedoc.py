# SPDX-License-Identifier: Apache-2.0
"""Text timing diagrams for the README, drawn from the cycle-accurate models.

    python -m halfpoint.flows.wavedoc
"""

from __future__ import annotations

from ..spec import encoding as enc
from ..spec.core import CoreInputs, CoreModel
from ..spec.program import move_count, profiled
from ..spec.stepgen import StepCfg, StepGenModel, StepInputs


def _row(name, vals, width=3):
    return f"{name:10s}" + "".join(f"{str(v):>{width}s}" for v in vals)


def _wave(name, bits):
    return f"{name:10s}" + "".join("  ‾" if b else "  _" for b in bits)


def segment_boundary() -> str:
    """An arc's last moves and the next line's first moves, queued ahead (profiles
    for 0.45 BLU per clock, the junction taken at full speed): the boundary costs
    the pins nothing."""
    cfg = [StepCfg(1, 0, 0, 0)] * 3
    m = CoreModel(3, 32, 16, 16, 1, 4, 2, cfg)
    m.clock(CoreInputs(rst=1))
    fast = int(0.45 * (1 << 32))
    arc_moves = move_count(enc.encode_arc(0, -6, 0, 0, 0), 3, 32)
    cmds = profiled([enc.encode_arc(0, -6, 0, 0, 0, cont=True),     # full circle R=6
                     enc.encode_line([3, -2, 1])], 3, 32, 1, v_cruise=fast, accel=1 << 36 - 3,
                    junction=fast)
    rows = []
    idx = 0
    for cyc in range(160):
        o = m.outputs()
        unit = "A" if m.arc.run is not None else "L" if m.line.run is not None else "-"
        rows.append((cyc, unit, o.move, o.pos, m.arc.out.done, m.line.out.done))
        inp = CoreInputs()
        if idx < len(cmds):
            inp = CoreInputs(tvalid=1, tdata=cmds[idx])
            if o.tready:
                idx += 1
        m.clock(inp)
    # window around the boundary of the moves: the rows after the arc's last move
    made = 0
    for b, r in enumerate(rows):
        made += r[2]
        if made == arc_moves + 1:
            break
    win = rows[b - 9:b + 8]
    lines = [
        _row("cycle", [r[0] for r in win]),
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


def hold_resume(every: int = 16) -> str:
    """Feed hold and resume on a straight line: hold asserted at clock 1600 and
    released at 3200; sampled every ``every`` clocks (the profile tick, DIV 4):
    hold, the path speed register (BLU per clock), moves made so far."""
    cfg = [StepCfg(1, 0, 0, 0)] * 3
    m = CoreModel(3, 32, 16, 16, 4, 4, 2, cfg)
    m.clock(CoreInputs(rst=1))
    cmds = profiled([enc.encode_line([2000, 500, 0])], 3, 32, 4, v_cruise=int(0.4 * (1 << 32)),
                    accel=1 << 32)
    idx = moves = 0
    cols = []
    for cyc in range(4800):
        o = m.outputs()
        hold = int(1600 <= cyc < 3200)
        moves += o.move
        if cyc % every == 0 and 1200 <= cyc < 3800 and (cyc // every) % 6 == 0:
            cols.append((cyc, hold, o.speed / 2 ** 38, moves))
        inp = CoreInputs(hold=hold)
        if idx < len(cmds):
            inp = CoreInputs(tvalid=1, tdata=cmds[idx], hold=hold)
            if o.tready:
                idx += 1
        m.clock(inp)
    return "\n".join([
        _row("cycle", [c[0] for c in cols], 6),
        _row("hold", [c[1] for c in cols], 6),
        _row("speed", [f"{c[2]:.2f}" for c in cols], 6),
        _row("moves", [c[3] for c in cols], 6),
    ])


if __name__ == "__main__":
    print("segment boundary\n" + segment_boundary())
    print("\nfeed hold and resume\n" + hold_resume())
    print("\nSTEP/DIR\n" + step_dir())
