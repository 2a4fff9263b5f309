# SPDX-License-Identifier: Apache-2.0
"""The generated command header rtl/halfpoint_cmd.vh: it is current (what
``halfpoint.flows.hdlgen`` writes from ``halfpoint.spec.encoding`` now), its
macros describe the commands the host encoder writes, and the RTL decodes
commands through it (a core built with a changed header decodes differently,
and the core's source has no literal field position, opcode or error code).
"""

from __future__ import annotations

import random
import re
import shutil
import subprocess
from dataclasses import replace
from pathlib import Path

import pytest

from halfpoint.flows import hdlgen
from halfpoint.sim.env import RTL, setup_verilator_env
from halfpoint.spec import encoding as enc


def macros(text: str) -> dict[str, str]:
    """`define name value of a header (continued lines joined)."""
    text = text.replace("\\\n", " ")
    return {m[1]: m[2].strip() for m in re.finditer(r"^`define\s+(\w+)[ \t]*(.*)$", text, re.M)}


def number(value: str) -> int:
    """A Verilog number of the header (decimal, or sized 'd / 'h)."""
    m = re.fullmatch(r"(?:\d+)?'([dh])([0-9a-fA-F_]+)", value)
    if m:
        return int(m[2].replace("_", ""), 10 if m[1] == "d" else 16)
    return int(value)


def test_header_is_current():
    """The checked-in header is what the generator writes now: a changed
    encoding without a regenerated header fails here."""
    assert hdlgen.HEADER.read_text() == hdlgen.generate(), (
        "rtl/halfpoint_cmd.vh is not current: run `python -m halfpoint.flows.hdlgen`")
    assert hdlgen.main(["--check"]) == 0


def test_check_mode_detects_a_stale_header(tmp_path):
    stale = tmp_path / "halfpoint_cmd.vh"
    stale.write_text(re.sub(r"(`define HALFPOINT_OP_LINE\s+)\S+", r"\g<1>4'd7", hdlgen.generate()))
    assert hdlgen.main(["--check", "--out", str(stale)]) == 1
    fresh = tmp_path / "fresh.vh"
    assert hdlgen.main(["--out", str(fresh)]) == 0
    assert hdlgen.main(["--check", "--out", str(fresh)]) == 0


def test_header_lines_fit():
    for n, line in enumerate(hdlgen.HEADER.read_text().splitlines(), 1):
        assert len(line) <= 100, f"halfpoint_cmd.vh:{n} is {len(line)} characters"


def encode_from_header(m: dict[str, str], opcode: int, cont: bool,
                       fields: dict[str, int]) -> int:
    """A command built from the header's macros alone."""
    def put(cmd, lsb, width, value):
        return cmd | ((value & ((1 << width) - 1)) << lsb)
    p = "HALFPOINT_"
    cmd = put(0, number(m[p + "CMD_OPCODE_LSB"]), number(m[p + "CMD_OPCODE_WIDTH"]), opcode)
    if cont:
        cmd |= 1 << number(m[p + "FLAG_CONT_BIT"])
    for name, value in fields.items():
        if name.startswith("profile_"):
            key = name[len("profile_"):].upper()
            cmd = put(cmd, number(m[p + f"CMD_PROFILE_{key}_LSB"]),
                      number(m[p + f"CMD_PROFILE_{key}_WIDTH"]), value)
        elif name.startswith("HELIX"):
            k = int(name[5:])
            lsb = number(m[p + "CMD_ARC_HELIX0_LSB"]) + k * number(m[p + "CMD_ARC_HELIX_STRIDE"])
            cmd = put(cmd, lsb, number(m[p + "CMD_ARC_HELIX0_WIDTH"]), value)
        elif name.startswith("delta"):
            k = int(name[5:])
            lsb = number(m[p + "CMD_DELTA_LSB"]) + k * number(m[p + "CMD_DELTA_STRIDE"])
            cmd = put(cmd, lsb, number(m[p + "CMD_DELTA_WIDTH"]), value)
        else:
            cmd = put(cmd, number(m[p + f"CMD_ARC_{name}_LSB"]),
                      number(m[p + f"CMD_ARC_{name}_WIDTH"]), value)
    return cmd


def test_header_describes_the_encoder():
    """Commands built from the header's macros equal those of the host
    encoder, bit for bit; the reserved masks are the bits no field uses; the
    opcodes and error codes are encoding's."""
    m = macros(hdlgen.HEADER.read_text())
    p = "HALFPOINT_"
    assert number(m[p + "CMD_BITS"]) == enc.CMD_BITS
    assert number(m[p + "MAX_AXES"]) == enc.MAX_AXES
    for name in ("OP_LINE", "OP_ARC_CW", "OP_ARC_CCW", "OP_PROFILE"):
        assert number(m[p + name]) == getattr(enc, name)
    assert number(m[p + "PROFILE_DISTANCE_EXTRA"]) == enc.PROFILE_DISTANCE_EXTRA
    codes = {n: v for n, v in vars(enc).items() if n.startswith("E_") and isinstance(v, int)}
    assert codes and all(number(m[p + n]) == v for n, v in codes.items())
    assert number(m[p + "ERR_CODE_BITS"]) == enc.ERR_CODE_BITS
    rng = random.Random(11)
    full = (1 << enc.CMD_BITS) - 1
    for _ in range(200):
        cont = rng.random() < 0.5
        deltas = [rng.randrange(-(1 << 31), 1 << 31) for _ in range(enc.MAX_AXES)]
        line = enc.encode_line(deltas, cont=cont)
        fields = {f"delta{k}": d for k, d in enumerate(deltas)}
        assert encode_from_header(m, enc.OP_LINE, cont, fields) == line
        assert line & number(m[p + "CMD_RESERVED_LINE"]) == 0
        i, j, x, y = (rng.randrange(-(1 << 31), 1 << 31) for _ in range(4))
        cw = rng.random() < 0.5
        plane = (rng.randrange(8), rng.randrange(8))
        count = rng.randrange(1 << 32)
        helix = [rng.randrange(-(1 << 31), 1 << 31) for _ in range(enc.HELIX_SLOTS)]
        arc = enc.encode_arc(cw, i, j, x, y, cont=cont, plane=plane, count=count, helix=helix)
        op = enc.OP_ARC_CW if cw else enc.OP_ARC_CCW
        arc_fields = {"I": i, "J": j, "X": x, "Y": y, "U_AXIS": plane[0], "V_AXIS": plane[1],
                      "COUNT": count, **{f"HELIX{k}": h for k, h in enumerate(helix)}}
        assert number(m[p + "HELIX_SLOTS"]) == enc.HELIX_SLOTS
        assert encode_from_header(m, op, cont, arc_fields) == arc
        assert arc & number(m[p + "CMD_RESERVED_ARC"]) == 0
        values = [rng.randrange(1 << width) for _, _, width in enc.PROFILE_FIELDS]
        profile = enc.encode_profile(*values)
        named = {f"profile_{name}": v for (name, _, _), v in zip(enc.PROFILE_FIELDS, values)}
        assert encode_from_header(m, enc.OP_PROFILE, False, named) == profile
        assert profile & number(m[p + "CMD_RESERVED_PROFILE"]) == 0
    # every bit outside the fields is reserved: all ones in every field leaves none
    ones_line = encode_from_header(m, 0xF, True, {f"delta{k}": -1 for k in range(enc.MAX_AXES)})
    assert ones_line | number(m[p + "CMD_RESERVED_LINE"]) == full
    ones_arc = encode_from_header(m, 0xF, True, {"I": -1, "J": -1, "X": -1, "Y": -1,
                                                 "U_AXIS": -1, "V_AXIS": -1, "COUNT": -1,
                                                 **{f"HELIX{k}": -1
                                                    for k in range(enc.HELIX_SLOTS)}})
    assert ones_arc | number(m[p + "CMD_RESERVED_ARC"]) == full
    ones_profile = encode_from_header(m, 0xF, False, {f"profile_{name}": -1
                                                      for name, _, _ in enc.PROFILE_FIELDS})
    assert ones_profile | number(m[p + "CMD_RESERVED_PROFILE"]) == full


def test_core_has_no_literal_layout():
    """The core takes every field position, opcode and error code from the
    header: none is written in its source as a number."""
    src = (RTL / "halfpoint_core.v").read_text()
    code = "\n".join(line.split("//")[0] for line in src.splitlines())
    assert '`include "halfpoint_cmd.vh"' in src
    # no slice of the command by number, e.g. cmd[63:32] or cmd[64 + 32*k +: 32]
    assert not re.search(r"\b(cmd|s_axis_tdata)\s*\[\s*\d", code)
    # no opcode or error code written as a number
    assert not re.search(r"opcode\s*==\s*\d", code)
    assert not re.search(r"err_code\s*<=\s*[^;]*\d+'d", code)
    for name in ("OP_LINE", "OP_ARC_CW", "OP_ARC_CCW", "OP_PROFILE", "E_OPCODE", "E_FIELD",
                 "E_ARC_RADIUS", "E_ARC_RANGE", "E_ARC_END", "E_PROFILE", "E_PROFILE_FIELD",
                 "CMD_RESERVED_LINE", "CMD_RESERVED_ARC", "CMD_RESERVED_PROFILE",
                 "CMD_PROFILE_V_CRUISE_LSB", "CMD_PROFILE_D_STOP_LSB", "CMD_DELTA_LSB",
                 "CMD_ARC_I_LSB", "FLAG_CONT_BIT", "PROFILE_DISTANCE_EXTRA",
                 "CMD_ARC_U_AXIS_LSB", "CMD_ARC_V_AXIS_LSB", "CMD_ARC_COUNT_LSB",
                 "CMD_ARC_HELIX0_LSB", "CMD_ARC_HELIX_STRIDE", "HELIX_SLOTS", "E_HELIX",
                 "E_HELIX_COUNT"):
        assert f"`HALFPOINT_{name}" in code, f"the core does not use HALFPOINT_{name}"


PROBE = """\
`default_nettype none
`include "halfpoint_cmd.vh"
// offers a line's profile, the command `first`, the profile again and the
// command `second` to the core; prints each reject (err_code) and, after 300
// clocks, the position of axes 0 and 1 (W = 8 bits, unsigned)
module decode_probe (
    input wire clk
);
    reg  [8:0] clock_q = 9'd0;
    wire       rst = (clock_q < 9'd2);
    wire       valid = (clock_q >= 9'd2) && (clock_q <= 9'd5);
    wire [`HALFPOINT_CMD_BITS-1:0] data =
        (clock_q == 9'd3) ? {bits}'h{first:0{digits}x}
        : (clock_q == 9'd5) ? {bits}'h{second:0{digits}x} : {bits}'h{profile:0{digits}x};
    wire ready, busy, move, err, underrun, dry;
    wire [37:0] speed;
    wire [1:0]  step_pin, dir_pin;
    wire [15:0] pos;
    wire [2:0]  level;
    wire [`HALFPOINT_ERR_CODE_BITS-1:0] err_code;
    halfpoint_core #(
        .NA    (2),
        .W     (8),
        .DEPTH (4),
        .TW    (2),
        .DIV   (1)
    ) dut (
        .clk           (clk),
        .rst           (rst),
        .s_axis_tvalid (valid),
        .s_axis_tready (ready),
        .s_axis_tdata  (data),
        .cfg_steplen   (4'b0101),
        .cfg_stepspace (4'b0101),
        .cfg_dirsetup  (4'b0101),
        .cfg_dirhold   (4'b0101),
        .cfg_step_inv  (2'b00),
        .cfg_dir_inv   (2'b00),
        .feed_override (8'd128),
        .hold          (1'b0),
        .stop          (1'b0),
        .abort_now     (1'b0),
        .step_pin      (step_pin),
        .dir_pin       (dir_pin),
        .pos           (pos),
        .move          (move),
        .busy          (busy),
        .queue_level   (level),
        .err           (err),
        .err_code      (err_code),
        .underrun      (underrun),
        .dry           (dry),
        .speed         (speed)
    );
    always @(posedge clk) begin
        clock_q <= clock_q + 9'd1;
        if (err) $display("REJECT %0d", err_code);
        if (clock_q == 9'd300) begin
            $display("POS %0d %0d", pos[7:0], pos[15:8]);
            $finish;
        end
    end
endmodule
"""

MAIN = """\
#include "Vdecode_probe.h"
#include "verilated.h"
int main(int argc, char** argv) {
    VerilatedContext context;
    context.commandArgs(argc, argv);
    Vdecode_probe top{&context};
    for (long n = 0; n < 100000 && !context.gotFinish(); ++n) {
        top.clk = 0;
        top.eval();
        top.clk = 1;
        top.eval();
    }
    return context.gotFinish() ? 0 : 1;
}
"""


def run_probe(work: Path, header: str, first: int, second: int) -> list[str]:
    """Build the core from a copy of rtl/ with ``header`` as halfpoint_cmd.vh,
    feed it the two commands, return what the probe printed."""
    rtl = work / "rtl"
    rtl.mkdir(parents=True)
    for src in RTL.glob("*.v"):
        shutil.copy(src, rtl / src.name)
    (rtl / "halfpoint_cmd.vh").write_text(header)
    probe = work / "decode_probe.v"
    profile = enc.encode_profile(1 << 30, 0, 1 << 33, 1 << 16, 0, 0)
    probe.write_text(PROBE.format(bits=enc.CMD_BITS, digits=enc.CMD_BITS // 4,
                                  first=first, second=second, profile=profile))
    main = work / "main.cpp"
    main.write_text(MAIN)
    exe = setup_verilator_env()
    cmd = [str(exe), "--cc", "--exe", "--build", "-j", "2", "-Wno-fatal",
           "--top-module", "decode_probe", f"-I{rtl}", "-Mdir", str(work / "obj"),
           str(main), str(probe),
           *(str(rtl / f"halfpoint_{m}.v")
             for m in ("core", "arc", "line", "stepgen", "profile"))]
    proc = subprocess.run(cmd, capture_output=True, text=True, cwd=work)
    assert proc.returncode == 0, proc.stdout[-3000:] + proc.stderr[-3000:]
    proc = subprocess.run([str(work / "obj" / "Vdecode_probe")], capture_output=True,
                          text=True, cwd=work)
    assert proc.returncode == 0, proc.stdout + proc.stderr
    return [line for line in proc.stdout.splitlines() if line.startswith(("REJECT", "POS"))]


@pytest.mark.parametrize("mutated", [False, True], ids=["header", "mutated-header"])
def test_core_decodes_through_the_header(tmp_path, mutated):
    """Two commands, LINE (3, -2) with opcode OP_LINE and LINE (-1, 4) with an
    opcode the encoding does not use (9), through the core built with the
    generated header and with one in which OP_LINE is 9 and E_OPCODE is 7:
    the core runs the line whose opcode its header calls a line and rejects
    the other with its header's code, so it really decodes through the header."""
    spare = 9
    assert spare not in (enc.OP_LINE, enc.OP_ARC_CW, enc.OP_ARC_CCW)
    lsb, width = hdlgen.bit_run(enc.OPCODE_MASK, "opcode")
    first = enc.encode_line([3, -2])
    second = enc.encode_line([-1, 4])
    second = (second & ~(enc.OPCODE_MASK << lsb)) | (spare << lsb)
    items = hdlgen.defines()
    if mutated:
        swap = {"OP_LINE": f"{width}'d{spare}", "E_OPCODE": f"{enc.ERR_CODE_BITS}'d12"}
        items = [replace(d, value=swap.get(d.name, d.value)) for d in items]
    out = run_probe(tmp_path, hdlgen.render(items), first, second)
    if mutated:
        assert out == ["REJECT 12", "POS 255 4"], out          # (-1, 4) at W = 8
    else:
        assert out == [f"REJECT {enc.E_OPCODE}", "POS 3 254"], out     # (3, -2)


# --- the serial link's header (rtl/halfpoint_link.vh from halfpoint.spec.link) --------------

def test_link_header_is_current_and_derived(tmp_path):
    """rtl/halfpoint_link.vh is what the generator writes from spec/link.py now; every
    opcode, reply byte, NAK reason and flag of the module is in it with its value; a
    changed module gives a different header, which --check reports."""
    import types

    from halfpoint.spec import link

    text = hdlgen.LINK_HEADER.read_text()
    assert text == hdlgen.generate_link(), (
        "rtl/halfpoint_link.vh is not current: run `python -m halfpoint.flows.hdlgen`")
    m = {k: number(v) for k, v in macros(text).items() if v}
    for name, value in vars(link).items():
        if name.isupper() and isinstance(value, int) and name.split("_")[0] in (
                "F", "R", "NAK", "FLAG"):
            assert m[f"HALFPOINT_LINK_{name}"] == value, name
    assert m["HALFPOINT_LINK_PROTOCOL_VERSION"] == link.PROTOCOL_VERSION
    assert m["HALFPOINT_LINK_STATUS_TAIL"] == link.status_payload(0)
    assert m["HALFPOINT_LINK_IDENT_PAYLOAD"] == link.IDENT_PAYLOAD
    changed = types.ModuleType("link2")
    changed.__dict__.update(vars(link))
    changed.F_STOP = 0xCA
    assert hdlgen.generate_link(changed) != text
    stale = tmp_path / "halfpoint_link.vh"
    stale.write_text(hdlgen.generate_link(changed))
    assert hdlgen.main(["--check", "--link-out", str(stale)]) == 1
    for n, line in enumerate(text.splitlines(), 1):
        assert len(line) <= 100, f"halfpoint_link.vh:{n} is {len(line)} characters"


def test_link_crc_matches_the_rtl_polynomial():
    """The host's CRC-8 is the polynomial the header gives the RTL (0x07, MSB first):
    the check value of '123456789' for CRC-8/SMBUS is 0xF4."""
    from halfpoint.spec import link

    assert link.crc8(b"123456789") == 0xF4
    assert number(macros(hdlgen.LINK_HEADER.read_text())["HALFPOINT_LINK_CRC_POLY"]) == 0x07
