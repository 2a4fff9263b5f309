# SPDX-License-Identifier: Apache-2.0
"""cocotb tests of the SoC register interface (halfpoint_wb with
cocotbext-wishbone, halfpoint_axil with cocotbext-axi): the register file and
the core equal to spec.regs.RegsModel on every clock (the bench's monitor),
every bus answer the model's, and end results checked independently: every
register, bus errors that change nothing, a whole program pushed through the
registers with positions read during the motion, the STEP/DIR pins timed and
counted, and the interrupts."""

from __future__ import annotations

import os
import random
import subprocess

import cocotb

from halfpoint.sim.env import BUILD, REPO
from halfpoint.sim.regsbench import RegsBench, address
from halfpoint.spec import encoding as enc
from halfpoint.spec import regmap as rm
from halfpoint.spec.program import expect, profiled, random_arc, random_line
from halfpoint.spec.regs import IRQ_BIT
from halfpoint.spec.rules import wrap

SEED = int(os.environ.get("HP_SEED", "1"))
ONE = 1 << 32               # a speed field of 1 BLU per clock
IRQ_ALL = sum(1 << b for b in IRQ_BIT.values())


def irq(name: str) -> int:
    return 1 << IRQ_BIT[name]


def plan(bench, rng, cmds, lo=0.2, hi=0.45):
    p = bench.params
    return profiled(cmds, p["NA"], p["W"], p["DIV"],
                    v_cruise=lambda k: int(rng.uniform(lo, hi) * ONE),
                    accel=lambda k: int(rng.uniform(0.3 / 40, 0.3 / 8) * (1 << 38)), rng=rng)


def program(bench, rng, count):
    axes = bench.axes
    cmds = []
    for _ in range(count):
        if rng.random() < 0.5:
            cmds.append(random_arc(rng, rmax=12))
        else:
            cmds.append(random_line(rng, axes, scale=12))
    return cmds


async def configure(bench, rng):
    """Random STEP/DIR timing and polarity through the registers; the pin
    checkers take the new settings (none runs while the polarity changes)."""
    bench.checkers = []
    tw = bench.params["TW"]
    top = min(3, (1 << tw) - 1)
    for k in range(bench.axes):
        await bench.write("STEP_TIMING", rng.randint(1, top) | rng.randint(0, top) << 16, k)
        await bench.write("DIR_TIMING", rng.randint(0, top) | rng.randint(0, top) << 16, k)
    await bench.write("POLARITY", rng.getrandbits(6) | rng.getrandbits(6) << 8)
    await bench.idle(2)
    bench.watch_pins()


async def read_all(bench) -> dict[int, tuple[bool, int]]:
    """Every word address of the window: (ok, value)."""
    out = {}
    for a in range(0, 1 << rm.ADDR_BITS, 4):
        out[a] = await bench.access(a)
    return out


def check_end(bench, cmds):
    trace, final, errors = expect(cmds, bench.axes, bench.width)
    assert bench.trace == trace, "positions after the moves differ from the host's expectation"
    assert bench.last["pos"] == final
    assert bench.errors == errors, (bench.errors, errors)
    for k, chk in enumerate(bench.checkers):
        assert wrap(chk.position, bench.width) == final[k], (
            f"axis {k}: the pins say {chk.position}, the program {final[k]}")
    return final


@cocotb.test()
async def every_register(dut):
    """Reset values of every address of the window, each writable register
    written and read back, and every kind of bad access answered by a bus error
    that changes nothing."""
    bench = RegsBench(dut)
    await bench.start()
    rng = random.Random(SEED)
    p = bench.params
    known = rm.addresses(bench.axes)
    first = await read_all(bench)
    for a, (ok, value) in first.items():
        assert ok == (a in known), f"address {a:#x}: ok={ok}"
    assert first[address("ID")][1] == rm.ID_VALUE
    assert first[address("VERSION")][1] == rm.VERSION_MAJOR << 16 | rm.VERSION_MINOR
    assert first[address("GEOMETRY")][1] == (p["NA"] | p["W"] << 8 | p["TW"] << 16
                                             | p["DIV"] << 24)
    assert first[address("QUEUES")][1] == (p["DEPTH"] | p["MOVE_DEPTH"] << 16
                                           | p["PROFILE_DEPTH"] << 24)
    assert first[address("CONTROL")][1] == 128 << 8
    assert first[address("QUEUE")][1] == p["DEPTH"] << 16
    assert first[address("STATUS")][1] == 1 << 1          # READY only
    for k in range(bench.axes):
        assert first[address("STEP_TIMING", k)][1] == 0x10001
    # write every writable register (not CMD_7: it pushes) and read it back
    tw_mask = (1 << p["TW"]) - 1
    axis_mask = (1 << bench.axes) - 1
    bench.checkers = []          # the polarity changes: no pin timing to check
    for a, (reg, k) in sorted(known.items()):
        if reg.access != rm.RW or (reg.name == "CMD" and k == 7) or reg.name == "CONTROL":
            continue
        value = rng.getrandbits(32)
        await bench.write(reg.name, value, k)
        back = await bench.read(reg.name, k)
        if reg.name in ("STEP_TIMING", "DIR_TIMING"):
            assert back == value & (tw_mask | tw_mask << 16)
        elif reg.name == "POLARITY":
            assert back == value & (axis_mask | axis_mask << 8)
        else:
            assert back == value & sum(f.mask for f in reg.fields), reg.name
    await bench.write("CONTROL", 77 << 8)
    assert await bench.read("CONTROL") == 77 << 8
    await bench.write("IRQ_THRESHOLD", 0)
    await bench.write("IRQ_STATUS", IRQ_ALL)
    before = await read_all(bench)
    # bad accesses: unknown addresses (read and write), read-only registers,
    # writes without all byte enables
    unknown = [a for a in range(0, 1 << rm.ADDR_BITS, 4) if a not in known]
    assert unknown
    for a in unknown:
        assert (await bench.access(a, rng.getrandbits(32)))[0] is False
    for a, (reg, k) in known.items():
        if reg.access == rm.RO:
            assert (await bench.access(a, rng.getrandbits(32)))[0] is False, reg.name
    for name, index in (("CONTROL", 0), ("IRQ_ENABLE", 0), ("CMD", 7), ("STEP_TIMING", 0),
                        ("IRQ_STATUS", 0)):
        # (cocotbext-axi writes at least one byte: no WSTRB of 0 on AXI4-Lite)
        for sel in (0x1, 0x3, 0xE) + ((0x0,) if bench.kind == "wb" else ()):
            ok, _ = await bench.access(address(name, index), 0xFFFFFFFF, sel)
            assert ok is False, (name, sel)
    after = await read_all(bench)
    assert after == before, "a bad access changed a register"
    assert bench.trace == [] and int(dut.irq.value) == 0
    if bench.kind == "axil":
        # writes and reads in flight together: taken one at a time, alternately
        m = bench.master
        writes = [cocotb.start_soon(m.write(address("IRQ_THRESHOLD"), k.to_bytes(4, "little")))
                  for k in range(1, 6)]
        reads = [cocotb.start_soon(m.read(address("ID"), 4)) for _ in range(5)]
        for task in writes:
            assert int((await task).resp) == 0
        for task in reads:
            result = await task
            assert int(result.resp) == 0
            assert int.from_bytes(result.data, "little") == rm.ID_VALUE
        assert await bench.read("IRQ_THRESHOLD") == 5


@cocotb.test()
async def program_through_registers(dut):
    """A whole profiled program of arcs and lines pushed through CMD_0..7 with
    flow control from QUEUE.FREE, coherent positions read during the motion,
    random STEP/DIR timing and polarity, a feed hold and an override change
    through CONTROL; DONE interrupt at the end; the pins timed and counted to
    the program's positions."""
    bench = RegsBench(dut)
    await bench.start()
    rng = random.Random(SEED + 1)
    await configure(bench, rng)
    cmds = plan(bench, rng, program(bench, rng, 24))
    snapshots = []
    half = len(cmds) // 2
    await bench.send(cmds[:half], positions=snapshots)
    # a feed hold through CONTROL in the motion: to rest (HOLDING), no move while
    # held, then released at a lower override
    await bench.write("CONTROL", 1 | 128 << 8)
    while not await bench.field("STATUS", "HOLDING"):
        snapshots.append(await bench.positions())
    assert await bench.field("STATUS", "BUSY") == 1, "the hold came after the motion"
    moved = len(bench.trace)
    await bench.idle(100)
    assert len(bench.trace) == moved, "moves while held"
    await bench.write("CONTROL", 90 << 8)
    await bench.send(cmds[half:], positions=snapshots)
    for _ in range(6):
        snapshots.append(await bench.positions())
    await bench.write("IRQ_STATUS", IRQ_ALL)
    await bench.write("IRQ_ENABLE", irq("DONE"))
    assert await bench.field("STATUS", "BUSY") == 1, "the program ended before the pushes"
    await bench.wait_irq()
    assert await bench.read("IRQ_STATUS") == irq("DONE")
    status = await bench.read("STATUS")
    assert status & 1 == 0 and (status >> 8) & 0xF == 0
    final = check_end(bench, cmds)
    # every snapshot is one moment of the motion: a position the program
    # passes through, all axes together
    visited = {tuple([0] * bench.axes)} | set(bench.trace)
    moving = [s for s in snapshots if s != snapshots[0]]
    assert moving, "no snapshot was taken during the motion"
    for s in snapshots:
        assert s in visited, f"snapshot {s} is not a position of the program"
    assert await bench.positions() == final
    await bench.write("IRQ_STATUS", irq("DONE"))
    assert int(dut.irq.value) == 0


@cocotb.test()
async def interrupts(dut):
    """QUEUE_LOW below the threshold (and set again after a clear while it
    holds), ERROR with the code in STATUS, OVERFLOW on a push into a full queue
    (the refused command never runs, nothing else is lost), the enables gate
    irq, DONE at the end; HOLD holds the motion (HOLDING) until released."""
    bench = RegsBench(dut)
    await bench.start()
    rng = random.Random(SEED + 2)
    depth = bench.depth
    # QUEUE_LOW: empty queue below a threshold of 1
    await bench.write("IRQ_THRESHOLD", 1)
    await bench.idle(2)
    assert await bench.read("IRQ_STATUS") == irq("QUEUE_LOW")
    assert int(dut.irq.value) == 0, "irq without an enable"
    await bench.write("IRQ_ENABLE", irq("QUEUE_LOW"))
    assert int(dut.irq.value) == 1
    await bench.write("IRQ_STATUS", irq("QUEUE_LOW"))
    assert await bench.read("IRQ_STATUS") == irq("QUEUE_LOW"), "cleared while the level holds"
    await bench.write("IRQ_THRESHOLD", 0)
    await bench.write("IRQ_STATUS", IRQ_ALL)
    assert await bench.read("IRQ_STATUS") == 0 and int(dut.irq.value) == 0
    # hold, then fill the queue: lines long enough that the queue stays full
    await bench.write("CONTROL", 1 | 128 << 8)
    await bench.write("IRQ_ENABLE", irq("OVERFLOW") | irq("ERROR"))
    lines = [random_line(rng, bench.axes, scale=30) for _ in range(depth + 8)]
    cmds = plan(bench, rng, lines)
    pushed = []
    while True:
        status = await bench.read("STATUS")
        if not status >> 1 & 1:            # READY low: the queue is full
            break
        await bench.push(cmds[len(pushed)])
        pushed.append(cmds[len(pushed)])
    assert await bench.field("QUEUE", "LEVEL") == depth
    assert await bench.field("QUEUE", "FREE") == 0
    assert await bench.field("STATUS", "HOLDING") == 1
    assert int(dut.irq.value) == 0
    await bench.write("IRQ_STATUS", IRQ_ALL)
    refused = enc.encode_line([5] + [0] * (bench.axes - 1))
    await bench.push(refused)
    assert int(dut.irq.value) == 1
    assert await bench.read("IRQ_STATUS") == irq("OVERFLOW")
    assert await bench.field("QUEUE", "LEVEL") == depth, "the refused push entered the queue"
    await bench.write("IRQ_STATUS", irq("OVERFLOW"))
    assert int(dut.irq.value) == 0
    moved = len(bench.trace)
    await bench.idle(200)
    assert len(bench.trace) == moved, "moves while held"
    # release; the rest of the program, then a bad command: ERROR, code in STATUS
    await bench.write("CONTROL", 128 << 8)
    rest = [c for c in cmds[len(pushed):]]
    bad = plan(bench, rng, [enc.encode_arc(1, 0, 0, 5, 5)])      # radius zero
    await bench.send(rest + bad)
    await bench.wait_irq()
    assert await bench.read("IRQ_STATUS") == irq("ERROR")
    assert await bench.field("STATUS", "ERR_CODE") == enc.E_ARC_RADIUS
    await bench.wait_done()
    check_end(bench, pushed + rest + bad)


@cocotb.test()
async def stop_abort_override(dut):
    """CONTROL during the motion: override changes, a controlled stop (pushes
    refused while it is set, the queue dropped at rest), then abort, each
    followed by a new program that runs from where the motion stopped."""
    bench = RegsBench(dut)
    await bench.start()
    rng = random.Random(SEED + 3)
    cmds = plan(bench, rng, program(bench, rng, 6), lo=0.05, hi=0.1)
    await bench.send(cmds)
    await bench.write("CONTROL", 40 << 8)               # override 40/128
    await bench.idle(300)
    await bench.write("CONTROL", 200 << 8)              # above 128 acts as 128
    await bench.idle(100)
    await bench.write("CONTROL", 2 | 128 << 8)          # stop
    while await bench.field("QUEUE", "LEVEL") or await bench.field("STATUS", "BUSY"):
        pass
    assert await bench.field("STATUS", "READY") == 0
    planned = len(expect(cmds, bench.axes, bench.width)[0])
    assert 0 < len(bench.trace) < planned, "the stop did not cut the program"
    stopped = len(bench.trace)
    await bench.write("IRQ_ENABLE", irq("OVERFLOW"))
    await bench.push(enc.encode_line([1] * bench.axes))
    assert int(dut.irq.value) == 1, "a push during stop was not refused"
    await bench.write("CONTROL", 128 << 8)
    await bench.write("IRQ_STATUS", IRQ_ALL)
    more = plan(bench, rng, program(bench, rng, 4), lo=0.05, hi=0.1)
    await bench.send(more)
    await bench.idle(150)
    await bench.write("CONTROL", 4 | 128 << 8)          # abort
    await bench.idle(20)
    assert await bench.field("STATUS", "BUSY") == 0
    assert await bench.field("QUEUE", "LEVEL") == 0
    second = len(bench.trace) - stopped
    assert second > 0, "nothing of the second program moved before the abort"
    assert second < len(expect(more, bench.axes, bench.width)[0]), (
        "the abort did not cut the second program")
    await bench.write("CONTROL", 128 << 8)
    last = plan(bench, rng, [enc.encode_line([3] + [-2] * (bench.axes - 1))])
    here = bench.last["pos"]
    await bench.send(last)
    await bench.wait_done()
    want = tuple(wrap(h + d, bench.width)
                 for h, d in zip(here, [3] + [-2] * (bench.axes - 1)))
    assert bench.last["pos"] == want
    for k, chk in enumerate(bench.checkers):
        assert wrap(chk.position, bench.width) == want[k]


@cocotb.test()
async def c_driver(dut):
    """examples/soc/drive.c, built with the system's gcc (-Wall -Wextra -Werror)
    against the generated header, drives the RTL: its register accesses come
    over a pipe and go out on the bus.  It probes the core, sets the timing,
    pushes a planned program with flow control, reads positions while moving,
    waits for the end; the pins and positions are those of the program."""
    bench = RegsBench(dut)
    await bench.start()
    rng = random.Random(SEED + 4)
    cmds = plan(bench, rng, program(bench, rng, 10))
    work = BUILD / "soc" / bench.kind
    work.mkdir(parents=True, exist_ok=True)
    exe = work / "drive"
    subprocess.run(["gcc", "-Wall", "-Wextra", "-Werror", "-std=c99", "-pedantic",
                    "-DHALFPOINT_PIPE", f"-I{REPO / 'include'}", "-o", str(exe),
                    str(REPO / "examples" / "soc" / "drive.c")], check=True)
    hexfile = work / "program.hex"
    hexfile.write_text("".join(" ".join(f"{w:08x}" for w in enc.unpack(c)) + "\n"
                               for c in cmds))
    proc = subprocess.Popen([str(exe), str(hexfile)], stdin=subprocess.PIPE,
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    cmd_lo, cmd_hi = address("CMD", 0), address("CMD", 7)
    watching = False
    try:
        while True:
            line = proc.stdout.readline().split()
            assert line, "drive.c ended without Q"
            if line[0] == "Q":
                break
            offset = int(line[1], 16)
            if line[0] == "W" and cmd_lo <= offset <= cmd_hi and not watching:
                bench.watch_pins()        # the timing drive.c set, before its first push
                watching = True
            data = int(line[2], 16) if line[0] == "W" else None
            ok, value = await bench.access(offset, data)
            proc.stdin.write(f"{int(ok)} {value:x}\n")
            proc.stdin.flush()
        out, err = proc.communicate(timeout=10)
    finally:
        if proc.poll() is None:
            proc.kill()
    assert proc.returncode == 0, err
    final = check_end(bench, cmds)
    lines = err.splitlines()
    assert f"final {' '.join(str(p) for p in final)}" in lines, err
    assert "error code 0" in lines, err
    assert any(line.startswith("moving") for line in lines), err
    assert [c.steplen for c in bench.model.core.cfg] == [2] * bench.axes
