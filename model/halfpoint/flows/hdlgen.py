# SPDX-License-Identifier: Apache-2.0
"""``python -m halfpoint.flows.hdlgen``: the Verilog header of the command
encoding, rtl/halfpoint_cmd.vh, generated from ``halfpoint.spec.encoding``.

``halfpoint.spec.encoding`` is the one definition of the motion core's
command layout.  This module derives every field's position from it (by
encoding commands that differ in one field only, so the positions are those
the host encoder really writes) and writes them, with the opcodes, the CONT
flag, the reserved bits and the core's error codes, as Verilog macros that
the RTL includes.  Each macro is ``HALFPOINT_`` followed by the name of the
constant in ``encoding`` (``HALFPOINT_OP_LINE``, ``HALFPOINT_E_FIELD``), or by
``CMD_<field>_LSB`` / ``CMD_<field>_WIDTH`` for a field's bits.

    python -m halfpoint.flows.hdlgen            write rtl/halfpoint_cmd.vh and
                                                rtl/halfpoint_link.vh
    python -m halfpoint.flows.hdlgen --check    exit 1 if one is not current

The second header, rtl/halfpoint_link.vh, is the serial link's constants
(frame opcodes, reply bytes, NAK reasons, status flags, payload sizes and the
protocol version) from ``halfpoint.spec.link``, the link's one definition;
``rtl/halfpoint_uart_cmd.v`` includes it.

``make lint`` runs the check, and tb/flows/test_hdlgen.py tests both the
header's currency and that the RTL decodes through it.
"""

from __future__ import annotations

import argparse
import sys
from dataclasses import dataclass
from pathlib import Path
from types import ModuleType

from ..sim.env import RTL
from ..spec import encoding, link

HEADER = RTL / "halfpoint_cmd.vh"
LINK_HEADER = RTL / "halfpoint_link.vh"
PREFIX = "HALFPOINT_"
GUARD = PREFIX + "CMD_VH"


@dataclass(frozen=True)
class Define:
    """One macro: `define <name> <value>, with a comment line above it.
    A Define with an empty name is a section comment only."""
    name: str
    value: str
    doc: str


def bit_run(mask: int, what: str) -> tuple[int, int]:
    """(lsb, width) of a mask that must be one contiguous run of ones."""
    if mask <= 0:
        raise ValueError(f"{what}: the encoder sets no bit for it")
    lsb = (mask & -mask).bit_length() - 1
    width = (mask >> lsb).bit_length()
    if mask != ((1 << width) - 1) << lsb:
        raise ValueError(f"{what}: bits {mask:#x} are not one contiguous field")
    return lsb, width


def field_bits(a: int, b: int, what: str) -> tuple[int, int]:
    """(lsb, width) of the field in which two encoded commands differ."""
    return bit_run(a ^ b, what)


def sized(width: int, value: int) -> str:
    return f"{width}'d{value}"


def defines(enc: ModuleType = encoding) -> list[Define]:
    """The header's macros, derived from the encoding module ``enc``."""
    bits = enc.CMD_BITS

    # word 0: opcode and CONT
    op_lsb, op_width = bit_run(enc.OPCODE_MASK, "opcode")
    line0 = enc.encode_line([0])
    if (line0 >> op_lsb) & enc.OPCODE_MASK != enc.OP_LINE:
        raise ValueError("the encoder does not put OP_LINE into the opcode bits")
    cont_lsb, cont_width = field_bits(enc.encode_line([0], cont=True), line0, "CONT")
    if cont_width != 1 or enc.FLAG_CONT != 1 << cont_lsb:
        raise ValueError("CONT is not the single bit FLAG_CONT")

    # the line deltas
    zeros = enc.encode_line([0] * enc.MAX_AXES)
    deltas = []
    for k in range(enc.MAX_AXES):
        marked = [0] * enc.MAX_AXES
        marked[k] = -1
        deltas.append(field_bits(enc.encode_line(marked), zeros, f"delta {k}"))
    stride = deltas[1][0] - deltas[0][0] if len(deltas) > 1 else deltas[0][1]
    for k, (lsb, width) in enumerate(deltas):
        if lsb != deltas[0][0] + k * stride or width != deltas[0][1]:
            raise ValueError("the line deltas are not evenly spaced fields of one width")

    # arc coordinates
    arc0 = enc.encode_arc(0, 0, 0, 0, 0)
    coords = {}
    for n, name in enumerate("IJXY"):
        args = [0, 0, 0, 0]
        args[n] = -1
        coords[name] = field_bits(enc.encode_arc(0, *args), arc0, f"arc {name}")
    arc_fields = {}
    for name, kwargs in (("U_AXIS", {"plane": (7, 0)}), ("V_AXIS", {"plane": (0, 7)}),
                         ("COUNT", {"plane": (0, 0), "count": 0xFFFFFFFF}),
                         *((f"HELIX{k}", {"plane": (0, 0),
                                          "helix": tuple(-1 if n == k else 0
                                                         for n in range(enc.HELIX_SLOTS))})
                           for k in range(enc.HELIX_SLOTS))):
        arc_fields[name] = field_bits(enc.encode_arc(0, 0, 0, 0, 0, **kwargs),
                                      enc.encode_arc(0, 0, 0, 0, 0, plane=(0, 0)),
                                      f"arc {name.lower()}")
    helix_stride = (arc_fields["HELIX1"][0] - arc_fields["HELIX0"][0]
                    if enc.HELIX_SLOTS > 1 else arc_fields["HELIX0"][1])
    cw = field_bits(enc.encode_arc(1, 0, 0, 0, 0), arc0, "arc direction")
    if cw[0] < op_lsb or cw[0] + cw[1] > op_lsb + op_width:
        raise ValueError("the arc's direction is not carried by the opcode")

    # profile fields: each found by encoding it all ones against all zeros
    profile0 = enc.encode_profile(0, 0, 0)
    if (profile0 >> op_lsb) & enc.OPCODE_MASK != enc.OP_PROFILE:
        raise ValueError("the encoder does not put OP_PROFILE into the opcode bits")
    prof = {}
    for n, (name, _, width) in enumerate(enc.PROFILE_FIELDS):
        args = [0] * len(enc.PROFILE_FIELDS)
        args[n] = (1 << width) - 1
        prof[name] = field_bits(enc.encode_profile(*args), profile0, f"profile {name}")

    # output fields, found the same way
    output0 = enc.encode_output()
    if (output0 >> op_lsb) & enc.OPCODE_MASK != enc.OP_OUTPUT:
        raise ValueError("the encoder does not put OP_OUTPUT into the opcode bits")
    outf = {}
    for n, (name, _, width) in enumerate(enc.OUTPUT_FIELDS):
        args = [0] * len(enc.OUTPUT_FIELDS)
        args[n] = (1 << width) - 1
        outf[name] = field_bits(enc.encode_output(*args), output0, f"output {name}")

    # reserved bits: everything a command of the kind does not use
    def mask(lsb: int, width: int) -> int:
        return ((1 << width) - 1) << lsb
    all_bits = (1 << bits) - 1
    common = mask(op_lsb, op_width) | enc.FLAG_CONT
    line_used = common
    for d in deltas:
        line_used |= mask(*d)
    arc_used = common
    for c in (*coords.values(), *arc_fields.values()):
        arc_used |= mask(*c)
    profile_used = mask(op_lsb, op_width)
    for f in prof.values():
        profile_used |= mask(*f)
    output_used = mask(op_lsb, op_width)
    for f in outf.values():
        output_used |= mask(*f)
    digits = (bits + 3) // 4

    errors = sorted((v, n) for n, v in vars(enc).items()
                    if n.startswith("E_") and isinstance(v, int))
    if max(v for v, _ in errors) >= 1 << enc.ERR_CODE_BITS:
        raise ValueError("an error code does not fit ERR_CODE_BITS")

    out = [
        Define("", "", "command: one beat of the AXI4-Stream input, little-endian 32-bit words"),
        Define("CMD_BITS", str(bits), "bits of a command"),
        Define("MAX_AXES", str(enc.MAX_AXES), "axes a line command can move"),
        Define("", "", "word 0: opcode and flags"),
        Define("CMD_OPCODE_LSB", str(op_lsb), "opcode field"),
        Define("CMD_OPCODE_WIDTH", str(op_width), ""),
        Define("OP_LINE", sized(op_width, enc.OP_LINE), "straight line, every axis"),
        Define("OP_ARC_CW", sized(op_width, enc.OP_ARC_CW),
               "arc in the plane (u, v), clockwise (G2)"),
        Define("OP_ARC_CCW", sized(op_width, enc.OP_ARC_CCW),
               "arc in the plane (u, v), counter-clockwise (G3)"),
        Define("FLAG_CONT_BIT", str(cont_lsb),
               "CONT: more segments of this program follow (for the underrun flag)"),
        Define("OP_PROFILE", sized(op_width, enc.OP_PROFILE),
               "velocity profile of the motion commands that follow"),
        Define("OP_OUTPUT", sized(op_width, enc.OP_OUTPUT),
               "spindle, laser and coolant outputs, once everything before has moved"),
        Define("", "", "line: signed delta of axis k in bits "
               "CMD_DELTA_LSB + k * CMD_DELTA_STRIDE +: CMD_DELTA_WIDTH"),
        Define("CMD_DELTA_LSB", str(deltas[0][0]), ""),
        Define("CMD_DELTA_STRIDE", str(stride), ""),
        Define("CMD_DELTA_WIDTH", str(deltas[0][1]), ""),
        Define("", "", "arc: I, J = centre minus the current position; "
               "X, Y = end minus it (signed)"),
    ]
    for name, (lsb, width) in coords.items():
        out += [Define(f"CMD_ARC_{name}_LSB", str(lsb), ""),
                Define(f"CMD_ARC_{name}_WIDTH", str(width), "")]
    out += [Define("", "", "arc: plane axes u, v (G17 0 1, G18 2 0, G19 1 2), "
                   "move count N (0: none), helix deltas (signed)")]
    for name in ("U_AXIS", "V_AXIS", "COUNT", "HELIX0"):
        lsb, width = arc_fields[name]
        out += [Define(f"CMD_ARC_{name}_LSB", str(lsb), ""),
                Define(f"CMD_ARC_{name}_WIDTH", str(width), "")]
    out += [Define("CMD_ARC_HELIX_STRIDE", str(helix_stride),
                   "slot k's delta at CMD_ARC_HELIX0_LSB + k * CMD_ARC_HELIX_STRIDE"),
            Define("HELIX_SLOTS", str(enc.HELIX_SLOTS), "helix slots of an arc command")]
    out += [Define("", "", "profile fields (unsigned; spec/profile.py gives their fixed point)")]
    for name, (lsb, width) in prof.items():
        out += [Define(f"CMD_PROFILE_{name.upper()}_LSB", str(lsb), ""),
                Define(f"CMD_PROFILE_{name.upper()}_WIDTH", str(width), "")]
    out += [Define("", "", "output fields (unsigned; spec/outputs.py gives their meaning)")]
    for name, (lsb, width) in outf.items():
        out += [Define(f"CMD_OUTPUT_{name.upper()}_LSB", str(lsb), ""),
                Define(f"CMD_OUTPUT_{name.upper()}_WIDTH", str(width), "")]
    out += [
        Define("OUTPUT_POWER_FULL", str(enc.OUTPUT_POWER_FULL),
               "output power of a 100 % duty; above it the command is rejected (E_FIELD)"),
        Define("PROFILE_DISTANCE_EXTRA", str(enc.PROFILE_DISTANCE_EXTRA),
               "d_exit, d_stop < 2^(W + PROFILE_DISTANCE_EXTRA) in a core of width W"),
        Define("", "", "reserved bits (must be zero, else the command is rejected, E_OPCODE)"),
        Define("CMD_RESERVED_LINE", f"{bits}'h{all_bits & ~line_used:0{digits}x}",
               "of a line command (deltas of axes the core does not have are checked too)"),
        Define("CMD_RESERVED_ARC", f"{bits}'h{all_bits & ~arc_used:0{digits}x}",
               "of an arc command"),
        Define("CMD_RESERVED_PROFILE", f"{bits}'h{all_bits & ~profile_used:0{digits}x}",
               "of a profile command"),
        Define("CMD_RESERVED_OUTPUT", f"{bits}'h{all_bits & ~output_used:0{digits}x}",
               "of an output command"),
        Define("", "", "error codes of the core (err_code output)"),
        Define("ERR_CODE_BITS", str(enc.ERR_CODE_BITS), ""),
    ]
    for value, name in errors:
        out.append(Define(name, sized(enc.ERR_CODE_BITS, value), enc.ERR_TEXT[value]))
    return out


def link_defines(lk: ModuleType = link) -> list[Define]:
    """The link header's macros, from the link module ``lk``: every frame opcode,
    reply byte, NAK reason and status flag (``HALFPOINT_LINK_`` and the constant's
    name), the payload sizes and the protocol version."""
    def byte(value: int) -> str:
        if not 0 <= value <= 0xFF:
            raise ValueError(f"link constant {value} does not fit a byte")
        return f"8'h{value:02x}"

    consts = {n: v for n, v in vars(lk).items() if isinstance(v, int) and n.isupper()}
    out = [Define("", "", "protocol version (the IDENT reply's first payload byte)"),
           Define("LINK_PROTOCOL_VERSION", byte(consts["PROTOCOL_VERSION"]), "")]
    groups = (("F_", "host frame opcodes (frame: opcode, payload, CRC-8 check)"),
              ("R_", "first bytes of the board's replies"),
              ("NAK_", "reasons of a NAK (its second byte)"),
              ("FLAG_", "bits of the STATUS reply's flags byte"))
    for prefix, doc in groups:
        out.append(Define("", "", doc))
        for name, value in sorted(consts.items(), key=lambda kv: (kv[1], kv[0])):
            if name.startswith(prefix):
                out.append(Define("LINK_" + name, byte(value), ""))
    tail = {name: n for name, n in lk.STATUS_TAIL_FIELDS}
    if list(tail) != ["level", "flags", "taken", "reject_index", "reject_code"] or \
            tail != {"level": 1, "flags": 1, "taken": 2, "reject_index": 2, "reject_code": 1}:
        raise ValueError("the RTL's status payload is level(1) flags(1) taken(2) "
                         "reject_index(2) reject_code(1) after the positions")
    ident = [n for n, _ in lk.IDENT_FIELDS]
    if ident != ["version", "axes", "width", "depth", "clock_hz", "baud", "div"] or \
            [n for _, n in lk.IDENT_FIELDS] != [1, 1, 1, 2, 4, 4, 1]:
        raise ValueError("the RTL's ident payload is version(1) axes(1) width(1) depth(2) "
                         "clock_hz(4) baud(4) div(1)")
    out += [
        Define("", "", "payload sizes in bytes"),
        Define("LINK_COMMAND_BYTES", str(lk.COMMAND_BYTES), "payload of a COMMAND frame"),
        Define("LINK_IDENT_PAYLOAD", str(lk.IDENT_PAYLOAD), "payload of an IDENT reply"),
        Define("LINK_STATUS_TAIL", str(lk.status_payload(0)),
               "payload of a STATUS reply after the positions (4 bytes per axis)"),
        Define("", "", "the check: CRC-8 with this polynomial, initial value 0, MSB first"),
        Define("LINK_CRC_POLY", byte(0x07 if lk.crc8(b"\x01") == 0x07 else -1), ""),
    ]
    return out


CMD_TITLE = ("halfpoint_cmd.vh: the motion core's command layout and error codes",
             "model/halfpoint/spec/encoding.py", "encoding",
             "or CMD_<field>_LSB / _WIDTH for a field's bits.")
LINK_TITLE = ("halfpoint_link.vh: the serial link's frames, replies and flags",
              "model/halfpoint/spec/link.py", "link",
              "prefixed LINK_ (HALFPOINT_LINK_F_COMMAND).")


def render(items: list[Define], title: tuple = CMD_TITLE,
           guard: str = GUARD) -> str:
    """The header's text."""
    head, source, what, naming = title
    lines = [
        "// SPDX-License-Identifier: Apache-2.0",
        "// " + "=" * 76,
        f"// {head}",
        "// " + "=" * 76,
        "// GENERATED by `python -m halfpoint.flows.hdlgen` from",
        f"// {source}, the one definition of the {what}.  Do not",
        f"// edit: change {Path(source).name} and run the generator; `make lint` and `make test`",
        "// fail while this file differs from what the generator writes.",
        "//",
        "// Macros only (no module, no `default_nettype change): include it at the top",
        "// of a file, before the module.  Each macro is HALFPOINT_ and the name of the",
        f"// constant in {Path(source).name}, {naming}",
        "// " + "=" * 76,
        f"`ifndef {guard}",
        f"`define {guard}",
    ]
    width = max(len(PREFIX + d.name) for d in items if d.name)
    for d in items:
        if not d.name:
            lines += ["", f"// {d.doc}"]
            continue
        if d.doc:
            lines.append(f"//   {d.doc}")
        line = f"`define {PREFIX + d.name:<{width}} {d.value}"
        if len(line) > 100:     # a wide mask: continue the macro on the next line
            line = f"`define {PREFIX + d.name} \\\n    {d.value}"
        lines.append(line)
    lines += ["", f"`endif  // {guard}", ""]
    text = "\n".join(lines)
    for n, line in enumerate(text.splitlines(), 1):
        if len(line) > 100:
            raise ValueError(f"generated header line {n} is longer than 100 characters")
    return text


def generate(enc: ModuleType = encoding) -> str:
    return render(defines(enc))


def generate_link(lk: ModuleType = link) -> str:
    return render(link_defines(lk), LINK_TITLE, PREFIX + "LINK_VH")


def is_current(path: Path = HEADER, text: str | None = None) -> bool:
    return path.exists() and path.read_text() == (generate() if text is None else text)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(prog="python -m halfpoint.flows.hdlgen", description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--check", action="store_true",
                    help="do not write; exit 1 if the header is not what would be written")
    ap.add_argument("--out", type=Path, default=None,
                    help=f"command header path (default {HEADER})")
    ap.add_argument("--link-out", type=Path, default=None,
                    help=f"link header path (default {LINK_HEADER}; not handled when only "
                         "--out is given)")
    args = ap.parse_args(argv)
    jobs = []
    if args.out is not None or args.link_out is None:
        jobs.append((args.out or HEADER, generate(), "halfpoint.spec.encoding"))
    if args.link_out is not None or args.out is None:
        jobs.append((args.link_out or LINK_HEADER, generate_link(), "halfpoint.spec.link"))
    status = 0
    for path, text, source in jobs:
        if args.check:
            if is_current(path, text):
                print(f"hdlgen ok   {path} is current")
            else:
                print(f"hdlgen FAIL {path} is not what {source} gives: "
                      "run `python -m halfpoint.flows.hdlgen`")
                status = 1
        else:
            path.write_text(text)
            print(f"hdlgen wrote {path}")
    return status


if __name__ == "__main__":
    sys.exit(main())
