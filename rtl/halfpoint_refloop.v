// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// ============================================================================
// halfpoint_refloop: the smallest loop the half-point method needs, as a
// timing reference for `make synth`
// ============================================================================
// One WR-bit register updated every clock by an add whose operand is chosen
// by the register's own sign bit: the recurrence at the heart of every
// interpolator here (deviation F, D1/D2, E_i: sign -> select -> one add).
// `make synth` places and routes it with the same flow and devices as the
// cores, so the report can show each core's Fmax as a fraction of what the
// fabric allows for this loop.  It has no other use.
//
//   FOLD = 0  acc <= acc + (acc[WR-1] ? a : b)      plain 2:1 mux, then add
//   FOLD = 1  acc <= acc + (acc[WR-1] ? a : -a)      one adder whose operand
//             is a XOR-ed with the sign (add/subtract); the XOR sits in the
//             LUTs in front of the carry chain, as the mux of FOLD = 0 does,
//             but needs one adder and no second operand register
//
// a (and b for FOLD = 0) are registered, loaded while `load` is high; acc is
// cleared by rst (a synchronous reset maps onto the flip-flops' own reset
// input), so the only logic in the loop is the one described above.
//
// Parameters: see the comment above each (an illegal value stops
// elaboration).
//
// Reset: synchronous, active high, clears acc (acc then runs from 0 with
// whatever a and b hold).
// ============================================================================
module halfpoint_refloop #(
    // register width, 8..64 (the arc unit's datapath is W+2 = 34 bits)
    parameter integer WR   = 34,
    // 0: operand chosen by a 2:1 mux; 1: add/subtract of one operand (above)
    parameter integer FOLD = 0
) (
    input  wire          clk,
    input  wire          rst,

    /*
     * Operands, registered while load is high
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
            halfpoint_refloop_illegal_parameter_WR_must_be_8_to_64 u_bad ();
        end
        if (FOLD != 0 && FOLD != 1) begin : g_bad_fold
            halfpoint_refloop_illegal_parameter_FOLD_must_be_0_or_1 u_bad ();
        end
    endgenerate

    reg [WR-1:0] a_q;
    reg [WR-1:0] acc_q;
    wire [WR-1:0] acc_n;

    generate
        if (FOLD == 0) begin : g_mux
            reg [WR-1:0] b_q;
            always @(posedge clk) begin
                if (load) begin
                    b_q <= b;
                end
            end
            assign acc_n = acc_q + (acc_q[WR-1] ? a_q : b_q);
        end else begin : g_fold
            wire unused_b = ^b;     // b is not used by this loop
            assign acc_n = acc_q + ({WR{~acc_q[WR-1]}} ^ a_q) + {{(WR-1){1'b0}}, ~acc_q[WR-1]};
        end
    endgenerate

    always @(posedge clk) begin
        if (rst) begin
            acc_q <= {WR{1'b0}};
        end else begin
            acc_q <= acc_n;
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
