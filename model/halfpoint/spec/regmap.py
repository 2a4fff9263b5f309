# SPDX-License-Identifier: Apache-2.0
"""The register map of the SoC register interface: the one definition.

``rtl/halfpoint_regs.v`` (the register file around ``halfpoint_core``, behind
the Wishbone wrapper ``halfpoint_wb`` and the AXI4-Lite wrapper
``halfpoint_axil``) decodes its addresses through ``rtl/halfpoint_regs.vh``,
the C header ``include/halfpoint_regs.h`` gives software the same names, and
the README's register table is the Markdown of ``markdown_table``: all three are
generated from this module by ``python -m halfpoint.flows.regmapgen``.
``spec.regs.RegsModel``, the cycle-accurate model of the register file, reads
the map from here too.

Every register is 32 bits wide at a byte offset that is a multiple of 4 in a
window of 2^ADDR_BITS bytes.  Arrays (one register per axis, or per command
word) have a count and a stride; a per-axis array has NA registers in a core
of NA axes, and the addresses of the absent axes are unknown addresses.

Rules of the bus (both wrappers): a read or a write of an address that is not
in the map, a write to a read-only register, and a write whose byte enables
are not all four set get an error response (Wishbone ERR, AXI4-Lite SLVERR)
and change nothing.  Fields narrower than their slot read the unused bits as
zero and ignore them on writes.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from . import encoding as enc

ADDR_BITS = 8                  # the register window: 256 bytes
DATA_BITS = 32
ID_VALUE = 0x48504E54          # "HPNT"
VERSION_MAJOR = 1
VERSION_MINOR = 0

# access kinds
RO = "ro"        # read only (a write is an error)
RW = "rw"        # read and write
W1C = "w1c"      # read; writing 1 to a bit clears it

PER_AXIS = "NA"  # count of a per-axis array: the core's NA


@dataclass(frozen=True)
class Field:
    name: str
    lsb: int
    width: int
    doc: str
    reset: int | str = 0       # a number, or the name of a design parameter

    @property
    def mask(self) -> int:
        return ((1 << self.width) - 1) << self.lsb


@dataclass(frozen=True)
class Register:
    name: str
    offset: int
    access: str
    doc: str
    fields: tuple[Field, ...] = field(default_factory=tuple)
    count: int | str = 1       # >1 or PER_AXIS: an array
    stride: int = 4

    def address(self, index: int = 0) -> int:
        return self.offset + self.stride * index

    def size(self, axes: int) -> int:
        return axes if self.count == PER_AXIS else int(self.count)


def _bits(name: str, lsb: int, doc: str, width: int = 1, reset: int | str = 0) -> Field:
    return Field(name, lsb, width, doc, reset)


# interrupt sources (IRQ_STATUS / IRQ_ENABLE bits)
IRQ_FIELDS = (
    _bits("QUEUE_LOW", 0, "the queue holds fewer commands than IRQ_THRESHOLD (set on every "
          "clock it does)"),
    _bits("ERROR", 1, "the core rejected a command (its code: STATUS.ERR_CODE)"),
    _bits("DONE", 2, "the core went from busy to idle: the program is done"),
    _bits("OVERFLOW", 3, "a push was refused (queue full, stop or abort): the command was "
          "not taken"),
)

REGISTERS = (
    Register("ID", 0x00, RO, f"identification, the constant 0x{ID_VALUE:08X} (\"HPNT\")",
             (_bits("VALUE", 0, "0x%08X" % ID_VALUE, 32, ID_VALUE),)),
    Register("VERSION", 0x04, RO, "version of this register map",
             (_bits("MINOR", 0, "minor version", 16, VERSION_MINOR),
              _bits("MAJOR", 16, "major version", 16, VERSION_MAJOR))),
    Register("GEOMETRY", 0x08, RO, "the core's parameters",
             (_bits("AXES", 0, "axes", 8, "NA"),
              _bits("WIDTH", 8, "position width in bits", 8, "W"),
              _bits("TIMING_WIDTH", 16, "width of the STEP/DIR timing settings", 8, "TW"),
              _bits("DIV", 24, "profile tick of 2^DIV clocks", 8, "DIV"))),
    Register("QUEUES", 0x0C, RO, "the core's queue depths",
             (_bits("DEPTH", 0, "command queue depth", 16, "DEPTH"),
              _bits("MOVE_DEPTH", 16, "move queue depth", 8, "MOVE_DEPTH"),
              _bits("PROFILE_DEPTH", 24, "profile queue depth", 8, "PROFILE_DEPTH"))),
    Register("CONTROL", 0x10, RW, "motion control (levels, as the core's inputs)",
             (_bits("HOLD", 0, "feed hold: decelerate to rest and wait"),
              _bits("STOP", 1, "controlled stop: decelerate, then drop everything not yet "
                    "moved (pushes are refused while it is set)"),
              _bits("ABORT", 2, "stop at once, drop everything not yet moved (pushes are "
                    "refused while it is set)"),
              _bits("OVERRIDE", 8, "feed override in 1/128 (128 = 100 %, above acts as 128)",
                    8, 128))),
    Register("POLARITY", 0x14, RW, "pin polarity, one bit per axis (bits of absent axes "
             "read 0)",
             (_bits("STEP_INV", 0, "invert STEP of axis k (bit k)", 6),
              _bits("DIR_INV", 8, "invert DIR of axis k (bit 8 + k)", 6))),
    Register("STATUS", 0x18, RO, "the core's status",
             (_bits("BUSY", 0, "commands queued or running, or a STEP pulse going"),
              _bits("READY", 1, "a push would be taken now (queue not full, no stop or "
                    "abort)"),
              _bits("HOLDING", 2, "CONTROL.HOLD is set, was set a clock before, and the "
                    "path speed is zero: no step until HOLD is cleared"),
              _bits("UNDERRUN", 3, "sticky: a CONT segment ended with no next one"),
              _bits("DRY", 4, "sticky: the profile stage decelerated for a dry queue"),
              _bits("ERR_CODE", 8, "code of the last rejected command (0: none)",
                    enc.ERR_CODE_BITS))),
    Register("QUEUE", 0x1C, RO, "command queue occupancy",
             (_bits("LEVEL", 0, "commands in the queue", 16),
              _bits("FREE", 16, "free entries (DEPTH - LEVEL)", 16))),
    Register("IRQ_STATUS", 0x20, W1C, "pending interrupts; write 1 to clear a bit",
             IRQ_FIELDS),
    Register("IRQ_ENABLE", 0x24, RW, "interrupt enables, the bits of IRQ_STATUS: irq is "
             "high while a pending bit is enabled", IRQ_FIELDS),
    Register("IRQ_THRESHOLD", 0x28, RW, "QUEUE_LOW is pending while QUEUE.LEVEL < this",
             (_bits("LEVEL", 0, "threshold in commands (0: never)", 16),)),
    Register("SPEED", 0x2C, RO, "path speed, BLU per clock x 2^32 (the core's speed / 64)",
             (_bits("VALUE", 0, "speed", 32),)),
    Register("CMD", 0x40, RW, "the command being written, word k of the 256-bit command "
             "(see Command encoding); writing CMD_7 pushes all eight words into the queue "
             "(or sets IRQ_STATUS.OVERFLOW if refused); the words keep their values",
             (_bits("WORD", 0, "command word", 32),), count=enc.CMD_WORDS),
    Register("POS", 0x60, RO, "position of axis k, sign-extended from W bits; reading POS_0 "
             "takes a snapshot of all axes on the same clock, POS_1.. read that snapshot",
             (_bits("VALUE", 0, "position, BLU", 32),), count=PER_AXIS),
    Register("STEP_TIMING", 0x80, RW, "STEP timing of axis k, in clocks (TW bits each)",
             (_bits("STEPLEN", 0, "STEP active time", 16, 1),
              _bits("STEPSPACE", 16, "STEP inactive time between steps", 16, 1)),
             count=PER_AXIS, stride=8),
    Register("DIR_TIMING", 0x84, RW, "DIR timing of axis k, in clocks (TW bits each)",
             (_bits("DIRSETUP", 0, "DIR change to STEP active", 16, 1),
              _bits("DIRHOLD", 16, "STEP inactive to DIR change", 16, 1)),
             count=PER_AXIS, stride=8),
)

BY_NAME = {r.name: r for r in REGISTERS}


def reset_value(reg: Register, params: dict[str, int]) -> int:
    """A register's value after reset for a core with ``params`` (NA, W, ...)."""
    out = 0
    for f in reg.fields:
        value = params[f.reset] if isinstance(f.reset, str) else f.reset
        out |= (value & ((1 << f.width) - 1)) << f.lsb
    return out


def addresses(axes: int = enc.MAX_AXES) -> dict[int, tuple[Register, int]]:
    """byte address -> (register, index) of every register of a core of ``axes`` axes."""
    out: dict[int, tuple[Register, int]] = {}
    for reg in REGISTERS:
        for k in range(reg.size(axes)):
            a = reg.address(k)
            if a in out:
                raise ValueError(
                    f"{reg.name}_{k} and {out[a][0].name} share address {a:#x}")
            out[a] = (reg, k)
    return out


def check() -> None:
    """The map's own rules: aligned addresses in the window, no overlaps, fields
    inside 32 bits and apart, the arrays sized for MAX_AXES axes."""
    for reg in REGISTERS:
        if reg.offset % 4 or reg.stride % 4:
            raise ValueError(f"{reg.name}: offset and stride must be multiples of 4")
        last = reg.address(reg.size(enc.MAX_AXES) - 1)
        if last >= 1 << ADDR_BITS:
            raise ValueError(f"{reg.name}: beyond the {1 << ADDR_BITS}-byte window")
        used = 0
        for f in reg.fields:
            if f.lsb < 0 or f.lsb + f.width > DATA_BITS or used & f.mask:
                raise ValueError(f"{reg.name}.{f.name}: outside 32 bits or overlapping")
            used |= f.mask
    addresses(enc.MAX_AXES)


check()
