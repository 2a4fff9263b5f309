# SPDX-License-Identifier: Apache-2.0
"""cocotb tests of the example board top, end to end: commands sent as bytes
on the serial line (cocotbext-uart), acknowledged one by one, executed by the
core; the STEP/DIR pins are checked for timing and counted, and the counted
positions must equal what the host expects from the commands.  The abort
button stops the motion and drops the queue; the reset button clears it all."""

import os
import random

import cocotb
from cocotb.clock import Clock
from cocotb.triggers import ClockCycles, RisingEdge, with_timeout
from cocotbext.uart import UartSink, UartSource

from halfpoint.spec import encoding as enc
from halfpoint.spec.rules import wrap
from halfpoint.spec.program import expect, profiled, random_arc, random_line
from halfpoint.spec.stepgen import StepCfg
from halfpoint.sim.design import read_parameters
from halfpoint.sim.timing import StepDirChecker

PARAMETERS = ("CLK_HZ", "BAUD", "NA", "W", "STEPLEN", "STEPSPACE", "DIRSETUP", "DIRHOLD",
              "DIV")
P: dict[str, int] = {}      # the design's parameters: bind() reads them
NA = W = CLK_NS = BIT_NS = 0
CFG = StepCfg()


def bind(dut) -> None:
    """Take the board top's parameters from the design under test."""
    global NA, W, CLK_NS, BIT_NS, CFG
    P.update(zip(PARAMETERS, read_parameters(dut, *PARAMETERS)))
    NA, W = P["NA"], P["W"]
    CLK_NS = 1_000_000_000 // P["CLK_HZ"]
    BIT_NS = CLK_NS * (P["CLK_HZ"] // P["BAUD"])
    CFG = StepCfg(P["STEPLEN"], P["STEPSPACE"], P["DIRSETUP"], P["DIRHOLD"])
ACK, LINE_ERR, CMD_ERR = 0x80, 0x40, 0x20


class Board:
    def __init__(self, dut):
        self.dut = dut
        self.host = UartSource(dut.uart_rx, baud=P["BAUD"])
        self.acks = UartSink(dut.uart_tx, baud=P["BAUD"])
        self.checkers = [StepDirChecker(CFG, f"axis {k}") for k in range(NA)]
        self.last_step_cycle = 0
        self.cycle = 0
        dut.uart_rx.value = 1
        dut.btn_reset.value = 1          # buttons idle high (BTN_ACTIVE_LOW = 1)
        dut.btn_abort.value = 1
        cocotb.start_soon(Clock(dut.clk, CLK_NS, unit="ns").start())
        cocotb.start_soon(self._pins())

    async def _pins(self):
        d = self.dut
        while True:
            await RisingEdge(d.clk)
            step, dr = int(d.step.value), int(d.dir.value)
            for k, chk in enumerate(self.checkers):
                chk.sample((step >> k) & 1, (dr >> k) & 1)
            if step:
                self.last_step_cycle = self.cycle
            self.cycle += 1

    def positions(self):
        return [wrap(c.position, W) for c in self.checkers]

    async def send(self, cmd: int) -> int:
        await self.host.write(cmd.to_bytes(32, "little"))
        ack = await with_timeout(self.acks.read(1), 100_000 * BIT_NS, "ns")
        assert ack[0] & ACK and not ack[0] & LINE_ERR, f"ack {ack[0]:#04x}"
        return ack[0]

    async def idle(self, quiet: int = 64, limit: int = 2_000_000):
        """Until busy is low and no STEP for `quiet` clocks."""
        start = self.cycle
        while True:
            await ClockCycles(self.dut.clk, 16)
            if not int(self.dut.led.value) & 1 and self.cycle - self.last_step_cycle > quiet:
                return
            assert self.cycle - start < limit, "motion did not finish"


def program(rng, n, speed=0.2):
    """``n`` random arcs and lines with planned profiles (the board's STEP timing
    allows a step every STEPLEN + STEPSPACE clocks per axis)."""
    cmds = []
    for k in range(n):
        if rng.random() < 0.5:
            cmds.append(random_arc(rng, rmax=20))
        else:
            cmds.append(random_line(rng, NA, scale=20))
    return profiled(cmds, NA, W, P["DIV"], v_cruise=int(speed * (1 << 32)), accel=1 << 32)


@cocotb.test()
async def program_over_serial(dut):
    bind(dut)
    rng = random.Random(int(os.environ.get("HP_SEED", "1")))
    b = Board(dut)
    await ClockCycles(dut.clk, 40)                 # power-on reset
    assert int(dut.enable_n.value) == 0, "drivers enabled after the power-on reset"
    cmds = program(rng, 10)
    # an arc whose end is off the circle, under an arc's profile: rejected
    cmds[6:6] = [enc.encode_profile(1 << 28, 0, 1 << 30), enc.encode_arc(0, -30, 0, 0, 33)]
    acks = [await b.send(c) for c in cmds]
    await b.idle()
    trace, final, errors = expect(cmds, NA, W)
    assert errors, "the bad arc must be rejected"
    assert b.positions() == list(final), f"pins counted {b.positions()}, host expects {final}"
    flagged = [a for a in acks if a & CMD_ERR]
    assert len(flagged) == 1 and (flagged[0] & 0x0F) == errors[0], [hex(a) for a in acks]
    assert int(dut.led.value) >> 1 & 1, "the reject LED is sticky"
    dut._log.info("%d commands, %d moves, final %s, %d clocks", len(cmds), len(trace), final, b.cycle)


@cocotb.test()
async def abort_and_reset_buttons(dut):
    bind(dut)
    rng = random.Random(2)
    b = Board(dut)
    await ClockCycles(dut.clk, 40)
    long_lines = profiled([enc.encode_line([400, -300, 100])] * 2, NA, W, P["DIV"],
                          v_cruise=(1 << 32) // 64, accel=1 << 32)
    for c in long_lines:
        await b.send(c)
    await ClockCycles(dut.clk, 2000)
    dut.btn_abort.value = 0                        # press
    await ClockCycles(dut.clk, 3 + P["STEPLEN"])
    assert int(dut.enable_n.value) == 1
    moved = b.positions()
    assert any(moved) and abs(moved[0]) < 400, moved
    await ClockCycles(dut.clk, 500)
    assert b.positions() == moved, "steps after abort"
    dut.btn_abort.value = 1                        # release
    await ClockCycles(dut.clk, 5)
    assert int(dut.enable_n.value) == 0
    assert not int(dut.led.value) & 1, "queue and segments dropped"
    # a new program continues from where the abort left the axes
    cmds = program(rng, 4)
    for c in cmds:
        await b.send(c)
    await b.idle()
    _, final, _ = expect(cmds, NA, W)
    assert b.positions() == [wrap(m + f, W) for m, f in zip(moved, final)]
    # reset button: everything cleared, the pins do not move
    dut.btn_reset.value = 0
    await ClockCycles(dut.clk, 5)
    assert int(dut.enable_n.value) == 1
    dut.btn_reset.value = 1
    await ClockCycles(dut.clk, 5)
    assert int(dut.enable_n.value) == 0 and int(dut.led.value) == 0
