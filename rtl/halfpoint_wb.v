// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// ============================================================================
// halfpoint_wb: the motion core on a Wishbone B4 slave (classic cycles, 32-bit
// data, word addresses: the bus LiteX uses), over the register file
// halfpoint_regs
// ============================================================================
// Classic single reads and writes: the master holds CYC, STB, WE, ADR, DAT_W
// and SEL until ACK or ERR.  ADR is a word address (byte address / 4) within
// the register window; the interconnect decodes the base.  The request is
// registered here and answered by the register file on the clock after, so
// ACK or ERR comes two clocks after STB (no wait states beyond those; STALL
// is not used, CTI and BTE are not needed: a burst runs as single cycles).
// ERR instead of ACK: an address not in the register map, a write to a
// read-only register or a write without all four SEL bits; nothing changes.
// A cycle the master drops (CYC low) before its answer still completes in the
// register file; the answer is then not driven.
//
// Register map, interrupt and the core's behaviour: halfpoint_regs and the
// README ("Putting it in a SoC").
//
// Parameters: those of halfpoint_core (see halfpoint_regs).
//
// Reset: synchronous, active high.
// ============================================================================
`include "halfpoint_regs.vh"

module halfpoint_wb #(
    // number of axes, 2..6 (arcs move axes 0 and 1)
    parameter integer NA    = 3,
    // coordinate and position width in bits, 8..32 (signed coordinates)
    parameter integer W     = 32,
    // command queue depth in commands, a power of two, 2..256
    parameter integer DEPTH = 16,
    // width of the STEP/DIR timing settings in bits, 2..16
    parameter integer TW    = 16,
    // speed-step tick of the profile stage: 2^DIV clocks, 1..24
    parameter integer DIV   = 12,
    // move queue depth in moves, 2..16
    parameter integer MOVE_DEPTH    = 4,
    // profile queue depth in segments, 1..8
    parameter integer PROFILE_DEPTH = 2,
    // spindle/laser PWM period of 2^PWM_BITS clocks, 4..16
    parameter integer PWM_BITS      = 10
) (
    input  wire                                 clk,
    input  wire                                 rst,

    /*
     * Wishbone B4 slave, classic cycles
     */
    input  wire                                 wb_cyc,
    input  wire                                 wb_stb,
    input  wire                                 wb_we,
    // word address in the register window
    input  wire [`HALFPOINT_REGS_ADDR_BITS-3:0] wb_adr,
    input  wire [31:0]                          wb_dat_w,
    input  wire [3:0]                           wb_sel,
    output wire [31:0]                          wb_dat_r,
    output wire                                 wb_ack,
    output wire                                 wb_err,

    /*
     * Interrupt (level, active high)
     */
    output wire                                 irq,

    /*
     * STEP/DIR outputs
     */
    output wire [NA-1:0]                        step_pin,
    output wire [NA-1:0]                        dir_pin,

    /*
     * Spindle, laser and coolant outputs (halfpoint_core's, set by OUTPUT commands)
     */
    output wire                                 spindle_enable,
    output wire                                 spindle_reverse,
    output wire                                 spindle_pwm,
    output wire                                 coolant_mist,
    output wire                                 coolant_flood
);

    localparam integer A = `HALFPOINT_REGS_ADDR_BITS;

    // the request handed to the register file, and a request outstanding
    reg          req_valid_q, req_write_q, pending_q;
    reg  [A-1:0] req_addr_q;
    reg  [31:0]  req_wdata_q;
    reg  [3:0]   req_wstrb_q;
    wire         resp_valid, resp_error;
    wire [31:0]  resp_rdata;

    always @(posedge clk) begin
        if (rst) begin
            req_valid_q <= 1'b0;
            pending_q <= 1'b0;
        end else begin
            req_valid_q <= wb_cyc && wb_stb && !pending_q;
            if (wb_cyc && wb_stb && !pending_q) pending_q <= 1'b1;
            else if (resp_valid) pending_q <= 1'b0;
        end
    end
    always @(posedge clk) begin
        if (!pending_q) begin
            req_write_q <= wb_we;
            req_addr_q <= {wb_adr, 2'b00};
            req_wdata_q <= wb_dat_w;
            req_wstrb_q <= wb_sel;
        end
    end

    assign wb_ack = wb_cyc && resp_valid && !resp_error;
    assign wb_err = wb_cyc && resp_valid && resp_error;
    assign wb_dat_r = resp_rdata;

    halfpoint_regs #(
        .NA            (NA),
        .W             (W),
        .DEPTH         (DEPTH),
        .TW            (TW),
        .DIV           (DIV),
        .MOVE_DEPTH    (MOVE_DEPTH),
        .PROFILE_DEPTH (PROFILE_DEPTH),
        .PWM_BITS      (PWM_BITS)
    ) u_regs (
        .clk           (clk),
        .rst           (rst),
        .req_valid     (req_valid_q),
        .req_write     (req_write_q),
        .req_addr      (req_addr_q),
        .req_wdata     (req_wdata_q),
        .req_wstrb     (req_wstrb_q),
        .resp_valid    (resp_valid),
        .resp_error    (resp_error),
        .resp_rdata    (resp_rdata),
        .irq           (irq),
        .step_pin      (step_pin),
        .dir_pin       (dir_pin),
        .spindle_enable  (spindle_enable),
        .spindle_reverse (spindle_reverse),
        .spindle_pwm     (spindle_pwm),
        .coolant_mist    (coolant_mist),
        .coolant_flood   (coolant_flood)
    );

endmodule

`default_nettype wire
