# SPDX-License-Identifier: Apache-2.0
"""The register file's model (spec.regs.RegsModel) against the rules of
spec/regmap.py, written out here: answers one clock after the request, errors
that change nothing, write-1-to-clear with events winning, the push and its
refusal, the coherent snapshot, the interrupt events and enables."""

from __future__ import annotations

from halfpoint.spec import encoding as enc
from halfpoint.spec import regmap as rm
from halfpoint.spec.program import profiled
from halfpoint.spec.regs import IRQ_BIT, RegsModel, Request

AXES = 3


def model(**kw) -> RegsModel:
    params = dict(axes=AXES, width=16, depth=2, tw=4, div=2, move_depth=2, profile_depth=1)
    params.update(kw)
    return RegsModel(**params)


def access(m: RegsModel, name: str, index: int = 0, data: int | None = None,
           strobe: int = 0xF, addr: int | None = None) -> tuple[int, int]:
    """One request, then one idle clock: (error, rdata) of the answer."""
    a = rm.BY_NAME[name].address(index) if addr is None else addr
    m.clock(Request(1, int(data is not None), a, data or 0, strobe))
    out = m.outputs()
    assert out.resp_valid == 1
    m.clock(Request())
    assert m.outputs().resp_valid == 0
    return out.resp_error, out.resp_rdata


def state(m: RegsModel) -> dict:
    return dict(m.values), list(m.snapshot)


def test_reset_values_and_unknown_addresses():
    m = model()
    known = rm.addresses(AXES)
    for a in range(0, 1 << rm.ADDR_BITS):
        error, value = access(m, "ID", addr=a)
        assert error == (a not in known), hex(a)
        if a in known:
            reg, _ = known[a]
            if reg.name not in ("STATUS", "QUEUE", "SPEED", "POS"):
                assert value == rm.reset_value(reg, m.params), reg.name
    assert access(m, "GEOMETRY")[1] == AXES | 16 << 8 | 4 << 16 | 2 << 24
    assert access(m, "STATUS")[1] == 0b10                # READY
    assert access(m, "QUEUE")[1] == 2 << 16              # FREE = DEPTH


def test_bad_writes_change_nothing():
    m = model()
    before = state(m)
    assert access(m, "ID", data=1) == (1, 0)                               # read-only
    assert access(m, "CONTROL", data=0, strobe=0x3) == (1, 0)              # partial
    assert access(m, "POS", 1, data=5) == (1, 0)
    assert access(m, "STEP_TIMING", addr=rm.BY_NAME["STEP_TIMING"].address(AXES),
                  data=7) == (1, 0)                                        # absent axis
    assert state(m) == before


def test_fields_are_cut_to_tw_and_na():
    m = model()
    assert access(m, "STEP_TIMING", 1, data=0xFFFF_FFFF) == (0, 0)
    assert access(m, "STEP_TIMING", 1)[1] == 0x000F_000F
    assert access(m, "POLARITY", data=0xFFFF_FFFF) == (0, 0)
    assert access(m, "POLARITY")[1] == 0x0707
    assert m.core.cfg[1].steplen == 15 and m.core.cfg[2].step_inv == 1


def test_write_one_to_clear_and_event_priority():
    m = model()
    access(m, "IRQ_THRESHOLD", data=1)             # level 0 < 1: QUEUE_LOW every clock
    low = 1 << IRQ_BIT["QUEUE_LOW"]
    assert access(m, "IRQ_STATUS")[1] == low
    access(m, "IRQ_STATUS", data=low)               # the event at the same edge wins
    assert access(m, "IRQ_STATUS")[1] == low
    access(m, "IRQ_THRESHOLD", data=0)
    access(m, "IRQ_STATUS", data=low)
    assert access(m, "IRQ_STATUS")[1] == 0
    assert m.outputs().irq == 0


def push(m: RegsModel, cmd: int) -> None:
    for k in range(enc.CMD_WORDS):
        access(m, "CMD", k, data=(cmd >> (32 * k)) & 0xFFFF_FFFF)


def test_push_refused_when_full_and_irq_enable():
    m = model()
    access(m, "CONTROL", data=1 | 128 << 8)         # hold: nothing drains far
    access(m, "IRQ_ENABLE", data=1 << IRQ_BIT["OVERFLOW"])
    bad = enc.pack([7, 0, 0, 0, 0, 0, 0, 0])        # rejected at the head, not before
    cmds = profiled([enc.encode_line([20, 0, 0])] * 6, AXES, 16, 2, v_cruise=1 << 30,
                    accel=1 << 30)
    pushed = 0
    while access(m, "STATUS")[1] & 0b10:
        push(m, cmds[pushed])
        pushed += 1
    level = access(m, "QUEUE")[1] & 0xFFFF
    assert level == 2 and m.outputs().irq == 0
    push(m, bad)
    assert m.outputs().irq == 1
    assert access(m, "QUEUE")[1] & 0xFFFF == level
    assert access(m, "CMD", 7)[1] == 0              # the words stay as written
    assert access(m, "CMD", 0)[1] == 7


def test_snapshot_is_taken_by_pos_0():
    m = model()
    m.core.pos = [5, -6, 7]
    assert access(m, "POS", 1)[1] == 0              # no snapshot yet
    assert access(m, "POS", 0)[1] == 5
    m.core.pos = [1, 2, 3]
    assert access(m, "POS", 1)[1] == (-6) & 0xFFFF_FFFF
    assert access(m, "POS", 2)[1] == 7
    assert access(m, "POS", 0)[1] == 1
    assert access(m, "POS", 2)[1] == 3


def test_holding_from_the_holds_second_clock():
    """STATUS.HOLDING reads 1 only from the hold's second clock: on its first the
    profile stage's target is still the one registered before the hold, and the speed
    may rise by a step (idle here, the speed is 0 throughout); then HOLDING = 1 means
    no step until HOLD is cleared."""
    m = model()
    holding = 1 << next(f.lsb for f in rm.BY_NAME["STATUS"].fields if f.name == "HOLDING")
    status = rm.BY_NAME["STATUS"].address(0)
    m.clock(Request(1, 1, rm.BY_NAME["CONTROL"].address(0), 1 | 128 << 8, 0xF))  # HOLD set
    m.clock(Request(1, 0, status, 0, 0xF))          # read on the hold's first clock
    first = m.outputs().resp_rdata
    m.clock(Request(1, 0, status, 0, 0xF))          # and on its second
    second = m.outputs().resp_rdata
    assert m.core.outputs().speed == 0
    assert not first & holding and second & holding
