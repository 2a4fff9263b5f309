# SPDX-License-Identifier: Apache-2.0
"""cocotb test of halfpoint_refloop: the register follows its recurrence
(see the module header) on every clock, with random operand reloads and
resets."""

import os
import random

import cocotb
from cocotb.clock import Clock
from cocotb.triggers import FallingEdge, ReadOnly, RisingEdge

from halfpoint.sim.design import read_parameters

WR = 34
MASK = (1 << WR) - 1


def step(acc: int, a: int, b: int, fold: int) -> int:
    """One clock of the loop: add a when acc is negative, else b (FOLD=0) or -a (FOLD=1)."""
    neg = acc >> (WR - 1) & 1
    if fold == 0:
        return (acc + (a if neg else b)) & MASK
    return (acc + (a if neg else -a)) & MASK


@cocotb.test()
async def recurrence(dut):
    (fold,) = read_parameters(dut, "FOLD")
    rng = random.Random(int(os.environ.get("HP_SEED", "1")))
    cocotb.start_soon(Clock(dut.clk, 10, unit="ns").start())
    # inputs applied before the next edge
    rst, load, a, b = 1, 1, 12345, (-54321) & MASK
    acc = a_q = b_q = None
    signs = set()
    for cycle in range(4000):
        dut.rst.value, dut.load.value, dut.a.value, dut.b.value = rst, load, a, b
        await RisingEdge(dut.clk)
        # the model takes the same edge with the inputs just applied
        if rst:
            acc = 0
        elif acc is not None:
            acc = step(acc, a_q, b_q, fold)
        if load:
            a_q, b_q = a, b
        await ReadOnly()
        if acc is not None:
            assert int(dut.acc.value) == acc, f"cycle {cycle}: {int(dut.acc.value):#x} != {acc:#x}"
            signs.add(acc >> (WR - 1))
        await FallingEdge(dut.clk)
        rst = int(rng.random() < 0.005)
        load = int(rng.random() < 0.02)
        a = rng.randrange(1, 1 << 20)
        b = (-rng.randrange(1, 1 << 20)) & MASK
    assert signs == {0, 1}, "the loop never changed sign: the select was not exercised"
