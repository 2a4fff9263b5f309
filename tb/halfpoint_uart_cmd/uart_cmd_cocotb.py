# SPDX-License-Identifier: Apache-2.0
"""cocotb tests of halfpoint_uart_cmd: command words assembled from the serial
line byte for byte, one acknowledge per word with the documented flags,
random backpressure from the core, and every kind of line error (overrun,
idle timeout on a partial word, bad stop bit) flagged without corrupting the
words around it.  The host side is cocotbext-uart, running HP_SKEW percent
off the core's bit rate."""

import os
import random

import cocotb
from cocotb.clock import Clock
from cocotb.triggers import ClockCycles, RisingEdge, Timer, with_timeout
from cocotbext.uart import UartSink, UartSource

from halfpoint.sim.design import read_parameters

CLK_NS = 1000
ACK = 0x80
LINE_ERR = 0x40
CMD_ERR = 0x20


class Bench:
    def __init__(self, dut):
        self.dut = dut
        clk_hz, baud_param = read_parameters(dut, "CLK_HZ", "BAUD")
        cpb = clk_hz // baud_param                  # clocks per bit, as the design divides
        skew = float(os.environ.get("HP_SKEW", "0"))
        self.bit_ns = cpb * CLK_NS
        baud = 1e9 / self.bit_ns
        self.rng = random.Random(int(os.environ.get("HP_SEED", "1")))
        self.host = UartSource(dut.rx, baud=baud * (1 + skew / 100))
        self.acks = UartSink(dut.tx, baud=baud)
        self.words = []             # words taken by the "core"
        self.ready_p = 1.0          # probability of tready in a clock
        self.hold = False           # tready forced low
        dut.rx.value = 1
        dut.m_axis_tready.value = 0
        dut.cmd_err.value = 0
        dut.cmd_err_code.value = 0
        cocotb.start_soon(Clock(dut.clk, CLK_NS, unit="ns").start())
        cocotb.start_soon(self._core())

    async def reset(self):
        self.dut.rst.value = 1
        await ClockCycles(self.dut.clk, 3)
        self.dut.rst.value = 0
        await ClockCycles(self.dut.clk, 2)

    async def _core(self):
        """The motion core's side: random tready, words recorded when taken."""
        dut = self.dut
        while True:
            ready = int(not self.hold and self.rng.random() < self.ready_p)
            dut.m_axis_tready.value = ready
            await RisingEdge(dut.clk)
            if ready and dut.m_axis_tvalid.value == 1:     # X before reset (Icarus)
                self.words.append(int(dut.m_axis_tdata.value))

    async def send_word(self, data: bytes, expect_ack: int, whole: bytes | None = None):
        """Send bytes that complete a word (`whole`, default `data`), wait for the ack."""
        whole = data if whole is None else whole
        n = len(self.words)
        await self.host.write(data)
        ack = await with_timeout(self.acks.read(1), 500 * self.bit_ns, "ns")
        assert len(self.words) == n + 1, "acknowledge without a word"
        assert self.words[-1] == int.from_bytes(whole, "little"), \
            f"word {n}: {self.words[-1]:#066x} != {whole[::-1].hex()}"
        assert ack[0] == expect_ack, f"ack {ack[0]:#04x}, expected {expect_ack:#04x}"

    def word(self) -> bytes:
        return bytes(self.rng.getrandbits(8) for _ in range(32))

    async def raw_byte(self, b: int, stop: int = 1):
        """Drive a byte on rx by hand (to make a bad stop bit)."""
        for bit in [0] + [(b >> k) & 1 for k in range(8)] + [stop]:
            self.dut.rx.value = bit
            await Timer(self.bit_ns, "ns")
        self.dut.rx.value = 1


@cocotb.test()
async def words_and_acks(dut):
    """Random words with random backpressure arrive intact, each acknowledged."""
    b = Bench(dut)
    await b.reset()
    b.ready_p = 0.3
    for _ in range(12):
        await b.send_word(b.word(), ACK)
    # all-zero and all-one bytes: start/stop detection at the extremes
    await b.send_word(bytes(32), ACK)
    await b.send_word(bytes([0xFF] * 32), ACK)
    assert b.acks.empty()


@cocotb.test()
async def reject_reported(dut):
    """A reject pulse from the core is reported, with its code, in the next ack only."""
    b = Bench(dut)
    await b.reset()
    await b.send_word(b.word(), ACK)
    await RisingEdge(dut.clk)
    dut.cmd_err.value = 1
    dut.cmd_err_code.value = 3
    await RisingEdge(dut.clk)
    dut.cmd_err.value = 0
    dut.cmd_err_code.value = 0
    await b.send_word(b.word(), ACK | CMD_ERR | 3)
    await b.send_word(b.word(), ACK)


@cocotb.test()
async def partial_word_times_out(dut):
    """A host that stops mid-word: the partial word is discarded after the idle
    time and flagged; the next word is intact."""
    b = Bench(dut)
    await b.reset()
    await b.host.write(b.word()[:13])
    await b.host.wait()
    await Timer(20 * b.bit_ns, "ns")
    assert not b.words and b.acks.empty()
    await b.send_word(b.word(), ACK | LINE_ERR)
    await b.send_word(b.word(), ACK)


@cocotb.test()
async def overrun_dropped_and_flagged(dut):
    """Bytes sent while a word waits for the core are dropped and flagged; the
    waiting word is not touched."""
    b = Bench(dut)
    await b.reset()
    b.hold = True
    w = b.word()
    await b.host.write(w)
    await b.host.wait()
    await Timer(2 * b.bit_ns, "ns")
    await b.host.write(b"\x55\xaa")          # host did not wait for the ack
    await b.host.wait()
    await Timer(2 * b.bit_ns, "ns")
    assert not b.words
    b.hold = False
    ack = await with_timeout(b.acks.read(1), 100 * b.bit_ns, "ns")
    assert b.words == [int.from_bytes(w, "little")]
    assert ack[0] == ACK | LINE_ERR
    await b.send_word(b.word(), ACK)


@cocotb.test()
async def bad_stop_bit(dut):
    """A byte with a low stop bit is dropped and flagged; the word is completed
    by the following bytes (the host resends the lost byte)."""
    b = Bench(dut)
    await b.reset()
    w = b.word()
    await b.host.write(w[:5])
    await b.host.wait()
    await b.raw_byte(0x3C, stop=0)
    await Timer(2 * b.bit_ns, "ns")
    await b.send_word(w[5:], ACK | LINE_ERR, whole=w)
    await b.send_word(b.word(), ACK)
