// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// ============================================================================
// halfpoint_axil: the motion core on an AXI4-Lite slave (32-bit data, byte
// addresses), over the register file halfpoint_regs
// ============================================================================
// One transaction at a time: a write is taken when both AW and W are valid
// (AWREADY and WREADY together), a read when AR is valid; when both wait, the
// kind not served last goes first.  The request is registered here and answered
// by the register file on the clock after; B (or R) is then held until the
// master takes it, and the next transaction is taken after that.  BRESP or
// RRESP is SLVERR for an address not in the register map (including an
// unaligned one), a write to a read-only register or a write without all four
// WSTRB bits; nothing changes then.  AWPROT and ARPROT are not used (not
// ports).  Only the register window's address bits are ports: the
// interconnect decodes the base.
//
// Register map, interrupt and the core's behaviour: halfpoint_regs and the
// README ("Putting it in a SoC").
//
// Parameters: those of halfpoint_core (see halfpoint_regs).
//
// Reset: synchronous, active high.
// ============================================================================
`include "halfpoint_regs.vh"

module halfpoint_axil #(
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
     * AXI4-Lite slave: write address, write data, write response
     */
    input  wire [`HALFPOINT_REGS_ADDR_BITS-1:0] s_axil_awaddr,
    input  wire                                 s_axil_awvalid,
    output wire                                 s_axil_awready,
    input  wire [31:0]                          s_axil_wdata,
    input  wire [3:0]                           s_axil_wstrb,
    input  wire                                 s_axil_wvalid,
    output wire                                 s_axil_wready,
    output reg  [1:0]                           s_axil_bresp,
    output reg                                  s_axil_bvalid,
    input  wire                                 s_axil_bready,

    /*
     * AXI4-Lite slave: read address, read data
     */
    input  wire [`HALFPOINT_REGS_ADDR_BITS-1:0] s_axil_araddr,
    input  wire                                 s_axil_arvalid,
    output wire                                 s_axil_arready,
    output reg  [31:0]                          s_axil_rdata,
    output reg  [1:0]                           s_axil_rresp,
    output reg                                  s_axil_rvalid,
    input  wire                                 s_axil_rready,

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
    localparam [1:0] RESP_OKAY = 2'b00;
    localparam [1:0] RESP_SLVERR = 2'b10;

    // busy_q: a transaction taken and not yet answered to the master
    reg          busy_q, last_write_q;
    reg          req_valid_q, req_write_q;
    reg  [A-1:0] req_addr_q;
    reg  [31:0]  req_wdata_q;
    reg  [3:0]   req_wstrb_q;
    wire         resp_valid, resp_error;
    wire [31:0]  resp_rdata;

    wire write_waiting = s_axil_awvalid && s_axil_wvalid;
    wire take_write = !busy_q && write_waiting && (!s_axil_arvalid || !last_write_q);
    wire take_read = !busy_q && s_axil_arvalid && !take_write;

    assign s_axil_awready = take_write;
    assign s_axil_wready = take_write;
    assign s_axil_arready = take_read;

    always @(posedge clk) begin
        if (rst) begin
            busy_q <= 1'b0;
            last_write_q <= 1'b0;
            req_valid_q <= 1'b0;
            s_axil_bvalid <= 1'b0;
            s_axil_rvalid <= 1'b0;
        end else begin
            req_valid_q <= take_write || take_read;
            if (take_write || take_read) begin
                busy_q <= 1'b1;
                last_write_q <= take_write;
            end
            if (resp_valid && req_write_q) s_axil_bvalid <= 1'b1;
            else if (s_axil_bready) s_axil_bvalid <= 1'b0;
            if (resp_valid && !req_write_q) s_axil_rvalid <= 1'b1;
            else if (s_axil_rready) s_axil_rvalid <= 1'b0;
            if ((s_axil_bvalid && s_axil_bready) || (s_axil_rvalid && s_axil_rready)) begin
                busy_q <= 1'b0;
            end
        end
    end
    always @(posedge clk) begin
        if (take_write || take_read) begin
            req_write_q <= take_write;
            req_addr_q <= take_write ? s_axil_awaddr : s_axil_araddr;
            req_wdata_q <= s_axil_wdata;
            req_wstrb_q <= s_axil_wstrb;
        end
        if (resp_valid) begin
            s_axil_bresp <= resp_error ? RESP_SLVERR : RESP_OKAY;
            s_axil_rresp <= resp_error ? RESP_SLVERR : RESP_OKAY;
            s_axil_rdata <= resp_rdata;
        end
    end

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
