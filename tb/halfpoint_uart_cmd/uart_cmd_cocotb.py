# SPDX-License-Identifier: Apache-2.0
"""cocotb tests of halfpoint_uart_cmd, the serial link (model/halfpoint/spec/link.py):
COMMAND frames assembled byte for byte into the core's words, RECEIVED then TAKEN for
each under random backpressure; STATUS and IDENT replies with their values and
checks; every line error (bad check, bad stop bit, an unfinished frame, an unknown
opcode) refused with its NAK and no effect; a COMMAND while one waits refused (BUSY);
HOLD, RESUME and STOP driving the core's hold and stop; a rejected command latching
FAULT with its index and code, stopping the core and refusing commands until STOP.
The host side is cocotbext-uart, running HP_SKEW percent off the port's bit rate."""

import os
import random

import cocotb
from cocotb.clock import Clock
from cocotb.triggers import ClockCycles, RisingEdge, Timer, with_timeout
from cocotbext.uart import UartSink, UartSource

from halfpoint.sim.design import read_parameters
from halfpoint.spec import link

CLK_NS = 1000


class Bench:
    def __init__(self, dut):
        self.dut = dut
        (clk_hz, baud_param, self.na, self.w, self.depth, self.div,
         self.idle_bits) = read_parameters(dut, "CLK_HZ", "BAUD", "NA", "W", "DEPTH", "DIV",
                                           "IDLE_BITS")
        self.clk_hz, self.baud = clk_hz, baud_param
        cpb = clk_hz // baud_param                  # clocks per bit, as the design divides
        skew = float(os.environ.get("HP_SKEW", "0"))
        self.bit_ns = cpb * CLK_NS
        baud = 1e9 / self.bit_ns
        self.rng = random.Random(int(os.environ.get("HP_SEED", "1")))
        self.host = UartSource(dut.rx, baud=baud * (1 + skew / 100))
        self.replies = UartSink(dut.tx, baud=baud)
        self.words = []             # words taken by the "core"
        self.ready_p = 1.0          # probability of tready in a clock
        self.hold = False           # tready forced low
        dut.rx.value = 1
        dut.m_axis_tready.value = 0
        dut.cmd_err.value = 0
        dut.cmd_err_code.value = 0
        dut.core_pos.value = 0
        dut.core_level.value = 0
        dut.core_busy.value = 0
        dut.core_underrun.value = 0
        dut.core_dry.value = 0
        dut.core_abort.value = 0
        cocotb.start_soon(Clock(dut.clk, CLK_NS, unit="ns").start())
        cocotb.start_soon(self._core())

    async def reset(self):
        self.dut.rst.value = 1
        await ClockCycles(self.dut.clk, 3)
        self.dut.rst.value = 0
        await ClockCycles(self.dut.clk, 2)

    async def _core(self):
        """The motion core's side: random tready, words recorded when taken.  While
        no word is offered it sleeps until one is (no coroutine call per clock)."""
        dut = self.dut
        while True:
            if dut.m_axis_tvalid.value != 1:        # 0, or X before reset (Icarus)
                dut.m_axis_tready.value = 0
                await RisingEdge(dut.m_axis_tvalid)
            ready = int(not self.hold and self.rng.random() < self.ready_p)
            dut.m_axis_tready.value = ready
            await RisingEdge(dut.clk)
            if ready and dut.m_axis_tvalid.value == 1:     # X before reset (Icarus)
                self.words.append(int(dut.m_axis_tdata.value))

    async def read(self, n: int, bits: int = 2000) -> bytes:
        """``n`` reply bytes, each within ``bits`` bit times."""
        out = b""
        for _ in range(n):
            out += bytes(await with_timeout(self.replies.read(1), bits * self.bit_ns, "ns"))
        return out

    async def quiet(self, bits: int = 30):
        """No reply for ``bits`` bit times."""
        await Timer(bits * self.bit_ns, "ns")
        assert self.replies.empty(), f"unexpected reply {bytes(self.replies.read_nowait()).hex()}"

    async def command(self, word: bytes):
        """A COMMAND frame: RECEIVED, then TAKEN with the word intact."""
        n = len(self.words)
        await self.host.write(link.frame(link.F_COMMAND, word))
        assert await self.read(1) == bytes([link.R_RECEIVED])
        assert await self.read(1, 20000) == bytes([link.R_TAKEN])
        assert len(self.words) == n + 1, "TAKEN without a word"
        assert self.words[-1] == int.from_bytes(word, "little"), f"word {n} corrupted"

    async def control(self, opcode: int):
        await self.host.write(link.frame(opcode))
        assert await self.read(1) == bytes([link.R_RECEIVED])

    async def status(self) -> dict:
        await self.host.write(link.frame(link.F_STATUS))
        n = link.status_payload(self.na)
        data = await self.read(n + 2)
        assert data[0] == link.R_STATUS and link.crc8(data[:-1]) == data[-1], data.hex()
        return link.parse_status(data[1:-1], self.na)

    async def nak(self, bits: int = 2000) -> int:
        data = await self.read(2, bits)
        assert data[0] == link.R_NAK, data.hex()
        return data[1]

    def word(self) -> bytes:
        return bytes(self.rng.getrandbits(8) for _ in range(32))

    async def raw_byte(self, b: int, stop: int = 1):
        """Drive a byte on rx by hand (to make a bad stop bit)."""
        for bit in [0] + [(b >> k) & 1 for k in range(8)] + [stop]:
            self.dut.rx.value = bit
            await Timer(self.bit_ns, "ns")
        self.dut.rx.value = 1


@cocotb.test()
async def commands_and_replies(dut):
    """Random words under random backpressure arrive intact: RECEIVED, then TAKEN."""
    b = Bench(dut)
    await b.reset()
    b.ready_p = 0.3
    words = 10
    for _ in range(words):
        await b.command(b.word())
    # all-zero and all-one bytes: start/stop detection at the extremes
    await b.command(bytes(32))
    await b.command(bytes([0xFF] * 32))
    await b.quiet()
    st = await b.status()
    assert st["taken"] == words + 2 and st["flags"] == 0, st


@cocotb.test()
async def status_and_ident(dut):
    """STATUS: positions sign-extended, level, flags, count; IDENT: the build."""
    b = Bench(dut)
    await b.reset()
    pos = [b.rng.randrange(-(1 << (b.w - 1)), 1 << (b.w - 1)) for _ in range(b.na)]
    dut.core_pos.value = sum((p & ((1 << b.w) - 1)) << (b.w * k) for k, p in enumerate(pos))
    dut.core_level.value = 3
    dut.core_busy.value = 1
    dut.core_dry.value = 1
    st = await b.status()
    assert st["position"] == tuple(pos), (st, pos)
    assert st["level"] == 3 and st["flags"] == link.FLAG_BUSY | link.FLAG_DRY, st
    await b.host.write(link.frame(link.F_IDENT))
    data = await b.read(link.IDENT_PAYLOAD + 2)
    assert data[0] == link.R_IDENT and link.crc8(data[:-1]) == data[-1]
    assert link.parse_ident(data[1:-1]) == {
        "version": link.PROTOCOL_VERSION, "axes": b.na, "width": b.w, "depth": b.depth,
        "clock_hz": b.clk_hz, "baud": b.baud, "div": b.div}


@cocotb.test()
async def line_errors(dut):
    """Each line error: its NAK, no word, no effect; the next frame works."""
    b = Bench(dut)
    await b.reset()
    w = b.word()
    bad = bytearray(link.frame(link.F_COMMAND, w))
    bad[-1] ^= 0x01
    await b.host.write(bytes(bad))                          # bad check
    assert await b.nak() == link.NAK_CHECK
    await b.host.write(link.frame(link.F_COMMAND, w)[:13])  # unfinished
    assert await b.nak() == link.NAK_INCOMPLETE
    await b.host.write(bytes([0x55, 0x00]))                 # unknown opcode
    assert await b.nak() == link.NAK_OPCODE
    await b.host.write(link.frame(link.F_COMMAND, w)[:5])   # a bad stop bit mid-frame
    await b.host.wait()
    await b.raw_byte(0x3C, stop=0)
    await b.host.write(link.frame(link.F_COMMAND, w)[6:])
    assert await b.nak() == link.NAK_FRAMING
    bad = bytearray(link.frame(link.F_HOLD))
    bad[-1] ^= 0x80
    await b.host.write(bytes(bad))                          # a control with a bad check
    assert await b.nak() == link.NAK_CHECK
    assert not b.words and not int(dut.core_hold.value)
    await b.command(w)
    await b.quiet()


@cocotb.test()
async def busy_waiting_word(dut):
    """While a word waits: STATUS answered (WAITING), a second COMMAND refused (BUSY)."""
    b = Bench(dut)
    await b.reset()
    b.hold = True
    w = b.word()
    await b.host.write(link.frame(link.F_COMMAND, w))
    assert await b.read(1) == bytes([link.R_RECEIVED])
    st = await b.status()
    assert st["flags"] & link.FLAG_WAITING, st
    await b.host.write(link.frame(link.F_COMMAND, b.word()))
    assert await b.nak() == link.NAK_BUSY
    assert not b.words
    b.hold = False
    assert await b.read(1) == bytes([link.R_TAKEN])
    assert b.words == [int.from_bytes(w, "little")]


@cocotb.test()
async def hold_resume_stop(dut):
    """HOLD and RESUME drive core_hold; STOP drops a waiting word (NAK STOPPED),
    releases the hold and drives core_stop until the core is at rest and empty."""
    b = Bench(dut)
    await b.reset()
    await b.control(link.F_HOLD)
    assert int(dut.core_hold.value) and (await b.status())["flags"] == link.FLAG_HOLD
    await b.control(link.F_RESUME)
    assert not int(dut.core_hold.value)
    await b.control(link.F_HOLD)
    b.hold = True
    dut.core_busy.value = 1
    dut.core_level.value = 2
    await b.host.write(link.frame(link.F_COMMAND, b.word()))
    assert await b.read(1) == bytes([link.R_RECEIVED])
    await b.host.write(link.frame(link.F_STOP))
    assert await b.read(1) == bytes([link.R_RECEIVED])
    assert await b.nak() == link.NAK_STOPPED                # the waiting word
    assert int(dut.core_stop.value) and not int(dut.core_hold.value)
    assert (await b.status())["flags"] == link.FLAG_STOPPING | link.FLAG_BUSY
    await b.host.write(link.frame(link.F_COMMAND, b.word()))
    assert await b.nak() == link.NAK_STOPPED                # refused while stopping
    dut.core_busy.value = 0
    dut.core_level.value = 0
    await ClockCycles(dut.clk, 2)
    assert not int(dut.core_stop.value)
    b.hold = False
    assert not b.words
    await b.command(b.word())


@cocotb.test()
async def reject_stops(dut):
    """A reject latches FAULT (index = taken - level - 1, the code), stops the core,
    drops the waiting word and refuses commands; STOP clears it."""
    b = Bench(dut)
    await b.reset()
    for _ in range(4):
        await b.command(b.word())
    b.hold = True
    await b.host.write(link.frame(link.F_COMMAND, b.word()))
    assert await b.read(1) == bytes([link.R_RECEIVED])
    dut.core_level.value = 2                    # two taken commands still queued
    dut.core_busy.value = 1
    await RisingEdge(dut.clk)
    dut.cmd_err.value = 1
    dut.cmd_err_code.value = 5
    await RisingEdge(dut.clk)
    dut.cmd_err.value = 0
    dut.cmd_err_code.value = 0
    assert await b.nak() == link.NAK_STOPPED
    assert int(dut.core_stop.value)
    st = await b.status()
    assert st["flags"] == link.FLAG_FAULT | link.FLAG_STOPPING | link.FLAG_BUSY, st
    assert st["reject_index"] == 4 - 2 - 1 and st["reject_code"] == 5, st
    dut.core_busy.value = 0
    dut.core_level.value = 0
    await ClockCycles(dut.clk, 2)
    assert not int(dut.core_stop.value)
    await b.host.write(link.frame(link.F_COMMAND, b.word()))
    assert await b.nak() == link.NAK_STOPPED                # FAULT refuses commands
    assert (await b.status())["flags"] == link.FLAG_FAULT
    await b.control(link.F_STOP)
    await ClockCycles(dut.clk, 3)
    assert (await b.status())["flags"] == 0
    b.hold = False
    await b.command(b.word())
    assert len(b.words) == 5
