# SPDX-License-Identifier: Apache-2.0
"""The motion core's command encoding: the one definition.

A command is one beat of the AXI4-Stream input, CMD_BITS = 256 bits, eight
32-bit little-endian words (word k in bits 32k+31 .. 32k):

====  ==============================  =====================================
word  LINE                            ARC (any plane, helix)
====  ==============================  =====================================
0     opcode (bits 3:0) = 1           opcode = 2 (CW, G2) or 3 (CCW, G3)
      bit 8: CONT, more segments of   bit 8: CONT; bits 18:16 axis u,
      this program follow             bits 22:20 axis v (the plane)
1     0 (reserved)                    count N: the arc's exact move count
                                      (unsigned; 0 = not given, flat only)
2..7  delta of axis 0..5 (signed)     2: I, 3: J = centre minus the current
                                      position; 4: U, 5: V = end minus the
                                      current position, in (u, v) (signed);
                                      6, 7: helix deltas of the first and
                                      second axis outside the plane
====  ==============================  =====================================

An arc runs in the plane of axes (u, v), clockwise or counter-clockwise as
seen from the positive normal axis u x v: G17 is (X, Y) = (0, 1), G18 is
(Z, X) = (2, 0) and G19 is (Y, Z) = (1, 2) (LinuxCNC's orientation).  The
helix slots 0 and 1 are the axes outside the plane in increasing order (a
core of NA axes has min(2, NA - 2) slots; a non-zero delta in a slot it does
not have is a reserved bit set, E_OPCODE).  Every arc move steps slot k's
axis by the difference method against N (``spec.helix``): after exactly N
moves it has made exactly |delta| steps, so |delta| <= N (else E_HELIX; a
delta with N = 0 too).  An axis pair out of range (u or v >= NA, u == v) or
a delta beyond W is E_FIELD.  If the arc makes a number of moves other than
N (the host's encoder gives the exact count from ``spec.arc.arc_stop``), the
helix steps beyond N are dropped, the steps short of |delta| are not made,
and the core reports E_HELIX_COUNT at the arc's last move.

PROFILE (opcode 4) sets the velocity profile of the motion commands that follow
it (``spec.profile.ProfileParams``; the host sends one before each motion
command, with its planned speeds and distances), and may carry the power of the
spindle / laser output for the segments run under it (laser mode: power changes
travel with the motion instead of waiting for rest, as grbl's laser mode does
with S words): the fields, in bits

================  =====  =====  ==============================================
field             lsb    bits   meaning (``spec.profile``'s fixed point)
================  =====  =====  ==============================================
v_cruise           32     32    cruise (peak) path speed, BLU per clock x 2^32
v_exit             64     32    exit speed, <= v_cruise; 0 = stop at the end
accel              96     34    speed step per tick (2^DIV clocks),
                                BLU per clock x 2^38, > 0
line_cost         130     18    one line iteration's length, BLU x 2^16; 0
                                for arcs, > 0 for lines
d_exit            148     54    decelerate to v_exit from this distance into
                                the segment, BLU x 2^16, < 2^(W + 19)
d_stop            202     54    decelerate to rest from here if the next
                                segment is not there yet (dry queue), <= d_exit
set_power           9      1    the output stage's power takes ``power`` at the
                                edge the profile stage takes this segment (the
                                first move of the segment is made after it); 0:
                                the power is left as it is
power              15     17    PWM duty as in OUTPUT, 65536 = 100 %, <= 65536;
                                0 unless set_power
================  =====  =====  ==============================================

OUTPUT (opcode 5; word 0 has no flag) sets the spindle, laser and coolant outputs
(``spec.outputs``; M3/M4/M5, S, M7/M8/M9).  It takes effect when everything
before it has moved (the dispatcher holds it at the queue head until the units,
the move and profile queues and the profile stage are idle; the host plans the
motion before it to end at rest) and before anything after it moves:

================  =====  =====  ==============================================
field             lsb    bits   meaning
================  =====  =====  ==============================================
power              32     17    PWM duty, 65536 = 100 %; <= 65536
enable             49      1    spindle (or laser) on
reverse            50      1    spindle counter-clockwise (M4, not laser mode)
laser              51      1    laser mode: the PWM is off at rest
dynamic            52      1    laser M4: the duty follows speed / cruise speed
mist               53      1    coolant mist (M7)
flood              54      1    coolant flood (M8)
================  =====  =====  ==============================================

All other bits are reserved and must be zero.  Deltas and coordinates are
BLU, relative to the current position (like G91 with G91.1).  A PROFILE stays
in force until the next one (so a stream of constant-speed segments needs one),
and is forgotten at reset, abort and stop: a motion command with no profile in
force, an arc under a profile with a line cost, or a line under one without, is
rejected (E_PROFILE), as is a PROFILE whose fields break the rules above
(E_PROFILE_FIELD; the profile in force is then forgotten too, so the commands
meant to run under the bad one are rejected, never run under an older one).
The RTL decodes through ``rtl/halfpoint_cmd.vh``, generated from this module
(``flows/hdlgen.py``); the tests and the host encoder use this module.
"""

from __future__ import annotations

CMD_WORDS = 8
CMD_BITS = 32 * CMD_WORDS
MAX_AXES = 6

OP_LINE = 1
OP_ARC_CW = 2
OP_ARC_CCW = 3
OP_PROFILE = 4
OP_OUTPUT = 5
FLAG_CONT = 1 << 8
OPCODE_MASK = 0xF

# error codes of the core (err_code output, ERR_CODE_BITS wide; also bits 3:0 of
# the serial port's acknowledge byte)
ERR_CODE_BITS = 4
E_NONE = 0
E_OPCODE = 1        # unknown opcode or reserved bits set
E_FIELD = 2         # a coordinate does not fit the core's width (or OUTPUT power > 100 %)
E_ARC_RADIUS = 3    # arc: radius zero
E_ARC_RANGE = 4     # arc: circle does not fit the width
E_ARC_END = 5       # arc: end point off the circle
E_PROFILE = 6       # motion with no profile in force, or of the wrong kind
E_PROFILE_FIELD = 7     # a PROFILE's fields break the rules
E_HELIX = 8         # arc: a helix delta exceeds the move count N (or N = 0)
E_HELIX_COUNT = 9   # arc: made a number of moves other than its N (helix cut short)

ERR_TEXT = {
    E_NONE: "ok",
    E_OPCODE: "unknown opcode or reserved bits set",
    E_FIELD: "coordinate does not fit the core's width, or output power above 100 %",
    E_ARC_RADIUS: "arc radius is zero",
    E_ARC_RANGE: "arc circle does not fit the coordinate width",
    E_ARC_END: "arc end point is off the circle",
    E_PROFILE: "no profile in force for this motion, or one of the other kind",
    E_PROFILE_FIELD: "profile fields break the rules (v_exit, accel, d_stop, d_exit, power)",
    E_HELIX: "helix delta exceeds the arc's move count",
    E_HELIX_COUNT: "arc made a number of moves other than its count (helix steps dropped)",
}

# ARC: the plane's axes (u, v) in word 0, the move count in word 1, the helix
# deltas in words 6, 7: (name, lsb, bits)
ARC_U_FIELD = ("u_axis", 16, 3)
ARC_V_FIELD = ("v_axis", 20, 3)
ARC_COUNT_FIELD = ("count", 32, 32)
HELIX_SLOTS = 2
# the planes of G17, G18, G19 as (u, v): CW/CCW as seen from the positive u x v
PLANES = {17: (0, 1), 18: (2, 0), 19: (1, 2)}
PLANE_XY = PLANES[17]


def helix_slots(axes: int) -> int:
    """Helix slots of a core of ``axes`` axes."""
    return max(0, min(HELIX_SLOTS, axes - 2))


def helix_axes(u: int, v: int, axes: int) -> tuple:
    """The axes of the helix slots of the plane (u, v): the axes outside the plane in
    increasing order, at most ``helix_slots(axes)`` of them."""
    return tuple(a for a in range(axes) if a not in (u, v))[:helix_slots(axes)]

# PROFILE fields: (name, lsb, bits), in order
PROFILE_FIELDS = (
    ("v_cruise", 32, 32),
    ("v_exit", 64, 32),
    ("accel", 96, 34),
    ("line_cost", 130, 18),
    ("d_exit", 148, 54),
    ("d_stop", 202, 54),
    ("set_power", 9, 1),
    ("power", 15, 17),
)
PROFILE_DISTANCE_EXTRA = 19     # d_exit, d_stop < 2^(W + 19) for a core of width W

# OUTPUT fields: (name, lsb, bits), in order
OUTPUT_FIELDS = (
    ("power", 32, 17),
    ("enable", 49, 1),
    ("reverse", 50, 1),
    ("laser", 51, 1),
    ("dynamic", 52, 1),
    ("mist", 53, 1),
    ("flood", 54, 1),
)
OUTPUT_POWER_FULL = 1 << 16     # power field of a 100 % duty; above it: E_FIELD


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


def encode_line(deltas, cont: bool = False) -> int:
    deltas = list(deltas)
    if not 1 <= len(deltas) <= MAX_AXES:
        raise ValueError(f"a line has 1..{MAX_AXES} deltas, got {len(deltas)}")
    words = [OP_LINE | (FLAG_CONT if cont else 0), 0] + deltas
    return pack(words + [0] * (CMD_WORDS - len(words)))


def encode_arc(cw: int, i: int, j: int, x: int, y: int, cont: bool = False, *,
               plane=PLANE_XY, count: int = 0, helix=(0, 0)) -> int:
    """An ARC command: ``i, j`` the centre and ``x, y`` the end minus the current
    position in the plane's (u, v) = ``plane``; ``count`` the exact move count
    (``spec.arc.arc_stop``; 0 only for a flat arc), ``helix`` the deltas of the
    helix slots (``helix_axes``)."""
    op = OP_ARC_CW if cw else OP_ARC_CCW
    u, v = plane
    helix = tuple(helix) + (0,) * (HELIX_SLOTS - len(tuple(helix)))
    if len(helix) != HELIX_SLOTS:
        raise ValueError(f"an arc has at most {HELIX_SLOTS} helix deltas")
    for name, (_, _, bits), value in (("u", ARC_U_FIELD, u), ("v", ARC_V_FIELD, v),
                                      ("count", ARC_COUNT_FIELD, count)):
        if not 0 <= value < 1 << bits:
            raise ValueError(f"arc {name} {value} does not fit {bits} bits unsigned")
    word0 = op | (FLAG_CONT if cont else 0) | (u << ARC_U_FIELD[1]) | (v << ARC_V_FIELD[1])
    return pack([word0, count, i, j, x, y, helix[0], helix[1]])


def encode_profile(v_cruise: int, v_exit: int, accel: int, line_cost: int = 0,
                   d_exit: int = 0, d_stop: int = 0, set_power: int = 0, power: int = 0) -> int:
    """A PROFILE command (the fields of ``spec.profile.ProfileParams``, in that order;
    ``encode_profile(*dataclasses.astuple(params))``).  Only the field widths are
    checked here: the core checks the rules (E_PROFILE_FIELD)."""
    out = OP_PROFILE
    for (name, lsb, bits), value in zip(PROFILE_FIELDS,
                                        (v_cruise, v_exit, accel, line_cost, d_exit, d_stop,
                                         int(set_power), power)):
        if not 0 <= value < 1 << bits:
            raise ValueError(f"profile {name} {value} does not fit {bits} bits unsigned")
        out |= value << lsb
    return out


def encode_output(power: int = 0, enable: int = 0, reverse: int = 0, laser: int = 0,
                  dynamic: int = 0, mist: int = 0, flood: int = 0) -> int:
    """An OUTPUT command (the fields of ``OUTPUT_FIELDS``, in that order).  Only the
    field widths are checked here: the core rejects a power above
    ``OUTPUT_POWER_FULL`` (E_FIELD)."""
    out = OP_OUTPUT
    for (name, lsb, bits), value in zip(OUTPUT_FIELDS,
                                        (power, enable, reverse, laser, dynamic, mist, flood)):
        value = int(value)
        if not 0 <= value < 1 << bits:
            raise ValueError(f"output {name} {value} does not fit {bits} bits unsigned")
        out |= value << lsb
    return out


def decode(cmd: int) -> dict:
    """Fields of a command word (for tests and tools)."""
    w = unpack(cmd)
    op = w[0] & OPCODE_MASK
    d = {"opcode": op, "cont": bool(w[0] & FLAG_CONT),
         "reserved_ok": (w[0] & ~(OPCODE_MASK | FLAG_CONT)) == 0 and w[1] == 0}
    if op == OP_LINE:
        d["deltas"] = [_s32(v) for v in w[2:2 + MAX_AXES]]
    elif op in (OP_ARC_CW, OP_ARC_CCW):
        d["cw"] = int(op == OP_ARC_CW)
        d["i"], d["j"], d["x"], d["y"] = (_s32(v) for v in w[2:6])
        d["u_axis"] = (w[0] >> ARC_U_FIELD[1]) & ((1 << ARC_U_FIELD[2]) - 1)
        d["v_axis"] = (w[0] >> ARC_V_FIELD[1]) & ((1 << ARC_V_FIELD[2]) - 1)
        d["count"] = w[1]
        d["helix"] = tuple(_s32(v) for v in w[6:6 + HELIX_SLOTS])
        used0 = OPCODE_MASK | FLAG_CONT
        for _, lsb, bits in (ARC_U_FIELD, ARC_V_FIELD):
            used0 |= ((1 << bits) - 1) << lsb
        d["reserved_ok"] = (w[0] & ~used0) == 0
    elif op == OP_PROFILE:
        d["cont"] = False
        used = OPCODE_MASK | ~((1 << 32) - 1)       # every bit above word 0 is a field
        for name, lsb, bits in PROFILE_FIELDS:
            d[name] = (cmd >> lsb) & ((1 << bits) - 1)
            used |= ((1 << bits) - 1) << lsb
        d["reserved_ok"] = (cmd & ~used) == 0
    elif op == OP_OUTPUT:
        d["cont"] = False
        used = OPCODE_MASK
        for name, lsb, bits in OUTPUT_FIELDS:
            d[name] = (cmd >> lsb) & ((1 << bits) - 1)
            used |= ((1 << bits) - 1) << lsb
        d["reserved_ok"] = (cmd & ~used) == 0
    return d
