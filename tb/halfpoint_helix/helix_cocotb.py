# SPDX-License-Identifier: Apache-2.0
"""cocotb test of halfpoint_helix against ``spec.helix.HelixMapper`` on every clock:
random arcs in every plane (any pair of the NA axes), both helix slots, counts right
and wrong, loads at the edge of the previous arc's last move, flushes; step, dir (of
the axes stepped) and count_error compared before every edge.

Run by ``test_helix_rtl.py``; NA and W are read from the design."""

from __future__ import annotations

import os
import random

import cocotb
from cocotb.clock import Clock
from cocotb.triggers import FallingEdge, RisingEdge, Timer

from halfpoint.sim.design import read_parameters
from halfpoint.spec import encoding as enc
from halfpoint.spec.helix import HelixCommand, HelixMapper

SEED = int(os.environ.get("HP_SEED", "1"))


def _random_command(rng, axes, width):
    u, v = rng.sample(range(axes), 2)
    count = rng.choice((0, 1, 2, rng.randint(3, 40)))
    slots = len(enc.helix_axes(u, v, axes))
    top = min(count, (1 << (width - 1)) - 1)
    deltas = [rng.randint(-top, top) if rng.random() < 0.8 else 0 for _ in range(slots)]
    return HelixCommand(u, v, count, tuple(deltas + [0] * (enc.HELIX_SLOTS - slots)))


@cocotb.test()
async def random_arcs(dut):
    axes, width = read_parameters(dut, "NA", "W")
    rng = random.Random(SEED)
    cocotb.start_soon(Clock(dut.clk, 10, unit="ns").start())
    model = HelixMapper(axes)
    dut.rst.value = 1
    for sig in (dut.flush, dut.take, dut.load, dut.move, dut.last):
        sig.value = 0
    dut.arc_step.value = 0
    dut.arc_dir.value = 0
    await RisingEdge(dut.clk)
    dut.rst.value = 0
    pending = None              # the command in the pending slot (not yet loaded)
    left = 0                    # moves the running arc still makes
    checked = 0
    for cycle in range(6000):
        await FallingEdge(dut.clk)
        take = None
        if pending is None and rng.random() < 0.3:
            take = pending_new = _random_command(rng, axes, width)
        move = left > 0 and rng.random() < 0.8
        last = move and left == 1
        load = pending is not None and (left == 0 or last) and rng.random() < 0.7
        flush = rng.random() < 0.003
        du, dv = rng.choice(((1, 0), (0, -1), (1, 1), (-1, 1)))
        dut.take.value = int(take is not None)
        if take is not None:
            mag = [abs(d) for d in take.deltas]
            dut.take_u.value = take.u
            dut.take_v.value = take.v
            dut.take_count.value = take.count
            dut.take_magnitude0.value = mag[0]
            dut.take_magnitude1.value = mag[1]
            dut.take_negative.value = sum(int(d < 0) << k for k, d in enumerate(take.deltas))
        dut.load.value = int(load)
        dut.move.value = int(move)
        dut.last.value = int(last)
        dut.flush.value = int(flush)
        dut.arc_step.value = int(du != 0) | (int(dv != 0) << 1)
        dut.arc_dir.value = int(du > 0) | (int(dv > 0) << 1)
        await Timer(1, unit="ns")
        # compare the combinational outputs before the edge
        want = model.steps(du, dv)
        step = int(dut.step.value)
        direction = int(dut.dir.value)
        for axis, s in enumerate(want):
            assert (step >> axis) & 1 == int(s != 0), f"cycle {cycle} axis {axis} step"
            if s:
                assert (direction >> axis) & 1 == int(s > 0), f"cycle {cycle} axis {axis} dir"
        assert int(dut.count_error.value) == int(move and model.count_error(last)), cycle
        checked += 1
        model.clock(take, load, move, abort=flush)
        if flush:
            pending, left = None, 0
            continue
        if move:
            left -= 1
        if load:
            # the arc's own move count: its count, or one off now and then
            left = max(1, pending.count + rng.choice((0, 0, 0, 0, -1, 1)))
            pending = None
        if take is not None:
            pending = pending_new
    assert checked == 6000
