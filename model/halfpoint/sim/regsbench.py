# SPDX-License-Identifier: Apache-2.0
"""cocotb bench for the SoC register interface: ``halfpoint_wb`` driven by
cocotbext-wishbone's WishboneMaster or ``halfpoint_axil`` by cocotbext-axi's
AxiLiteMaster.

A monitor compares, on every clock, the register file ``u_regs`` (its
response, ``irq``, the STEP/DIR pins, and the core's positions, status and
speed) with :class:`halfpoint.spec.regs.RegsModel`, fed with the requests the
wrapper hands to the register file; it checks every answer the bus master gets
against the model's response, runs the independent STEP/DIR timing checker on
every axis and records the positions after every move.

Used inside a simulator only (it imports cocotb).
"""

from __future__ import annotations

import logging

import cocotb
from cocotb.clock import Clock
from cocotb.triggers import FallingEdge, RisingEdge

from ..spec import regmap as rm
from ..spec.regs import Request, RegsModel
from ..spec.rules import wrap
from ..spec.stepgen import StepCfg
from .design import read_parameters
from .timing import StepDirChecker

PARAMETERS = ("NA", "W", "DEPTH", "TW", "DIV", "MOVE_DEPTH", "PROFILE_DEPTH")


# the core's spindle, laser and coolant pins, passed through by both slaves
OUTPUT_PINS = ("spindle_enable", "spindle_reverse", "spindle_pwm", "coolant_mist",
               "coolant_flood")


def _known(handle) -> int:
    """A signal's value, 0 while it is not a resolvable 0/1 pattern (X or Z)."""
    try:
        return int(handle.value)
    except ValueError:
        return 0

class Mismatch(AssertionError):
    pass


def address(name: str, index: int = 0) -> int:
    return rm.BY_NAME[name].address(index)


class RegsBench:
    def __init__(self, dut, timeout_cycles: int = 2_000_000):
        self.dut = dut
        self.params = dict(zip(PARAMETERS, read_parameters(dut, *PARAMETERS)))
        self.axes, self.width = self.params["NA"], self.params["W"]
        self.depth = self.params["DEPTH"]
        self.model = RegsModel(*(self.params[p] for p in PARAMETERS))
        self.kind = "wb" if hasattr(dut, "wb_cyc") else "axil"
        self.regs = dut.u_regs
        self.cycle = 0
        self.timeout_cycles = timeout_cycles
        self.checkers: list[StepDirChecker] | None = None
        self.trace: list[tuple] = []           # positions after every move
        self.responses: list[tuple] = []       # (error, rdata) of every request answered
        self.errors: list[int] = []            # codes of the commands the core rejected
        self.failure: AssertionError | None = None
        self.last: dict = {}
        self.master = None

    # -- set-up ---------------------------------------------------------
    async def start(self) -> None:
        d = self.dut
        cocotb.start_soon(Clock(d.clk, 10, unit="ns").start())
        d.rst.value = 1
        if self.kind == "wb":
            # The Wishbone master's idle lines, driven here with ordinary (scheduled)
            # writes, and the master made only after time 0: its constructor writes
            # the same values with Immediate, and Icarus 11 does not take a value put
            # before its time-0 initialisation (the lines stay Z), and such a put
            # can leave a net downstream stuck at X for good (here wb_ack = wb_cyc
            # && resp_valid && !resp_error: the master then waits for an ACK
            # forever): iverilog issues #1041/#1111, fixed upstream in 2024 (PR
            # #1065), after the 12.0 release.
            for name in ("cyc", "stb", "we", "adr", "dat_w"):
                getattr(d, f"wb_{name}").value = 0
            d.wb_sel.value = 0xF
        else:
            from cocotbext.axi import AxiLiteBus, AxiLiteMaster

            self.master = AxiLiteMaster(AxiLiteBus.from_prefix(d, "s_axil"), d.clk, d.rst)
            self.master.write_if.log.setLevel(logging.WARNING)
            self.master.read_if.log.setLevel(logging.WARNING)
        for _ in range(3):
            await RisingEdge(d.clk)
        if self.kind == "wb":
            from cocotbext.wishbone.driver import WishboneMaster

            self.master = WishboneMaster(
                d, "wb", d.clk, width=32, timeout=1000,
                signals_dict={"cyc": "cyc", "stb": "stb", "we": "we", "adr": "adr",
                              "datwr": "dat_w", "datrd": "dat_r", "ack": "ack"})
        await FallingEdge(d.clk)
        d.rst.value = 0
        self.model.clock(Request(), rst=1)
        self.watch_pins()
        cocotb.start_soon(self._monitor())

    def watch_pins(self) -> None:
        """(Re)start the pin timing checkers with the settings now in the model."""
        self.checkers = [StepDirChecker(StepCfg(**vars(c)), f"axis {k}")
                         for k, c in enumerate(self.model.core.cfg)]

    # -- the monitor ----------------------------------------------------
    def _read(self) -> dict:
        r, w = self.regs, self.width
        raw = int(r.core_pos.value)
        return {
            "resp_valid": int(r.resp_valid.value), "resp_error": int(r.resp_error.value),
            "resp_rdata": int(r.resp_rdata.value), "irq": int(r.irq.value),
            "step_pins": int(r.step_pin.value), "dir_pins": int(r.dir_pin.value),
            "pos": tuple(wrap(raw >> (k * w), w) for k in range(self.axes)),
            "busy": int(r.core_busy.value), "level": int(r.core_level.value),
            "tready": int(r.core_ready.value), "err": int(r.core_err.value),
            "err_code": int(r.core_err_code.value), "speed": int(r.core_speed.value),
            "move": int(r.core_move.value),
            "outputs": tuple(int(getattr(self.dut, n).value) for n in OUTPUT_PINS),
        }

    def _expected(self) -> dict:
        o = self.model.outputs()
        c = o.core
        return {"resp_valid": o.resp_valid, "resp_error": o.resp_error,
                "resp_rdata": o.resp_rdata, "irq": o.irq, "step_pins": c.step_pins,
                "dir_pins": c.dir_pins, "pos": c.pos, "busy": c.busy, "level": c.level,
                "tready": c.tready, "err": c.err, "err_code": c.err_code, "speed": c.speed,
                "move": c.move, "outputs": tuple(getattr(c, n) for n in OUTPUT_PINS)}

    async def _monitor(self) -> None:
        r = self.regs
        while True:
            got = self._read()
            want = self._expected()
            bad = [k for k in want if got[k] != want[k]]
            if bad:
                detail = ", ".join(f"{k}: rtl={got[k]} model={want[k]}" for k in bad)
                self.failure = Mismatch(f"cycle {self.cycle}: {detail}")
                raise self.failure
            for k, chk in enumerate(self.checkers):
                chk.sample((got["step_pins"] >> k) & 1, (got["dir_pins"] >> k) & 1)
            if got["move"]:
                self.trace.append(got["pos"])
            if got["err"]:
                self.errors.append(got["err_code"])
            if got["resp_valid"]:
                self.responses.append((got["resp_error"], got["resp_rdata"]))
            # a bus master leaves its lines undriven (Z, X in a 4-state simulator such
            # as Icarus) between transfers: only a valid request's fields matter
            valid = _known(r.req_valid)
            req = Request(valid, *((_known(h) if valid else 0)
                                   for h in (r.req_write, r.req_addr, r.req_wdata,
                                             r.req_wstrb)))
            self.model.clock(req)
            self.cycle += 1
            self.last = got
            await FallingEdge(self.dut.clk)

    def _raise(self) -> None:
        if self.failure is not None:
            raise self.failure

    # -- bus access -----------------------------------------------------
    async def access(self, addr: int, data: int | None = None, sel: int = 0xF) -> tuple[bool, int]:
        """One read (``data`` None) or write on the bus; returns (ok, read data).
        The answer must be the one the model gave for this request."""
        before = len(self.responses)
        if self.kind == "wb":
            from cocotbext.wishbone.driver import WBOp

            (res,) = await self.master.send_cycle([WBOp(adr=addr >> 2, dat=data, sel=sel)])
            ok, value = res.ack == 1, int(res.datrd)
            if res.ack not in (1, 2):
                raise AssertionError(f"Wishbone answer {res.ack} (neither ACK nor ERR)")
        else:
            if data is None:
                res = await self.master.read(addr, 4)
                value = int.from_bytes(res.data, "little")
            else:
                lanes = [k for k in range(4) if sel >> k & 1]
                lo, hi = lanes[0], lanes[-1] + 1
                if lanes != list(range(lo, hi)):
                    raise ValueError("AXI4-Lite byte lanes of one write must be contiguous here")
                res = await self.master.write(addr + lo,
                                              data.to_bytes(4, "little")[lo:hi])
                value = 0
            ok = int(res.resp) == 0
        await FallingEdge(self.dut.clk)
        self._raise()
        new = self.responses[before:]
        assert len(new) == 1, f"{len(new)} register-file answers to one bus access"
        error, rdata = new[0]
        assert ok == (not error), f"bus says ok={ok}, the register file error={error}"
        if data is None and ok:
            assert value == rdata, f"bus read {value:#x}, the register file {rdata:#x}"
        return ok, value

    async def read(self, name: str, index: int = 0) -> int:
        ok, value = await self.access(address(name, index))
        assert ok, f"read of {name}_{index} answered an error"
        return value

    async def write(self, name: str, value: int, index: int = 0) -> None:
        ok, _ = await self.access(address(name, index), value)
        assert ok, f"write of {name}_{index} answered an error"

    async def field(self, name: str, field: str, index: int = 0) -> int:
        reg = rm.BY_NAME[name]
        f = next(f for f in reg.fields if f.name == field)
        return (await self.read(name, index) >> f.lsb) & ((1 << f.width) - 1)

    async def push(self, cmd: int) -> None:
        """Write one command's eight words (CMD_7 pushes)."""
        for k in range(8):
            await self.write("CMD", (cmd >> (32 * k)) & 0xFFFFFFFF, k)

    async def send(self, cmds, positions: list | None = None) -> None:
        """Push ``cmds``, waiting (reading QUEUE.FREE) while the queue is full, so
        none is refused; with ``positions``, read the snapshot of all axes before
        every push into it."""
        for cmd in cmds:
            while await self.field("QUEUE", "FREE") == 0:
                if positions is not None:
                    positions.append(await self.positions())
            if positions is not None:
                positions.append(await self.positions())
            await self.push(cmd)

    async def positions(self) -> tuple:
        """All axes, coherently: POS_0 snapshots, POS_1.. read the snapshot."""
        out = []
        for k in range(self.axes):
            out.append(wrap(await self.read("POS", k), 32))
        return tuple(out)

    async def wait_irq(self, max_cycles: int | None = None) -> None:
        start = self.cycle
        while not int(self.dut.irq.value):
            await FallingEdge(self.dut.clk)
            self._raise()
            if self.cycle - start > (max_cycles or self.timeout_cycles):
                raise AssertionError("no interrupt")

    async def wait_done(self) -> None:
        """Wait until the core has run everything pushed: clear DONE, and if
        STATUS still says busy, wait for the DONE interrupt (enabled here)."""
        done = 1 << rm.BY_NAME["IRQ_STATUS"].fields[2].lsb
        assert rm.BY_NAME["IRQ_STATUS"].fields[2].name == "DONE"
        enable = await self.read("IRQ_ENABLE")
        await self.write("IRQ_ENABLE", done)
        await self.write("IRQ_STATUS", done)
        if await self.read("STATUS") & 1:
            await self.wait_irq()
        await self.write("IRQ_ENABLE", enable)

    async def idle(self, cycles: int) -> None:
        for _ in range(cycles):
            await FallingEdge(self.dut.clk)
        self._raise()
