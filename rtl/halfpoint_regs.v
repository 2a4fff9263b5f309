// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// ============================================================================
// halfpoint_regs: the register file of the SoC interface, around one
// halfpoint_core (the bus wrappers halfpoint_wb and halfpoint_axil drive its
// access port)
// ============================================================================
// The register map (addresses, fields, resets) is defined once, in
// model/halfpoint/spec/regmap.py, and reaches this file through the generated
// rtl/halfpoint_regs.vh (HALFPOINT_REG_* macros); the cycle-accurate model is
// model/halfpoint/spec/regs.py, which the tests compare with this module on
// every clock.
//
// Access port: a request (req_valid with req_write, the byte address req_addr,
// req_wdata, req_wstrb) is taken on the edge it is valid at and answered on
// the next clock: resp_valid high for one clock with resp_error and
// resp_rdata.  An address not in the map (for this NA), a write to a
// read-only register, or a write without all four byte enables answers an
// error and changes nothing.  A read answers the value before the edge;
// reading POS_0 also copies every axis's position into the snapshot that
// POS_1.. read (one coherent set of positions).  Writing CMD_7 offers the
// command {CMD_7, CMD_6 .. CMD_0} to the core's stream on that edge: taken
// if the core is ready, else refused and IRQ_STATUS.OVERFLOW set.
//
// The core's inputs are these registers (CONTROL: hold, stop, abort,
// override; POLARITY; the per-axis STEP/DIR timing), acting from the clock
// after the write.  Interrupt events, at every edge: QUEUE_LOW while the queue
// level is below IRQ_THRESHOLD, ERROR when the core rejects a command, DONE
// when busy falls, OVERFLOW on a refused push; each sets its IRQ_STATUS bit
// (an event wins over a write-1-to-clear at the same edge); irq is high while
// a set IRQ_STATUS bit is enabled in IRQ_ENABLE.
//
// Parameters: those of halfpoint_core, passed to it (it stops elaboration on
// an illegal value).
//
// Reset: synchronous, active high (the core's too).
// ============================================================================
`include "halfpoint_cmd.vh"
`include "halfpoint_regs.vh"

module halfpoint_regs #(
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
     * Register access port (from a bus wrapper)
     */
    input  wire                                 req_valid,
    input  wire                                 req_write,
    input  wire [`HALFPOINT_REGS_ADDR_BITS-1:0] req_addr,
    input  wire [31:0]                          req_wdata,
    input  wire [3:0]                           req_wstrb,
    output reg                                  resp_valid,
    output reg                                  resp_error,
    output reg  [31:0]                          resp_rdata,

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
    localparam integer LEVEL_W = $clog2(DEPTH) + 1;
    localparam integer IRQ_W = `HALFPOINT_REG_IRQ_STATUS_BITS;
    localparam integer CMD_COUNT = `HALFPOINT_REG_CMD_COUNT;
    // constant registers
    localparam [31:0] GEOMETRY =
        (NA << `HALFPOINT_REG_GEOMETRY_AXES_LSB) | (W << `HALFPOINT_REG_GEOMETRY_WIDTH_LSB) |
        (TW << `HALFPOINT_REG_GEOMETRY_TIMING_WIDTH_LSB) | (DIV << `HALFPOINT_REG_GEOMETRY_DIV_LSB);
    localparam [31:0] QUEUES = (DEPTH << `HALFPOINT_REG_QUEUES_DEPTH_LSB) |
                               (MOVE_DEPTH << `HALFPOINT_REG_QUEUES_MOVE_DEPTH_LSB) |
                               (PROFILE_DEPTH << `HALFPOINT_REG_QUEUES_PROFILE_DEPTH_LSB);
    localparam [15:0] DEPTH_16 = DEPTH[15:0];
    // reset values of the timing settings (16-bit fields, TW bits kept)
    localparam [15:0] STEPLEN_RESET = `HALFPOINT_REG_STEP_TIMING_STEPLEN_RESET;
    localparam [15:0] STEPSPACE_RESET = `HALFPOINT_REG_STEP_TIMING_STEPSPACE_RESET;
    localparam [15:0] DIRSETUP_RESET = `HALFPOINT_REG_DIR_TIMING_DIRSETUP_RESET;
    localparam [15:0] DIRHOLD_RESET = `HALFPOINT_REG_DIR_TIMING_DIRHOLD_RESET;

    // ------------------------------------------------------------------
    // Registers
    // ------------------------------------------------------------------
    reg                       hold_q, stop_q, abort_q;
    reg  [7:0]                override_q;
    reg  [NA-1:0]             step_inv_q, dir_inv_q;
    reg  [NA*TW-1:0]          steplen_q, stepspace_q, dirsetup_q, dirhold_q;
    reg  [IRQ_W-1:0]          irq_status_q, irq_enable_q;
    reg  [15:0]               irq_threshold_q;
    reg  [32*CMD_COUNT-1:0]   cmd_q;
    reg  [NA*W-1:0]           snapshot_q;
    reg                       busy_before_q;

    // the core's outputs
    wire                      core_ready, core_busy, core_move, core_err, core_underrun;
    wire                      core_dry;
    wire [NA*W-1:0]           core_pos;
    wire [LEVEL_W-1:0]        core_level;
    wire [`HALFPOINT_ERR_CODE_BITS-1:0] core_err_code;
    wire [37:0]               core_speed;

    // ------------------------------------------------------------------
    // Address decoding
    // ------------------------------------------------------------------
    // is addr that of element index of an array register at base, stride apart?
    function is_element;
        input [A-1:0] addr;
        input [A-1:0] base;
        input [A-1:0] stride;
        input integer index;
        begin
            is_element = {{(32-A){1'b0}}, addr} ==
                         {{(32-A){1'b0}}, base} + {{(32-A){1'b0}}, stride} * index;
        end
    endfunction
    // a position, sign-extended to 32 bits
    function [31:0] extend;
        input [W-1:0] value;
        begin
            extend = {32{value[W-1]}};
            extend[W-1:0] = value;
        end
    endfunction
    // a TW-bit setting, zero-extended to a 16-bit field
    function [15:0] setting;
        input [TW-1:0] value;
        begin
            setting = 16'd0;
            setting[TW-1:0] = value;
        end
    endfunction

    wire [15:0] level_16 = {{(16-LEVEL_W){1'b0}}, core_level};
    // HOLDING: held at rest, from the hold's second clock (on its first the
    // profile stage's target is the one registered before, and the speed may
    // still rise by a step); then no step comes until HOLD is cleared
    reg         hold_before_q;
    wire        holding = hold_q && hold_before_q && (core_speed == 38'd0);

    reg                 known, writable;
    reg  [31:0]         read_value;
    reg                 hit_control, hit_polarity, hit_irq_status, hit_irq_enable;
    reg                 hit_irq_threshold, hit_pos_0;
    reg  [CMD_COUNT-1:0] hit_cmd;
    reg  [NA-1:0]       hit_step_timing, hit_dir_timing;
    integer k;
    always @(*) begin
        known = 1'b1;
        writable = 1'b0;
        read_value = 32'd0;
        hit_control = 1'b0;
        hit_polarity = 1'b0;
        hit_irq_status = 1'b0;
        hit_irq_enable = 1'b0;
        hit_irq_threshold = 1'b0;
        hit_pos_0 = 1'b0;
        hit_cmd = {CMD_COUNT{1'b0}};
        hit_step_timing = {NA{1'b0}};
        hit_dir_timing = {NA{1'b0}};
        case (req_addr)
            `HALFPOINT_REG_ID:       read_value = `HALFPOINT_REG_ID_VALUE;
            `HALFPOINT_REG_VERSION:  read_value = `HALFPOINT_REG_VERSION_VALUE;
            `HALFPOINT_REG_GEOMETRY: read_value = GEOMETRY;
            `HALFPOINT_REG_QUEUES:   read_value = QUEUES;
            `HALFPOINT_REG_CONTROL: begin
                writable = 1'b1;
                hit_control = 1'b1;
                read_value[`HALFPOINT_REG_CONTROL_HOLD_LSB] = hold_q;
                read_value[`HALFPOINT_REG_CONTROL_STOP_LSB] = stop_q;
                read_value[`HALFPOINT_REG_CONTROL_ABORT_LSB] = abort_q;
                read_value[`HALFPOINT_REG_CONTROL_OVERRIDE_LSB +:
                           `HALFPOINT_REG_CONTROL_OVERRIDE_WIDTH] = override_q;
            end
            `HALFPOINT_REG_POLARITY: begin
                writable = 1'b1;
                hit_polarity = 1'b1;
                read_value[`HALFPOINT_REG_POLARITY_STEP_INV_LSB +: NA] = step_inv_q;
                read_value[`HALFPOINT_REG_POLARITY_DIR_INV_LSB +: NA] = dir_inv_q;
            end
            `HALFPOINT_REG_STATUS: begin
                read_value[`HALFPOINT_REG_STATUS_BUSY_LSB] = core_busy;
                read_value[`HALFPOINT_REG_STATUS_READY_LSB] = core_ready;
                read_value[`HALFPOINT_REG_STATUS_HOLDING_LSB] = holding;
                read_value[`HALFPOINT_REG_STATUS_UNDERRUN_LSB] = core_underrun;
                read_value[`HALFPOINT_REG_STATUS_DRY_LSB] = core_dry;
                read_value[`HALFPOINT_REG_STATUS_ERR_CODE_LSB +:
                           `HALFPOINT_REG_STATUS_ERR_CODE_WIDTH] = core_err_code;
            end
            `HALFPOINT_REG_QUEUE: begin
                read_value[`HALFPOINT_REG_QUEUE_LEVEL_LSB +: 16] = level_16;
                read_value[`HALFPOINT_REG_QUEUE_FREE_LSB +: 16] = DEPTH_16 - level_16;
            end
            `HALFPOINT_REG_IRQ_STATUS: begin
                writable = 1'b1;
                hit_irq_status = 1'b1;
                read_value[IRQ_W-1:0] = irq_status_q;
            end
            `HALFPOINT_REG_IRQ_ENABLE: begin
                writable = 1'b1;
                hit_irq_enable = 1'b1;
                read_value[IRQ_W-1:0] = irq_enable_q;
            end
            `HALFPOINT_REG_IRQ_THRESHOLD: begin
                writable = 1'b1;
                hit_irq_threshold = 1'b1;
                read_value[`HALFPOINT_REG_IRQ_THRESHOLD_LEVEL_LSB +: 16] = irq_threshold_q;
            end
            `HALFPOINT_REG_SPEED:    read_value = core_speed[37:6];
            default:                 known = 1'b0;
        endcase
        // the arrays
        for (k = 0; k < CMD_COUNT; k = k + 1) begin
            if (is_element(req_addr, `HALFPOINT_REG_CMD, `HALFPOINT_REG_CMD_STRIDE, k)) begin
                known = 1'b1;
                writable = 1'b1;
                hit_cmd[k] = 1'b1;
                read_value = cmd_q[32*k +: 32];
            end
        end
        for (k = 0; k < NA; k = k + 1) begin
            if (is_element(req_addr, `HALFPOINT_REG_POS, `HALFPOINT_REG_POS_STRIDE, k)) begin
                known = 1'b1;
                hit_pos_0 = (k == 0);
                read_value = extend(k == 0 ? core_pos[W-1:0] : snapshot_q[k*W +: W]);
            end
            if (is_element(req_addr, `HALFPOINT_REG_STEP_TIMING,
                           `HALFPOINT_REG_STEP_TIMING_STRIDE, k)) begin
                known = 1'b1;
                writable = 1'b1;
                hit_step_timing[k] = 1'b1;
                read_value[`HALFPOINT_REG_STEP_TIMING_STEPLEN_LSB +: 16] =
                    setting(steplen_q[k*TW +: TW]);
                read_value[`HALFPOINT_REG_STEP_TIMING_STEPSPACE_LSB +: 16] =
                    setting(stepspace_q[k*TW +: TW]);
            end
            if (is_element(req_addr, `HALFPOINT_REG_DIR_TIMING,
                           `HALFPOINT_REG_DIR_TIMING_STRIDE, k)) begin
                known = 1'b1;
                writable = 1'b1;
                hit_dir_timing[k] = 1'b1;
                read_value[`HALFPOINT_REG_DIR_TIMING_DIRSETUP_LSB +: 16] =
                    setting(dirsetup_q[k*TW +: TW]);
                read_value[`HALFPOINT_REG_DIR_TIMING_DIRHOLD_LSB +: 16] =
                    setting(dirhold_q[k*TW +: TW]);
            end
        end
    end

    wire bad_request = !known || (req_write && (!writable || req_wstrb != 4'hF));
    wire write = req_valid && req_write && !bad_request;
    wire read = req_valid && !req_write && !bad_request;

    // ------------------------------------------------------------------
    // Command push and interrupt events
    // ------------------------------------------------------------------
    wire                  push = write && hit_cmd[CMD_COUNT-1];
    wire [IRQ_W-1:0]      irq_event;
    wire [IRQ_W-1:0]      irq_clear = (write && hit_irq_status) ? req_wdata[IRQ_W-1:0]
                                                                 : {IRQ_W{1'b0}};
    assign irq_event[`HALFPOINT_REG_IRQ_STATUS_QUEUE_LOW_LSB] = level_16 < irq_threshold_q;
    assign irq_event[`HALFPOINT_REG_IRQ_STATUS_ERROR_LSB] = core_err;
    assign irq_event[`HALFPOINT_REG_IRQ_STATUS_DONE_LSB] = busy_before_q && !core_busy;
    assign irq_event[`HALFPOINT_REG_IRQ_STATUS_OVERFLOW_LSB] = push && !core_ready;
    assign irq = |(irq_status_q & irq_enable_q);

    // ------------------------------------------------------------------
    // Register writes, the response, the snapshot
    // ------------------------------------------------------------------
    integer j;      // the loops of this block (k is the decoder's)
    always @(posedge clk) begin
        if (rst) begin
            hold_q <= `HALFPOINT_REG_CONTROL_HOLD_RESET;
            stop_q <= `HALFPOINT_REG_CONTROL_STOP_RESET;
            abort_q <= `HALFPOINT_REG_CONTROL_ABORT_RESET;
            override_q <= `HALFPOINT_REG_CONTROL_OVERRIDE_RESET;
            step_inv_q <= {NA{1'b0}};
            dir_inv_q <= {NA{1'b0}};
            irq_status_q <= {IRQ_W{1'b0}};
            irq_enable_q <= {IRQ_W{1'b0}};
            irq_threshold_q <= `HALFPOINT_REG_IRQ_THRESHOLD_LEVEL_RESET;
            cmd_q <= {32*CMD_COUNT{1'b0}};
            snapshot_q <= {NA*W{1'b0}};
            busy_before_q <= 1'b0;
            hold_before_q <= 1'b0;
            resp_valid <= 1'b0;
            resp_error <= 1'b0;
            resp_rdata <= 32'd0;
            for (j = 0; j < NA; j = j + 1) begin
                steplen_q[j*TW +: TW] <= STEPLEN_RESET[TW-1:0];
                stepspace_q[j*TW +: TW] <= STEPSPACE_RESET[TW-1:0];
                dirsetup_q[j*TW +: TW] <= DIRSETUP_RESET[TW-1:0];
                dirhold_q[j*TW +: TW] <= DIRHOLD_RESET[TW-1:0];
            end
        end else begin
            if (write && hit_control) begin
                hold_q <= req_wdata[`HALFPOINT_REG_CONTROL_HOLD_LSB];
                stop_q <= req_wdata[`HALFPOINT_REG_CONTROL_STOP_LSB];
                abort_q <= req_wdata[`HALFPOINT_REG_CONTROL_ABORT_LSB];
                override_q <= req_wdata[`HALFPOINT_REG_CONTROL_OVERRIDE_LSB +:
                                        `HALFPOINT_REG_CONTROL_OVERRIDE_WIDTH];
            end
            if (write && hit_polarity) begin
                step_inv_q <= req_wdata[`HALFPOINT_REG_POLARITY_STEP_INV_LSB +: NA];
                dir_inv_q <= req_wdata[`HALFPOINT_REG_POLARITY_DIR_INV_LSB +: NA];
            end
            if (write && hit_irq_enable) irq_enable_q <= req_wdata[IRQ_W-1:0];
            if (write && hit_irq_threshold) begin
                irq_threshold_q <= req_wdata[`HALFPOINT_REG_IRQ_THRESHOLD_LEVEL_LSB +: 16];
            end
            irq_status_q <= (irq_status_q & ~irq_clear) | irq_event;
            for (j = 0; j < CMD_COUNT; j = j + 1) begin
                if (write && hit_cmd[j]) cmd_q[32*j +: 32] <= req_wdata;
            end
            for (j = 0; j < NA; j = j + 1) begin
                if (write && hit_step_timing[j]) begin
                    steplen_q[j*TW +: TW] <=
                        req_wdata[`HALFPOINT_REG_STEP_TIMING_STEPLEN_LSB +: TW];
                    stepspace_q[j*TW +: TW] <=
                        req_wdata[`HALFPOINT_REG_STEP_TIMING_STEPSPACE_LSB +: TW];
                end
                if (write && hit_dir_timing[j]) begin
                    dirsetup_q[j*TW +: TW] <=
                        req_wdata[`HALFPOINT_REG_DIR_TIMING_DIRSETUP_LSB +: TW];
                    dirhold_q[j*TW +: TW] <=
                        req_wdata[`HALFPOINT_REG_DIR_TIMING_DIRHOLD_LSB +: TW];
                end
            end
            if (read && hit_pos_0) snapshot_q <= core_pos;
            busy_before_q <= core_busy;
            hold_before_q <= hold_q;
            resp_valid <= req_valid;
            resp_error <= req_valid && bad_request;
            resp_rdata <= read ? read_value : 32'd0;
        end
    end

    // ------------------------------------------------------------------
    // The core
    // ------------------------------------------------------------------
    halfpoint_core #(
        .NA            (NA),
        .W             (W),
        .DEPTH         (DEPTH),
        .TW            (TW),
        .DIV           (DIV),
        .MOVE_DEPTH    (MOVE_DEPTH),
        .PROFILE_DEPTH (PROFILE_DEPTH),
        .PWM_BITS      (PWM_BITS)
    ) u_core (
        .clk           (clk),
        .rst           (rst),
        .s_axis_tvalid (push),
        .s_axis_tready (core_ready),
        .s_axis_tdata  ({req_wdata, cmd_q[32*(CMD_COUNT-1)-1:0]}),
        .cfg_steplen   (steplen_q),
        .cfg_stepspace (stepspace_q),
        .cfg_dirsetup  (dirsetup_q),
        .cfg_dirhold   (dirhold_q),
        .cfg_step_inv  (step_inv_q),
        .cfg_dir_inv   (dir_inv_q),
        .feed_override (override_q),
        .hold          (hold_q),
        .stop          (stop_q),
        .abort_now     (abort_q),
        .step_pin      (step_pin),
        .dir_pin       (dir_pin),
        .pos           (core_pos),
        .move          (core_move),
        .busy          (core_busy),
        .queue_level   (core_level),
        .err           (core_err),
        .err_code      (core_err_code),
        .underrun      (core_underrun),
        .dry           (core_dry),
        .speed         (core_speed),
        .spindle_enable  (spindle_enable),
        .spindle_reverse (spindle_reverse),
        .spindle_pwm     (spindle_pwm),
        .coolant_mist    (coolant_mist),
        .coolant_flood   (coolant_flood)
    );

    // the move strobe has no register (positions are read from pos)
    wire unused_move = core_move;
endmodule

`default_nettype wire
