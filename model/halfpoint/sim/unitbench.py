# SPDX-License-Identifier: Apache-2.0
"""Generic cocotb driver, monitor and checker for the interpolation units.

Used inside a simulator only (it imports cocotb).  Every clock cycle, at the
falling edge, the bench reads every output of the DUT, compares it with the
unit's cycle-accurate model, then drives the inputs for the next rising edge
into both.  Command inputs that are not valid are driven with random values,
so the checker also sees that they are ignored.

A unit has: a command port (s_valid/s_ready + fields), en, rst, and the
outputs move, done, reject, err_code, busy plus unit-specific ones.  The
monitor attributes what it sees: a reject belongs to the most recently
accepted command (the validator holds one command at a time), moves and done
belong to the oldest accepted command that is neither rejected nor finished.
"""

from __future__ import annotations

import random
from abc import ABC, abstractmethod
from dataclasses import dataclass, field

import cocotb
from cocotb.clock import Clock
from cocotb.triggers import FallingEdge


class Mismatch(AssertionError):
    pass


@dataclass
class CmdResult:
    """What one accepted command did, as seen at the DUT's ports."""

    cmd: tuple
    moves: list = field(default_factory=list)
    rejected: int = 0
    finished: bool = False


@dataclass
class RunStats:
    cycles: int = 0
    moves: int = 0
    first_move: int | None = None
    last_done: int | None = None


class UnitBench(ABC):
    FIELDS: tuple = ()
    SIGNED: frozenset = frozenset()

    def __init__(self, dut, model, seed: int = 1, check: bool = True):
        self.dut = dut
        self.model = model
        self.rng = random.Random(seed)
        self.check = check
        self.cycle = 0
        self._clock_started = False

    # -- unit-specific hooks -------------------------------------------
    @abstractmethod
    def command_inputs(self, cmd):
        """Inputs that offer ``cmd`` on the command port."""

    @abstractmethod
    def idle_inputs(self, **kw):
        """Inputs with s_valid low and random command fields."""

    @abstractmethod
    def drive(self, inputs) -> None:
        """Put ``inputs`` on the DUT's ports."""

    @abstractmethod
    def move_record(self, got: dict):
        """What to record for a move shown in ``got``."""

    # -- common --------------------------------------------------------
    def drive_control(self, i) -> None:
        """The control inputs every unit has: rst, en, start_en, abort_now, s_valid."""
        d = self.dut
        d.rst.value = i.rst
        d.en.value = i.en
        d.start_en.value = i.start_en
        d.abort_now.value = i.abort
        d.s_valid.value = i.s_valid

    def _read(self) -> dict:
        out = {}
        for name in self.FIELDS:
            val = getattr(self.dut, name).value
            out[name] = val.to_signed() if name in self.SIGNED else int(val)
        return out

    async def _cycle(self, inputs) -> dict:
        """Check the outputs of this cycle, then drive ``inputs`` for the next edge."""
        await FallingEdge(self.dut.clk)
        got = self._read()
        if self.check:
            exp = vars(self.model.outputs())
            bad = [k for k in self.FIELDS if got[k] != exp[k]]
            if bad:
                detail = ", ".join(f"{k}: rtl={got[k]} model={exp[k]}" for k in bad)
                raise Mismatch(f"cycle {self.cycle}: {detail}")
        self.drive(inputs)
        self.model.clock(inputs)
        self.cycle += 1
        return got

    async def start(self) -> None:
        if not self._clock_started:
            cocotb.start_soon(Clock(self.dut.clk, 10, unit="ns").start())
            self._clock_started = True
        rst = self.idle_inputs(rst=1)
        self.drive(rst)
        self.model.clock(rst)
        for _ in range(2):
            await self._cycle(self.idle_inputs(rst=1))

    async def run(self, cmds, valid_idle: float = 0.0, en_idle: float = 0.0,
                  max_cycles: int = 10_000_000):
        """Drive ``cmds`` until every one is finished or rejected.

        ``valid_idle``: chance that s_valid stays low in a cycle although a
        command is waiting; ``en_idle``: chance that en is low in a cycle.
        """
        results: list[CmdResult] = []
        running: list[CmdResult] = []
        stats = RunStats()
        idx = 0
        start_cycle = self.cycle
        while True:
            if self.cycle - start_cycle > max_cycles:
                raise AssertionError(f"no completion within {max_cycles} cycles")
            if idx < len(cmds) and self.rng.random() >= valid_idle:
                inp = self.command_inputs(cmds[idx])
            else:
                inp = self.idle_inputs()
            inp.en = int(self.rng.random() >= en_idle)
            got = await self._cycle(inp)
            if got["reject"]:
                victim = results[-1]
                victim.rejected = got["err_code"]
                running.remove(victim)
            if got["move"]:
                running[0].moves.append(self.move_record(got))
                stats.moves += 1
                if stats.first_move is None:
                    stats.first_move = self.cycle - 1
            if got["done"]:
                running.pop(0).finished = True
                stats.last_done = self.cycle - 1
            if inp.s_valid and got["s_ready"]:
                res = CmdResult(cmd=tuple(cmds[idx]))
                results.append(res)
                running.append(res)
                idx += 1
            if idx == len(cmds) and not got["busy"] and not self.model.outputs().busy:
                break
        await self._cycle(self.idle_inputs())   # compare the last edge's outputs
        stats.cycles = self.cycle - start_cycle
        return results, stats
