// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// ============================================================================
// halfpoint_refloop_ccu2c: the reference loop of halfpoint_refloop (FOLD = 1)
// with the sign select folded into the ECP5 carry chain by hand -- a timing
// reference for `make synth` on ECP5 only
// ============================================================================
// acc <= acc + (acc[WR-1] ? a : -a), the same function, ports and reset as
// halfpoint_refloop with FOLD = 1, but built from Lattice ECP5 CCU2C cells
// (two LUT4 + carry each) so that the add/subtract select costs no logic in
// front of the chain: each bit's LUT4 computes the propagate
// acc[i] ^ a[i] ^ ~s from its own inputs A = acc[i], B = a[i], C = s
// (s = acc[WR-1]), D = 1, and the generate is A (when the propagate is 0, the
// two operand bits are equal).  The first half-cell makes the carry-in ~s
// (propagate 0, generate ~A with A = s).  Yosys keeps a Verilog XOR in a
// separate LUT in front of the chain (see halfpoint_refloop), so this is the
// loop's best case on this fabric: what the report's "of ref" column divides
// by on ECP5.
//
// Simulation needs the ECP5 cell models (Yosys's share/ecp5/cells_sim.v);
// tb/test_synth_flow.py proves it equivalent to halfpoint_refloop (FOLD = 1)
// with Yosys's equivalence checker.  It is not part of the core.
//
// INIT encoding (CCU2C): LUT4 index {D, C, B, A}; the LUT2 behind the
// generate uses INIT[3:0], index {B, A}.
//   bit cell   16'h69AA: D = 1 half 0x69 = ~(A ^ B ^ C); INIT[3:0] = 0xA = A
//   carry-in   16'h0005: D = 1 half 0 (propagate 0); INIT[3:0] = 0x5 = ~A
//
// Parameters: see the comment above each (an illegal value stops
// elaboration).
//
// Reset: synchronous, active high, clears acc.
// ============================================================================
module halfpoint_refloop_ccu2c #(
    // register width, 8..64
    parameter integer WR = 34
) (
    input  wire          clk,
    input  wire          rst,

    /*
     * Operands, registered while load is high (b is not used, as in FOLD = 1)
     */
    input  wire          load,
    input  wire [WR-1:0] a,
    input  wire [WR-1:0] b,

    /*
     * The loop register
     */
    output wire [WR-1:0] acc
);
    generate
        if (WR < 8 || WR > 64) begin : g_bad_wr
            halfpoint_refloop_ccu2c_illegal_parameter_WR_must_be_8_to_64 u_bad ();
        end
    endgenerate

    // slot 0: carry-in; slot j = 1..WR: bit j-1; slots above WR unused
    localparam integer CELLS = (WR + 1) / 2 + 1;    // CCU2C cells
    localparam integer SLOTS = 2 * CELLS;           // half-cell slots

    reg  [WR-1:0]    a_q;
    reg  [WR-1:0]    acc_q;
    wire             sign = acc_q[WR-1];
    wire [SLOTS-1:0] slot_a, slot_b, slot_sum;
    wire [CELLS:0]   carry;
    wire             unused_b = ^b;                 // b is not used by this loop

    assign slot_a = {{(SLOTS - WR - 1){1'b0}}, acc_q, sign};
    assign slot_b = {{(SLOTS - WR - 1){1'b0}}, a_q, 1'b0};
    assign carry[0] = 1'b0;

    genvar k;
    generate
        for (k = 0; k < CELLS; k = k + 1) begin : g_cell
            localparam [15:0] INIT_LOW  = (k == 0) ? 16'h0005 : 16'h69AA;
            localparam [15:0] INIT_HIGH = (2 * k + 1 <= WR) ? 16'h69AA : 16'h0000;
            CCU2C #(
                .INIT0     (INIT_LOW),
                .INIT1     (INIT_HIGH),
                .INJECT1_0 ("NO"),
                .INJECT1_1 ("NO")
            ) u_ccu (
                .CIN  (carry[k]),
                .A0   (slot_a[2 * k]),
                .B0   (slot_b[2 * k]),
                .C0   (sign),
                .D0   (1'b1),
                .A1   (slot_a[2 * k + 1]),
                .B1   (slot_b[2 * k + 1]),
                .C1   (sign),
                .D1   (1'b1),
                .S0   (slot_sum[2 * k]),
                .S1   (slot_sum[2 * k + 1]),
                .COUT (carry[k + 1])
            );
        end
    endgenerate

    wire unused_ok = &{1'b0, unused_b, slot_sum[0], slot_sum[SLOTS-1:WR+1], carry[CELLS]};

    always @(posedge clk) begin
        if (rst) begin
            acc_q <= {WR{1'b0}};
        end else begin
            acc_q <= slot_sum[WR:1];
        end
    end
    always @(posedge clk) begin
        if (load) begin
            a_q <= a;
        end
    end
    assign acc = acc_q;
endmodule
`default_nettype wire
