# SPDX-License-Identifier: Apache-2.0
"""cocotb driver, monitor and checker for ``halfpoint_arc``.

Used inside a simulator only (it imports cocotb): by the cocotb tests in
``tb/halfpoint_arc/`` and by the ``rtl`` engine of the command line.

Every clock cycle, at the falling edge, the bench reads every output of the
DUT, compares it with :class:`halfpoint.arc.ArcUnitModel`, then drives the
inputs for the next rising edge into both.  Inputs that are not valid are
driven with random values, so the checker also sees that they are ignored.
"""

from __future__ import annotations

import random
from dataclasses import dataclass, field

import cocotb
from cocotb.clock import Clock
from cocotb.triggers import FallingEdge

from .arc import ArcInputs, ArcUnitModel

FIELDS = (
    "s_ready", "busy", "move", "step_x", "step_y", "dir_x", "dir_y",
    "x", "y", "f", "done", "reject", "err_code",
)
SIGNED = {"x", "y", "f"}


class Mismatch(AssertionError):
    pass


@dataclass
class ArcResult:
    """What one accepted command did, as seen at the DUT's ports."""

    cmd: tuple[int, int, int, int, int]
    points: list[tuple[int, int]] = field(default_factory=list)
    rejected: int = 0
    finished: bool = False


@dataclass
class RunStats:
    cycles: int = 0
    moves: int = 0
    first_move: int | None = None
    last_done: int | None = None


class ArcBench:
    def __init__(self, dut, width: int, seed: int = 1, check: bool = True):
        self.dut = dut
        self.width = width
        self.rng = random.Random(seed)
        self.check = check
        self.model = ArcUnitModel(width)
        self.cycle = 0
        self.mask = (1 << width) - 1
        self._clock_started = False

    # -- low level -----------------------------------------------------
    def _read(self) -> dict:
        d = self.dut
        out = {}
        for name in FIELDS:
            val = getattr(d, name).value
            out[name] = val.to_signed() if name in SIGNED else int(val)
        return out

    def _drive(self, i: ArcInputs) -> None:
        d = self.dut
        d.rst.value = i.rst
        d.en.value = i.en
        d.s_valid.value = i.s_valid
        d.s_cw.value = i.s_cw
        for name in ("s_xs", "s_ys", "s_xe", "s_ye"):
            getattr(d, name).value = getattr(i, name) & self.mask

    def _random_garbage(self) -> ArcInputs:
        r = self.rng
        half = 1 << (self.width - 1)
        return ArcInputs(
            s_valid=0, s_cw=r.randint(0, 1),
            s_xs=r.randrange(-half, half), s_ys=r.randrange(-half, half),
            s_xe=r.randrange(-half, half), s_ye=r.randrange(-half, half),
        )

    async def _cycle(self, i: ArcInputs) -> dict:
        """Check the outputs of this cycle, then drive ``i`` for the next edge."""
        await FallingEdge(self.dut.clk)
        got = self._read()
        if self.check:
            exp = vars(self.model.outputs())
            bad = [k for k in FIELDS if got[k] != exp[k]]
            if bad:
                detail = ", ".join(f"{k}: rtl={got[k]} model={exp[k]}" for k in bad)
                raise Mismatch(f"cycle {self.cycle}: {detail}")
        self._drive(i)
        self.model.clock(i)
        self.cycle += 1
        return got

    async def start(self) -> None:
        if not self._clock_started:
            cocotb.start_soon(Clock(self.dut.clk, 10, unit="ns").start())
            self._clock_started = True
        self._drive(ArcInputs(rst=1))
        self.model.clock(ArcInputs(rst=1))
        for _ in range(2):
            await self._cycle(ArcInputs(rst=1))
        # The model was reset before the first checked cycle; the RTL has
        # been in reset for the same edges, so both start aligned.

    # -- command runs --------------------------------------------------
    async def run(
        self,
        cmds,
        valid_idle: float = 0.0,
        en_idle: float = 0.0,
        max_cycles: int = 10_000_000,
    ) -> tuple[list[ArcResult], RunStats]:
        """Drive ``cmds`` (cw, xs, ys, xe, ye) until all are done or rejected.

        ``valid_idle``: chance that s_valid stays low in a cycle although a
        command is waiting; ``en_idle``: chance that en is low in a cycle.
        """
        results: list[ArcResult] = []
        running: list[ArcResult] = []      # accepted, not rejected, not finished
        stats = RunStats()
        idx = 0
        start_cycle = self.cycle
        while True:
            if self.cycle - start_cycle > max_cycles:
                raise AssertionError(f"no completion within {max_cycles} cycles")
            pending = idx < len(cmds)
            if pending and self.rng.random() >= valid_idle:
                cw, xs, ys, xe, ye = cmds[idx]
                inp = ArcInputs(s_valid=1, s_cw=cw, s_xs=xs, s_ys=ys, s_xe=xe, s_ye=ye)
            else:
                inp = self._random_garbage()
            inp.en = int(self.rng.random() >= en_idle)
            got = await self._cycle(inp)
            # monitor: attribute what this cycle shows
            if got["reject"]:
                # the validator held the most recently accepted command
                victim = results[-1]
                victim.rejected = got["err_code"]
                running.remove(victim)
            if got["move"]:
                arc = running[0]
                arc.points.append((got["x"], got["y"]))
                stats.moves += 1
                if stats.first_move is None:
                    stats.first_move = self.cycle - 1
            if got["done"]:
                arc = running.pop(0)
                arc.finished = True
                stats.last_done = self.cycle - 1
            # accept: s_ready seen this cycle and s_valid driven for the edge
            if inp.s_valid and got["s_ready"]:
                res = ArcResult(cmd=tuple(cmds[idx]))
                res.points.append((cmds[idx][1], cmds[idx][2]))
                results.append(res)
                running.append(res)
                idx += 1
            if idx == len(cmds) and not got["busy"] and not inp.s_valid and not self.model.outputs().busy:
                break
        # one more checked cycle so the last edge's outputs are compared
        await self._cycle(self._random_garbage())
        stats.cycles = self.cycle - start_cycle
        return results, stats
