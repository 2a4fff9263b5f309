# SPDX-License-Identifier: Apache-2.0
"""The motion core's command encoding: the one definition.

A command is one beat of the AXI4-Stream input, CMD_BITS = 256 bits, eight
32-bit little-endian words (word k in bits 32k+31 .. 32k):

====  ==============================  =====================================
word  LINE                            ARC (XY plane)
====  ==============================  =====================================
0     opcode (bits 3:0) = 1           opcode = 2 (CW, G2) or 3 (CCW, G3)
      bit 8: CONT, more segments of   bit 8: CONT
      this program follow
1     rate: BLU per clock x 2^24      rate: BLU of path per clock x 2^24
      (unsigned; 2^24 = 1 move/clock)
2..7  delta of axis 0..5 (signed)     2: I, 3: J = centre minus the current
                                      position; 4: X, 5: Y = end minus the
                                      current position (signed); 6, 7: 0
====  ==============================  =====================================

All other bits are reserved and must be zero.  Deltas and coordinates are
BLU, relative to the current position (like G91 with G91.1).  The RTL decodes
these fields in ``rtl/halfpoint_core.v``; the tests and the host encoder use
this module, and a test checks both against each other.
"""

from __future__ import annotations

CMD_WORDS = 8
CMD_BITS = 32 * CMD_WORDS
MAX_AXES = 6

OP_LINE = 1
OP_ARC_CW = 2
OP_ARC_CCW = 3
FLAG_CONT = 1 << 8
OPCODE_MASK = 0xF

RATE_FRAC_BITS = 24
RATE_ONE = 1 << RATE_FRAC_BITS          # 1 BLU per clock

# error codes of the core (err_code output, ERR_CODE_BITS wide; also bits 3:0 of
# the serial port's acknowledge byte)
ERR_CODE_BITS = 4
E_NONE = 0
E_OPCODE = 1        # unknown opcode or reserved bits set
E_FIELD = 2         # a coordinate does not fit the core's width
E_ARC_RADIUS = 3    # arc: radius zero
E_ARC_RANGE = 4     # arc: circle does not fit the width
E_ARC_END = 5       # arc: end point off the circle

ERR_TEXT = {
    E_NONE: "ok",
    E_OPCODE: "unknown opcode or reserved bits set",
    E_FIELD: "coordinate does not fit the core's width",
    E_ARC_RADIUS: "arc radius is zero",
    E_ARC_RANGE: "arc circle does not fit the coordinate width",
    E_ARC_END: "arc end point is off the circle",
}


def _u32(v: int) -> int:
    if not -(1 << 31) <= v < (1 << 32):
        raise ValueError(f"{v} does not fit a 32-bit field")
    return v & 0xFFFFFFFF


def _s32(w: int) -> int:
    return w - (1 << 32) if w & (1 << 31) else w


def pack(words) -> int:
    out = 0
    for k, w in enumerate(words):
        out |= _u32(w) << (32 * k)
    return out


def unpack(cmd: int) -> list[int]:
    return [(cmd >> (32 * k)) & 0xFFFFFFFF for k in range(CMD_WORDS)]


def encode_line(deltas, rate: int = RATE_ONE, cont: bool = False) -> int:
    deltas = list(deltas)
    if not 1 <= len(deltas) <= MAX_AXES:
        raise ValueError(f"a line has 1..{MAX_AXES} deltas, got {len(deltas)}")
    if not 0 <= rate < (1 << 32):
        raise ValueError(f"rate {rate} does not fit 32 bits unsigned")
    words = [OP_LINE | (FLAG_CONT if cont else 0), rate] + deltas
    return pack(words + [0] * (CMD_WORDS - len(words)))


def encode_arc(cw: int, i: int, j: int, x: int, y: int, rate: int = RATE_ONE,
               cont: bool = False) -> int:
    if not 0 <= rate < (1 << 32):
        raise ValueError(f"rate {rate} does not fit 32 bits unsigned")
    op = OP_ARC_CW if cw else OP_ARC_CCW
    return pack([op | (FLAG_CONT if cont else 0), rate, i, j, x, y, 0, 0])


def decode(cmd: int) -> dict:
    """Fields of a command word (for tests and tools)."""
    w = unpack(cmd)
    op = w[0] & OPCODE_MASK
    d = {"opcode": op, "cont": bool(w[0] & FLAG_CONT), "rate": w[1],
         "reserved_ok": (w[0] & ~(OPCODE_MASK | FLAG_CONT)) == 0}
    if op == OP_LINE:
        d["deltas"] = [_s32(v) for v in w[2:2 + MAX_AXES]]
    elif op in (OP_ARC_CW, OP_ARC_CCW):
        d["cw"] = int(op == OP_ARC_CW)
        d["i"], d["j"], d["x"], d["y"] = (_s32(v) for v in w[2:6])
        d["reserved_ok"] = d["reserved_ok"] and w[6] == 0 and w[7] == 0
    return d
