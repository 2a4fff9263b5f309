# SPDX-License-Identifier: Apache-2.0
"""cocotb bench for ``halfpoint_core``: cocotbext-axi drives the command
stream; a monitor compares every output (positions, STEP/DIR pins, status)
with :class:`halfpoint.spec.core.CoreModel` on every clock and runs an independent
timing checker on every axis's pins.

Used inside a simulator only (it imports cocotb).  It also reads a few of the
core's internal signals (the registered step readiness and the head move);
HP_CORE_SCOPE names the instance that holds them when it is not the top, as
in the mutation flow's wrapper (``u_mutants``).
"""

from __future__ import annotations

import itertools
import os
import random

import cocotb
from cocotb.clock import Clock
from cocotb.triggers import FallingEdge, RisingEdge
from cocotbext.axi import AxiStreamBus, AxiStreamFrame, AxiStreamSource

from ..spec.core import CoreInputs, CoreModel
from ..spec.rules import wrap
from ..spec.stepgen import StepCfg
from .timing import StepDirChecker

FIELDS = ("tready", "busy", "level", "move", "pos", "step_pins", "dir_pins",
          "err", "err_code", "underrun", "dry", "speed", "spindle_enable", "spindle_reverse",
          "spindle_pwm", "coolant_mist", "coolant_flood")


class Mismatch(AssertionError):
    pass


class CoreBench:
    def __init__(self, dut, axes: int, width: int, depth: int, tw: int,
                 cfg: list[StepCfg] | None = None, seed: int = 1, check: bool = True,
                 div: int = 12, move_depth: int = 4, profile_depth: int = 2,
                 pwm_bits: int = 10):
        self.dut = dut
        # the instance holding the core's internal signals (see the docstring)
        scope = os.environ.get("HP_CORE_SCOPE", "")
        self.inner = getattr(dut, scope) if scope else dut
        self.axes, self.width, self.depth, self.tw = axes, width, depth, tw
        self.cfg = cfg or [StepCfg() for _ in range(axes)]
        self.model = CoreModel(axes, width, depth, tw, div, move_depth, profile_depth,
                               self.cfg, pwm_bits)
        self.checkers = [StepDirChecker(c, f"axis {k}") for k, c in enumerate(self.cfg)]
        self.rng = random.Random(seed)
        self.check = check
        self.cycle = 0
        self.override = 128
        self.override_schedule: dict[int, int] = {}
        self.abort_schedule: set[int] = set()     # cycles with abort high
        self.hold_schedule: set[int] = set()      # cycles with hold high
        self.stop_schedule: set[int] = set()      # cycles with stop high
        self.speeds: list[int] = []               # the speed register, every cycle
        # the spindle/laser/coolant pins every cycle: (moves made before the cycle,
        # spindle_enable, spindle_reverse, coolant_mist, coolant_flood, spindle_pwm)
        self.output_pins: list[tuple] = []
        self.trace: list[tuple] = []       # positions after every move
        self.move_cycles: list[int] = []   # the cycle each move was seen in
        self.max_level = 0
        self.errors: list[tuple[int, int]] = []   # (cycle, code)
        self.moves = 0
        self.source = None
        self.history: list = []

    def _apply_cfg(self) -> None:
        d, tw = self.dut, self.tw

        def pack(vals):
            out = 0
            for k, v in enumerate(vals):
                out |= v << (k * tw)
            return out

        d.cfg_steplen.value = pack(c.steplen for c in self.cfg)
        d.cfg_stepspace.value = pack(c.stepspace for c in self.cfg)
        d.cfg_dirsetup.value = pack(c.dirsetup for c in self.cfg)
        d.cfg_dirhold.value = pack(c.dirhold for c in self.cfg)
        d.cfg_step_inv.value = sum(c.step_inv << k for k, c in enumerate(self.cfg))
        d.cfg_dir_inv.value = sum(c.dir_inv << k for k, c in enumerate(self.cfg))
        d.feed_override.value = self.override
        d.abort_now.value = 0
        d.hold.value = 0
        d.stop.value = 0

    def _read(self) -> dict:
        d = self.dut
        w = self.width
        raw = int(d.pos.value)
        pos = [wrap(raw >> (k * w), w) for k in range(self.axes)]
        return {
            "tready": int(d.s_axis_tready.value), "busy": int(d.busy.value),
            "level": int(d.queue_level.value), "move": int(d.move.value),
            "pos": tuple(pos), "step_pins": int(d.step_pin.value),
            "dir_pins": int(d.dir_pin.value), "err": int(d.err.value),
            "err_code": int(d.err_code.value), "underrun": int(d.underrun.value),
            "dry": int(d.dry.value), "speed": int(d.speed.value),
            "spindle_enable": int(d.spindle_enable.value),
            "spindle_reverse": int(d.spindle_reverse.value),
            "spindle_pwm": int(d.spindle_pwm.value),
            "coolant_mist": int(d.coolant_mist.value),
            "coolant_flood": int(d.coolant_flood.value),
        }

    async def start(self, pause_prob: float = 0.0) -> None:
        d = self.dut
        cocotb.start_soon(Clock(d.clk, 10, unit="ns").start())
        self._apply_cfg()
        d.rst.value = 1
        d.s_axis_tvalid.value = 0
        self.source = AxiStreamSource(AxiStreamBus.from_prefix(d, "s_axis"), d.clk, d.rst)
        if pause_prob:
            rng = random.Random(self.rng.random())
            self.source.set_pause_generator(
                int(rng.random() < pause_prob) for _ in itertools.count())
        for _ in range(3):
            await RisingEdge(d.clk)
        await FallingEdge(d.clk)
        d.rst.value = 0
        self.model.clock(CoreInputs(rst=1))
        cocotb.start_soon(self._monitor())

    async def _monitor(self) -> None:
        d = self.dut
        while True:
            got = self._read()
            if self.check:
                o = vars(self.model.outputs())
                bad = [k for k in FIELDS if got[k] != o[k]]
                if bad:
                    detail = ", ".join(f"{k}: rtl={got[k]} model={o[k]}" for k in bad)
                    hist = "\n".join(f"  cycle {c}: {g}" for c, g in self.history[-6:])
                    self.failure = Mismatch(f"cycle {self.cycle}: {detail}\nrecent RTL outputs:\n{hist}")
                    raise self.failure
                self._check_steps_ready()
            self.history = (self.history + [(self.cycle, got)])[-8:]
            for k, chk in enumerate(self.checkers):
                chk.sample((got["step_pins"] >> k) & 1, (got["dir_pins"] >> k) & 1)
            if got["move"]:
                self.trace.append(got["pos"])
                self.move_cycles.append(self.cycle)
                self.moves += 1
            if got["err"]:
                self.errors.append((self.cycle, got["err_code"]))
            self.max_level = max(self.max_level, got["level"])
            if self.cycle in self.override_schedule:
                self.override = self.override_schedule[self.cycle]
                d.feed_override.value = self.override
            self.speeds.append(got["speed"])
            self.output_pins.append((self.moves, got["spindle_enable"], got["spindle_reverse"],
                                     got["coolant_mist"], got["coolant_flood"],
                                     got["spindle_pwm"]))
            abort = int(self.cycle in self.abort_schedule)
            hold = int(self.cycle in self.hold_schedule)
            stop = int(self.cycle in self.stop_schedule)
            d.abort_now.value = abort
            d.hold.value = hold
            d.stop.value = stop
            inp = CoreInputs(
                tvalid=int(d.s_axis_tvalid.value),
                tdata=int(d.s_axis_tdata.value) if int(d.s_axis_tvalid.value) else 0,
                override=self.override,
                abort=abort, hold=hold, stop=stop,
            )
            self.model.clock(inp)
            self.cycle += 1
            self.last = got
            await FallingEdge(d.clk)

    def _check_steps_ready(self) -> None:
        """The core's registered readiness of the head move (computed a clock
        ahead from the generators' lookahead) equals the readiness of the head's
        axes as the generators report it now."""
        d = self.inner
        if not (d.head_step.value.is_resolvable and d.head_dir.value.is_resolvable):
            return      # a four-state simulator before the head was first loaded
        step, direction = int(d.head_step.value), int(d.head_dir.value)
        pos, neg = int(d.unused_ready_pos.value), int(d.unused_ready_neg.value)
        every = (1 << self.axes) - 1
        ready = int((~step | (direction & pos) | (~direction & neg)) & every == every)
        if int(d.steps_ready_q.value) != ready:
            self.failure = Mismatch(f"cycle {self.cycle}: steps_ready_q "
                                    f"{int(d.steps_ready_q.value)}, head axes ready {ready}")
            raise self.failure

    async def send(self, cmds) -> None:
        for c in cmds:
            await self.source.send(AxiStreamFrame(c.to_bytes(32, "little")))

    async def drain(self, max_cycles: int = 2_000_000) -> None:
        """Wait until everything sent has been executed and the pins are idle."""
        await self.source.wait()
        start = self.cycle
        idle = 0
        while idle < 8:
            await FallingEdge(self.dut.clk)
            if getattr(self, "failure", None):
                raise self.failure
            busy = self.last["busy"] or self.last["level"] or int(self.dut.s_axis_tvalid.value)
            idle = 0 if busy else idle + 1
            if self.cycle - start > max_cycles:
                raise AssertionError(f"core still busy after {max_cycles} cycles")
        await FallingEdge(self.dut.clk)
        if getattr(self, "failure", None):
            raise self.failure
