# SPDX-License-Identifier: Apache-2.0
"""Cycle-accurate model of the register file ``rtl/halfpoint_regs.v``: the
registers of ``spec.regmap`` around a ``spec.core.CoreModel``.

The register file has one access port, which the bus wrappers (Wishbone
``halfpoint_wb``, AXI4-Lite ``halfpoint_axil``) drive: a request (``valid``,
``write``, byte ``addr``, ``wdata``, ``wstrb``) is taken on the edge it is
valid at and answered on the next clock (``resp_valid`` for one clock, with
``resp_error`` and ``resp_rdata``), whatever the request.

On the edge of a request:

* an address not in the map (for this core's NA), a write to a read-only
  register, or a write whose byte enables are not all set: error response, no
  register changes (and ``resp_rdata`` is 0);
* a read answers the register's value before the edge; reading POS_0 copies
  every axis's position into the snapshot that POS_1.. read;
* a write sets the register (the fields only; the bits of absent axes and the
  bits beyond TW are dropped); writing IRQ_STATUS clears the bits written 1;
  writing CMD_7 also offers the command {wdata, CMD_6 .. CMD_0} to the core's
  stream on that same edge: taken if the core is ready, else refused (OVERFLOW).

The core's inputs are the registers: CONTROL (hold, stop, abort, override),
POLARITY and the timing settings act from the clock after the write (the
STEP/DIR pins are registers of the step generators, made with the polarity
of the clock before: a POLARITY write reaches the pins one clock later).

Interrupt events, at every edge: QUEUE_LOW while the queue level (before the
edge) is below IRQ_THRESHOLD; ERROR when the core's ``err`` is high; DONE when
``busy`` was high on the clock before and is low now; OVERFLOW on a refused
push.  An event sets its IRQ_STATUS bit (an event wins over a clear at the
same edge); ``irq`` = any IRQ_STATUS bit whose IRQ_ENABLE bit is set.
"""

from __future__ import annotations

from dataclasses import dataclass

from . import encoding as enc
from . import regmap as rm
from .core import CoreInputs, CoreModel, CoreOutputs
from .stepgen import StepCfg

FULL_STROBE = 0xF
SPEED_SHIFT = 6         # SPEED = the core's speed (BLU/clock x 2^38) / 2^6
IRQ_BIT = {f.name: f.lsb for f in rm.IRQ_FIELDS}
IRQ_MASK = sum(f.mask for f in rm.IRQ_FIELDS)


@dataclass
class Request:
    valid: int = 0
    write: int = 0
    addr: int = 0
    wdata: int = 0
    wstrb: int = FULL_STROBE


@dataclass
class RegsOutputs:
    resp_valid: int
    resp_error: int
    resp_rdata: int
    irq: int
    core: CoreOutputs


def field_value(reg: rm.Register, name: str, word: int) -> int:
    f = next(f for f in reg.fields if f.name == name)
    return (word >> f.lsb) & ((1 << f.width) - 1)


class RegsModel:
    """Clock-by-clock twin of ``halfpoint_regs``: :meth:`outputs` is what the RTL
    shows during the current clock, :meth:`clock` applies one rising edge."""

    def __init__(self, axes: int = 3, width: int = 32, depth: int = 16, tw: int = 16,
                 div: int = 12, move_depth: int = 4, profile_depth: int = 2):
        self.params = {"NA": axes, "W": width, "DEPTH": depth, "TW": tw, "DIV": div,
                       "MOVE_DEPTH": move_depth, "PROFILE_DEPTH": profile_depth}
        self.axes, self.width, self.depth, self.tw = axes, width, depth, tw
        self.core = CoreModel(axes, width, depth, tw, div, move_depth, profile_depth,
                              [StepCfg() for _ in range(axes)])
        self.map = rm.addresses(axes)
        self.reset()

    # ------------------------------------------------------------------
    def reset(self) -> None:
        self.core.reset()
        self.values = {}            # (name, index) -> stored value of RW/W1C registers
        for reg in rm.REGISTERS:
            if reg.access != rm.RO:
                for k in range(reg.size(self.axes)):
                    self.values[(reg.name, k)] = self._masked(reg, rm.reset_value(reg,
                                                                                self.params))
        self.snapshot = [0] * self.axes
        self.pin_inv = [(0, 0)] * self.axes     # the polarity the pins were made with
        self.busy_before = 0
        self.hold_before = 0        # CONTROL.HOLD as it was in the clock before
        self.resp = (0, 0, 0)
        self._apply_config()

    def _masked(self, reg: rm.Register, word: int) -> int:
        """The bits a write keeps: the fields, cut to TW bits (timing) or NA bits
        (polarity)."""
        out = 0
        for f in reg.fields:
            width = f.width
            if reg.name in ("STEP_TIMING", "DIR_TIMING"):
                width = min(width, self.tw)
            elif reg.name == "POLARITY":
                width = min(width, self.axes)
            out |= ((word >> f.lsb) & ((1 << width) - 1)) << f.lsb
        return out

    def _get(self, name: str, index: int = 0) -> int:
        return self.values[(name, index)]

    def _field(self, name: str, fld: str, index: int = 0) -> int:
        return field_value(rm.BY_NAME[name], fld, self._get(name, index))

    def _apply_config(self) -> None:
        """The core's STEP/DIR settings from the registers."""
        step_inv = self._field("POLARITY", "STEP_INV")
        dir_inv = self._field("POLARITY", "DIR_INV")
        for k in range(self.axes):
            self.core.cfg[k] = StepCfg(
                self._field("STEP_TIMING", "STEPLEN", k),
                self._field("STEP_TIMING", "STEPSPACE", k),
                self._field("DIR_TIMING", "DIRSETUP", k),
                self._field("DIR_TIMING", "DIRHOLD", k),
                (step_inv >> k) & 1, (dir_inv >> k) & 1)

    # ------------------------------------------------------------------
    def outputs(self) -> RegsOutputs:
        irq = int(bool(self._get("IRQ_STATUS") & self._get("IRQ_ENABLE")))
        valid, error, rdata = self.resp
        # the STEP/DIR pins are registers: made at the last edge with the
        # polarity of the clock before it, so a POLARITY write shows on the pins
        # one clock after the settings take it
        cfg = self.core.cfg
        self.core.cfg = [StepCfg(c.steplen, c.stepspace, c.dirsetup, c.dirhold, si, di)
                         for c, (si, di) in zip(cfg, self.pin_inv)]
        try:
            core = self.core.outputs()
        finally:
            self.core.cfg = cfg
        return RegsOutputs(valid, error, rdata, irq, core)

    def read_value(self, reg: rm.Register, index: int, co: CoreOutputs) -> int:
        """The value a read of register ``reg`` (element ``index``) answers now."""
        name = reg.name
        if reg.access == rm.RO and name not in ("STATUS", "QUEUE", "SPEED", "POS"):
            return rm.reset_value(reg, self.params)
        mask32 = (1 << 32) - 1
        if name == "STATUS":
            # from the hold's second clock: on its first the speed may still
            # rise by one step (the profile stage's target was registered before)
            holding = int(self._field("CONTROL", "HOLD") == 1 and self.hold_before == 1
                          and co.speed == 0)
            fields = {"BUSY": co.busy, "READY": co.tready, "HOLDING": holding,
                      "UNDERRUN": co.underrun, "DRY": co.dry, "ERR_CODE": co.err_code}
            return sum(fields[f.name] << f.lsb for f in reg.fields)
        if name == "QUEUE":
            return co.level | (self.depth - co.level) << 16
        if name == "SPEED":
            return (co.speed >> SPEED_SHIFT) & mask32
        if name == "POS":
            value = co.pos[0] if index == 0 else self.snapshot[index]
            return value & mask32           # positions are signed: sign-extended
        return self._get(name, index)

    def decode(self, req: Request) -> tuple[rm.Register, int] | None:
        """The register a request addresses, or None when it gets an error."""
        hit = self.map.get(req.addr)
        if hit is None:
            return None
        if req.write and (hit[0].access == rm.RO or req.wstrb != FULL_STROBE):
            return None
        return hit

    def clock(self, req: Request, rst: int = 0) -> None:
        """One rising edge with ``req`` on the access port."""
        if rst:
            self.reset()
            return
        co = self.core.outputs()
        hold_now = self._field("CONTROL", "HOLD")
        hit = self.decode(req) if req.valid else None
        events = 0
        if co.level < self._field("IRQ_THRESHOLD", "LEVEL"):
            events |= 1 << IRQ_BIT["QUEUE_LOW"]
        if co.err:
            events |= 1 << IRQ_BIT["ERROR"]
        if self.busy_before and not co.busy:
            events |= 1 << IRQ_BIT["DONE"]
        # the core's edge, with the registers as they were before it
        tvalid, tdata = 0, 0
        if hit is not None and req.write and hit[0].name == "CMD" \
                and hit[1] == enc.CMD_WORDS - 1:
            tvalid = 1
            tdata = sum(self._get("CMD", k) << (32 * k) for k in range(enc.CMD_WORDS - 1))
            tdata |= req.wdata << (32 * (enc.CMD_WORDS - 1))
            if not co.tready:
                events |= 1 << IRQ_BIT["OVERFLOW"]
        self.core.clock(CoreInputs(
            tvalid=tvalid, tdata=tdata,
            override=self._field("CONTROL", "OVERRIDE"),
            abort=self._field("CONTROL", "ABORT"), hold=self._field("CONTROL", "HOLD"),
            stop=self._field("CONTROL", "STOP")))
        # the bus
        clear = 0
        if not req.valid:
            self.resp = (0, 0, 0)
        elif hit is None:
            self.resp = (1, 1, 0)
        else:
            reg, index = hit
            if req.write:
                if reg.access == rm.W1C:
                    clear = req.wdata & IRQ_MASK
                else:
                    self.values[(reg.name, index)] = self._masked(reg, req.wdata)
                self.resp = (1, 0, 0)
            else:
                self.resp = (1, 0, self.read_value(reg, index, co))
                if reg.name == "POS" and index == 0:
                    self.snapshot = list(co.pos)
        status = self._get("IRQ_STATUS")
        self.values[("IRQ_STATUS", 0)] = (status & ~clear) | events
        self.busy_before = co.busy
        self.hold_before = hold_now
        self.pin_inv = [(c.step_inv, c.dir_inv) for c in self.core.cfg]
        self._apply_config()
