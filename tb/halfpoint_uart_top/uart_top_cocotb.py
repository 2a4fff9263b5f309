# SPDX-License-Identifier: Apache-2.0
"""cocotb tests of the example board top, end to end: commands sent in COMMAND
frames of the serial link (model/halfpoint/spec/link.py) on the serial line
(cocotbext-uart), each RECEIVED and TAKEN, executed by the core; the STEP/DIR pins
are checked for timing and counted, and the counted positions must equal what the
host expects from the commands and what the STATUS reply says.  A rejected command
stops the machine on the path before it (nothing after it runs) and is reported
with its index and code until STOP; HOLD stops the pins, RESUME continues with no
step lost.  The abort button stops the motion and drops the queue; the reset
button clears it all."""

import os
import random

import cocotb
from cocotb.clock import Clock
from cocotb.triggers import ClockCycles, RisingEdge, with_timeout
from cocotbext.uart import UartSink, UartSource

from halfpoint.spec import encoding as enc
from halfpoint.spec import link
from halfpoint.spec.rules import wrap
from halfpoint.spec.program import expect, profiled, random_arc, random_line
from halfpoint.spec.stepgen import StepCfg
from halfpoint.sim.design import read_parameters
from halfpoint.sim.timing import StepDirChecker

PARAMETERS = ("CLK_HZ", "BAUD", "NA", "W", "DEPTH", "STEPLEN", "STEPSPACE", "DIRSETUP", "DIRHOLD",
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


class Board:
    def __init__(self, dut):
        self.dut = dut
        self.host = UartSource(dut.uart_rx, baud=P["BAUD"])
        self.acks = UartSink(dut.uart_tx, baud=P["BAUD"])
        self.checkers = [StepDirChecker(CFG, f"axis {k}") for k in range(NA)]
        self.last_step_cycle = 0
        self.cycle = 0
        self.reset_taken = False         # a clock edge has seen the reset (rst_q) high
        dut.uart_rx.value = 1
        dut.btn_reset.value = 1          # buttons idle high (BTN_ACTIVE_LOW = 1)
        dut.btn_abort.value = 1
        cocotb.start_soon(Clock(dut.clk, CLK_NS, unit="ns").start())
        cocotb.start_soon(self._pins())

    async def _pins(self):
        """Sample STEP/DIR at every rising edge (the values before the edge).  Before
        the first edge that takes the power-on reset, the step generators'
        flip-flops are not initialised: a 4-state simulator (Icarus) shows X there,
        Verilator 0.  Such samples are skipped; X or Z after the reset fails."""
        d = self.dut
        while True:
            await RisingEdge(d.clk)
            step, dr = d.step.value, d.dir.value
            resolved = step.is_resolvable and dr.is_resolvable
            if resolved:
                step, dr = int(step), int(dr)
                for k, chk in enumerate(self.checkers):
                    chk.sample((step >> k) & 1, (dr >> k) & 1)
                if step:
                    self.last_step_cycle = self.cycle
            elif self.reset_taken:
                raise AssertionError(f"cycle {self.cycle}: STEP/DIR unresolved after the "
                                     f"reset: step={step} dir={dr}")
            self.reset_taken = self.reset_taken or str(d.rst_q.value) == "1"
            self.cycle += 1

    def positions(self):
        return [wrap(c.position, W) for c in self.checkers]

    async def read(self, n: int, bits: int = 100_000) -> bytes:
        out = b""
        for _ in range(n):
            out += bytes(await with_timeout(self.acks.read(1), bits * BIT_NS, "ns"))
        return out

    async def send(self, cmd: int) -> bytes:
        """A COMMAND frame: RECEIVED, then TAKEN (or NAK STOPPED: returned)."""
        await self.host.write(link.command_frame(cmd))
        first = await self.read(1)
        if first[0] == link.R_NAK:
            return first + await self.read(1)
        assert first[0] == link.R_RECEIVED, first.hex()
        second = await self.read(1)
        if second[0] == link.R_NAK:
            return second + await self.read(1)
        assert second[0] == link.R_TAKEN, second.hex()
        return second

    async def control(self, opcode: int):
        await self.host.write(link.frame(opcode))
        assert await self.read(1) == bytes([link.R_RECEIVED])

    async def status(self) -> dict:
        await self.host.write(link.frame(link.F_STATUS))
        data = await self.read(link.status_payload(NA) + 2)
        assert data[0] == link.R_STATUS and link.crc8(data[:-1]) == data[-1], data.hex()
        return link.parse_status(data[1:-1], NA)

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
    await b.host.write(link.frame(link.F_IDENT))
    data = await b.read(link.IDENT_PAYLOAD + 2)
    assert link.parse_ident(data[1:-1]) == {
        "version": link.PROTOCOL_VERSION, "axes": NA, "width": W, "depth": P["DEPTH"],
        "clock_hz": P["CLK_HZ"], "baud": P["BAUD"], "div": P["DIV"]}
    cmds = program(rng, 10)
    replies = [await b.send(c) for c in cmds]
    assert all(r == bytes([link.R_TAKEN]) for r in replies)
    await b.idle()
    trace, final, errors = expect(cmds, NA, W)
    assert not errors
    assert b.positions() == list(final), f"pins counted {b.positions()}, host expects {final}"
    st = await b.status()
    assert list(st["position"]) == list(final) and st["taken"] == len(cmds), st
    assert st["flags"] == 0 and st["level"] == 0, st
    dut._log.info("%d commands, %d moves, final %s, %d clocks", len(cmds), len(trace), final,
                  b.cycle)


@cocotb.test()
async def reject_stops_the_job(dut):
    """A bad arc in the middle: the machine comes to rest on the path before it,
    nothing after it runs; STATUS names it (index, code); commands are refused until
    STOP; then a new program runs from there."""
    bind(dut)
    rng = random.Random(3)
    b = Board(dut)
    await ClockCycles(dut.clk, 40)
    st0 = await b.status()          # the board as the test before left it (no reset)
    good = program(rng, 6)
    bad = [enc.encode_profile(1 << 28, 0, 1 << 30), enc.encode_arc(0, -30, 0, 0, 33)]
    after = program(rng, 4)
    cmds = good + bad + after
    replies = [await b.send(c) for c in cmds]
    assert bytes([link.R_NAK, link.NAK_STOPPED]) in replies, replies
    await b.idle()
    st = await b.status()
    assert st["flags"] & link.FLAG_FAULT and st["reject_code"] == enc.E_ARC_END, st
    assert st["reject_index"] == st0["taken"] + len(good) + 1, st
    trace, _, _ = expect(good, NA, W)
    assert tuple(b.positions()) in {(0,) * NA, *trace}, "a move after the rejected command"
    assert [wrap(p - q, W) for p, q in zip(st["position"], st0["position"])] == b.positions()
    refused = await b.send(after[0])
    assert refused == bytes([link.R_NAK, link.NAK_STOPPED])
    await b.control(link.F_STOP)
    await ClockCycles(dut.clk, 20)
    assert (await b.status())["flags"] == 0
    here = b.positions()
    more = program(rng, 3)
    for c in more:
        assert await b.send(c) == bytes([link.R_TAKEN])
    await b.idle()
    _, final, _ = expect(more, NA, W)
    assert b.positions() == [wrap(h + f, W) for h, f in zip(here, final)]


@cocotb.test()
async def hold_and_resume(dut):
    """HOLD: the pins stop (after the deceleration) and stay; RESUME: the line
    completes with no step lost."""
    bind(dut)
    b = Board(dut)
    await ClockCycles(dut.clk, 40)
    line = profiled([enc.encode_line([300, -200, 100])], NA, W, P["DIV"],
                    v_cruise=(1 << 32) // 16, accel=1 << 30)
    for c in line:
        await b.send(c)
    await ClockCycles(dut.clk, 1500)
    await b.control(link.F_HOLD)
    await ClockCycles(dut.clk, 3000)
    held = b.positions()
    assert 0 < held[0] < 300, held
    await ClockCycles(dut.clk, 2000)
    assert b.positions() == held, "steps while held"
    assert (await b.status())["flags"] & link.FLAG_HOLD
    await b.control(link.F_RESUME)
    await b.idle()
    assert b.positions() == [300, -200, 100]


@cocotb.test()
async def abort_and_reset_buttons(dut):
    bind(dut)
    rng = random.Random(2)
    b = Board(dut)
    await ClockCycles(dut.clk, 40)
    long_lines = profiled([enc.encode_line([400, -300, 100])] * 2, NA, W, P["DIV"],
                          v_cruise=(1 << 32) // 64, accel=1 << 32)
    for c in long_lines:
        assert await b.send(c) == bytes([link.R_TAKEN])
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
        assert await b.send(c) == bytes([link.R_TAKEN])
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
