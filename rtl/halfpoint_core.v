// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// ============================================================================
// halfpoint_core: the motion core -- command stream, queue, sequencing of
// arcs and lines, feed rate, STEP/DIR outputs and absolute positions
// ============================================================================
// Commands arrive as single 256-bit beats on an AXI4-Stream slave; their
// layout, opcodes and the error codes come from halfpoint_cmd.vh, generated
// from the one definition in model/halfpoint/spec/encoding.py (tabled in the
// README), so no field position is written here.  They wait in a queue of
// DEPTH entries; a dispatcher hands them in program order to the arc unit (XY
// plane, axes 0 and 1) or the line unit (all NA axes), with at most one
// command in flight (handed over, not yet started), so that a unit's pending
// segment starts at the edge of the previous segment's last move: no idle
// clock at a boundary when the next segment has been validated in time.
//
// The running unit moves when `go`:
//   * the feed credit covers the move's cost (2^24 for an axis move or a line
//     iteration, round(sqrt(2) * 2^24) for a diagonal arc move), the credit
//     growing by rate * k per clock, k in {0, 1, 2} from the feed override
//     (percent, 0..200; 0 holds the motion; registered, so a change acts one
//     clock later), capped at 2^26;
//   * and every axis the move steps has its STEP/DIR generator ready for the
//     move's direction (otherwise the move waits: no step dropped or merged).
// Positions count every step.  Rejected commands (bad opcode or reserved
// bits, field out of range, arc validator rejects) make no motion, set
// err_code and pulse err; the rest of the program runs.  A line whose deltas
// are all zero is a no-op.  underrun is set (sticky until reset) when a
// segment flagged CONT ended and no segment started at that edge.
// abort_now (level): at each edge while it is high no move is made, the queue,
// the command in flight and both units' segments are dropped and the feed
// credit is cleared; tready is low.  A STEP pulse already started completes
// with its full timing; positions keep every step made.
//
// Parameters: see the comment above each (an illegal value stops
// elaboration).
//
// Reset: synchronous, active high.
// ============================================================================
`include "halfpoint_cmd.vh"

module halfpoint_core #(
    // number of axes, 2..6 (arcs move axes 0 and 1)
    parameter integer NA    = 3,
    // coordinate and position width in bits, 8..32 (signed coordinates)
    parameter integer W     = 32,
    // command queue depth in commands, a power of two, 2..256
    parameter integer DEPTH = 16,
    // width of the STEP/DIR timing settings in bits, 2..16
    parameter integer TW    = 16
) (
    input  wire                           clk,
    input  wire                           rst,

    /*
     * Command stream (AXI4-Stream slave, one command per beat)
     */
    input  wire                           s_axis_tvalid,
    output wire                           s_axis_tready,
    input  wire [`HALFPOINT_CMD_BITS-1:0] s_axis_tdata,

    /*
     * STEP/DIR configuration: timing per axis (axis k in bits k*TW +: TW), polarity
     */
    input  wire [NA*TW-1:0]               cfg_steplen,
    input  wire [NA*TW-1:0]               cfg_stepspace,
    input  wire [NA*TW-1:0]               cfg_dirsetup,
    input  wire [NA*TW-1:0]               cfg_dirhold,
    input  wire [NA-1:0]                  cfg_step_inv,
    input  wire [NA-1:0]                  cfg_dir_inv,

    /*
     * Motion control
     */
    // feed override in percent; values above 200 act as 200
    input  wire [7:0]                     feed_override,
    // stop now: no move, queue and pending segments dropped (level)
    input  wire                           abort_now,

    /*
     * STEP/DIR outputs
     */
    output wire [NA-1:0]                  step_pin,
    output wire [NA-1:0]                  dir_pin,

    /*
     * Status
     */
    // absolute position per axis (axis k in bits k*W +: W)
    output reg  [NA*W-1:0]                pos,
    // a move was made at the last edge
    output reg                            move,
    output wire                           busy,
    output wire [$clog2(DEPTH):0]         queue_level,
    // a command was rejected at the last edge
    output reg                            err,
    // code of the last rejected command (HALFPOINT_E_* of halfpoint_cmd.vh)
    output reg  [`HALFPOINT_ERR_CODE_BITS-1:0] err_code,
    // a CONT segment ended and no segment started at that edge (sticky)
    output reg                            underrun
);

    generate
        if (NA < 2 || NA > 6) begin : g_bad_na
            halfpoint_core_illegal_parameter_NA_must_be_2_to_6 u_bad ();
        end
        if (W < 8 || W > 32) begin : g_bad_w
            halfpoint_core_illegal_parameter_W_must_be_8_to_32 u_bad ();
        end
        if (DEPTH < 2 || DEPTH > 256 || (DEPTH & (DEPTH - 1)) != 0) begin : g_bad_depth
            halfpoint_core_illegal_parameter_DEPTH_must_be_a_power_of_2 u_bad ();
        end
        if (TW < 2 || TW > 16) begin : g_bad_tw
            halfpoint_core_illegal_parameter_TW_must_be_2_to_16 u_bad ();
        end
    endgenerate

    localparam integer INDEX_W = $clog2(DEPTH);         // queue index width
    localparam integer CODE_W = `HALFPOINT_ERR_CODE_BITS;
    localparam [34:0] COST_AXIS = 35'd16777216;     // 2^24
    localparam [34:0] COST_DIAGONAL = 35'd23726566; // round(sqrt(2) * 2^24)
    localparam [34:0] CREDIT_CAP = 35'd67108864;    // 2^26

    // ------------------------------------------------------------------
    // Decode at the queue's input
    // ------------------------------------------------------------------
    // Each command is checked and put in run form as it is pushed, so that
    // the queue head feeds the dispatcher and the units with no arithmetic
    // in between.  The checks are the same and their results are acted on
    // when the command reaches the head, exactly as if it were decoded there.
    wire [`HALFPOINT_CMD_BITS-1:0] cmd = s_axis_tdata;
    wire [`HALFPOINT_CMD_OPCODE_WIDTH-1:0] opcode =
        cmd[`HALFPOINT_CMD_OPCODE_LSB +: `HALFPOINT_CMD_OPCODE_WIDTH];
    wire        cmd_cont = cmd[`HALFPOINT_FLAG_CONT_BIT];
    wire [31:0] cmd_rate = cmd[`HALFPOINT_CMD_RATE_LSB +: `HALFPOINT_CMD_RATE_WIDTH];

    // does a 33-bit signed value fit W bits?
    function fits;
        input [32:0] value;
        reg   [32:0] top;
        begin
            top  = value >> (W - 1);
            fits = (top == 33'd0) || (top == ({33{1'b1}} >> (W - 1)));
        end
    endfunction
    function [32:0] sign_extend;
        input [31:0] value;
        begin
            sign_extend = {value[31], value};
        end
    endfunction

    // line fields: the deltas of the core's NA axes; those of the others
    // must be zero (they are reserved bits of this core)
    reg             line_fits, line_reserved_set, line_zero;
    reg  [NA*W-1:0] line_delta;
    reg  [31:0]     delta;
    integer k;
    always @(*) begin
        line_fits = 1'b1;
        line_reserved_set = 1'b0;
        line_zero = 1'b1;
        line_delta = {NA*W{1'b0}};
        for (k = 0; k < `HALFPOINT_MAX_AXES; k = k + 1) begin
            delta = cmd[`HALFPOINT_CMD_DELTA_LSB + `HALFPOINT_CMD_DELTA_STRIDE * k
                        +: `HALFPOINT_CMD_DELTA_WIDTH];
            if (k < NA) begin
                if (!fits(sign_extend(delta))) line_fits = 1'b0;
                if (delta != 32'd0) line_zero = 1'b0;
                line_delta[k*W +: W] = delta[W-1:0];
            end else if (delta != 32'd0) begin
                line_reserved_set = 1'b1;
            end
        end
    end

    // arc fields: start and end relative to the centre
    wire [32:0] arc_i  = sign_extend(cmd[`HALFPOINT_CMD_ARC_I_LSB +: `HALFPOINT_CMD_ARC_I_WIDTH]);
    wire [32:0] arc_j  = sign_extend(cmd[`HALFPOINT_CMD_ARC_J_LSB +: `HALFPOINT_CMD_ARC_J_WIDTH]);
    wire [32:0] arc_x  = sign_extend(cmd[`HALFPOINT_CMD_ARC_X_LSB +: `HALFPOINT_CMD_ARC_X_WIDTH]);
    wire [32:0] arc_y  = sign_extend(cmd[`HALFPOINT_CMD_ARC_Y_LSB +: `HALFPOINT_CMD_ARC_Y_WIDTH]);
    wire [32:0] arc_xs = 33'd0 - arc_i;
    wire [32:0] arc_ys = 33'd0 - arc_j;
    wire [32:0] arc_xe = arc_x - arc_i;
    wire [32:0] arc_ye = arc_y - arc_j;
    wire        arc_fits = fits(arc_i) && fits(arc_j) && fits(arc_x) && fits(arc_y) &&
                           fits(arc_xs) && fits(arc_ys) && fits(arc_xe) && fits(arc_ye);

    wire is_line = (opcode == `HALFPOINT_OP_LINE);
    wire is_arc_cw = (opcode == `HALFPOINT_OP_ARC_CW);
    wire is_arc  = is_arc_cw || (opcode == `HALFPOINT_OP_ARC_CCW);
    wire line_reserved = ((cmd & `HALFPOINT_CMD_RESERVED_LINE) != {`HALFPOINT_CMD_BITS{1'b0}}) ||
                         line_reserved_set;
    wire arc_reserved  = ((cmd & `HALFPOINT_CMD_RESERVED_ARC) != {`HALFPOINT_CMD_BITS{1'b0}});
    wire bad_opcode = !(is_line || is_arc) || (is_line && line_reserved) ||
                      (is_arc && arc_reserved);
    wire bad_fit = !bad_opcode && ((is_line && !line_fits) || (is_arc && !arc_fits));
    wire is_nop  = !bad_opcode && !bad_fit && is_line && line_zero;

    // queue entry: {payload, rate, flags}; payload = line deltas, or the arc's
    // start and end relative to the centre {ye, xe, ys, xs}
    localparam integer PAYLOAD_W = (NA * W > 4 * W) ? NA * W : 4 * W;
    localparam integer ENTRY_W   = PAYLOAD_W + 40;
    wire [PAYLOAD_W-1:0] in_payload =
        is_arc ? {{(PAYLOAD_W-4*W){1'b0}}, arc_ye[W-1:0], arc_xe[W-1:0], arc_ys[W-1:0],
                  arc_xs[W-1:0]}
               : {{(PAYLOAD_W-NA*W){1'b0}}, line_delta};
    wire [7:0]     in_flags = {1'b0, is_nop, bad_fit, bad_opcode, cmd_cont, is_line, is_arc_cw,
                               is_arc};
    wire [ENTRY_W-1:0] in_entry = {in_payload, cmd_rate, in_flags};

    // ------------------------------------------------------------------
    // Queue
    // ------------------------------------------------------------------
    reg  [ENTRY_W-1:0] queue_mem [0:DEPTH-1];
    reg  [INDEX_W-1:0] write_index_q, read_index_q;
    reg  [INDEX_W:0]   count_q;
    wire               pop;
    wire               push = s_axis_tvalid && s_axis_tready;
    localparam [INDEX_W:0]   QUEUE_FULL = {1'b1, {INDEX_W{1'b0}}};     // DEPTH
    localparam [INDEX_W-1:0] INDEX_ONE = {{(INDEX_W-1){1'b0}}, 1'b1};
    localparam [INDEX_W:0]   COUNT_ONE = {{INDEX_W{1'b0}}, 1'b1};

    assign s_axis_tready = (count_q != QUEUE_FULL) && !abort_now;
    assign queue_level   = count_q;

    always @(posedge clk) begin
        if (push) queue_mem[write_index_q] <= in_entry;
    end
    always @(posedge clk) begin
        if (rst || abort_now) begin
            write_index_q <= {INDEX_W{1'b0}};
            read_index_q <= {INDEX_W{1'b0}};
            count_q <= {(INDEX_W+1){1'b0}};
        end else begin
            if (push) write_index_q <= write_index_q + INDEX_ONE;
            if (pop)  read_index_q <= read_index_q + INDEX_ONE;
            if (push && !pop) count_q <= count_q + COUNT_ONE;
            else if (pop && !push) count_q <= count_q - COUNT_ONE;
        end
    end

    // the queue head, decoded
    wire [ENTRY_W-1:0]   head = queue_mem[read_index_q];
    wire                 head_arc     = head[0];
    wire                 head_cw      = head[1];
    wire                 head_line    = head[2];
    wire                 head_cont    = head[3];
    wire                 head_bad_opcode = head[4];
    wire                 head_bad_fit = head[5];
    wire                 head_nop     = head[6];
    wire [31:0]          head_rate    = head[39:8];
    wire [PAYLOAD_W-1:0] head_payload = head[ENTRY_W-1:40];
    wire                 unused_head  = head[7];

    // ------------------------------------------------------------------
    // Dispatcher
    // ------------------------------------------------------------------
    reg         in_flight_q;
    wire        head_ok = (count_q != {(INDEX_W+1){1'b0}}) && !in_flight_q && !abort_now;
    wire        head_bad = head_bad_opcode || head_bad_fit;
    wire        arc_s_valid  = head_ok && head_arc && !head_bad;
    wire        line_s_valid = head_ok && head_line && !head_bad && !head_nop;
    wire        arc_s_ready, line_s_ready;
    wire        arc_take  = arc_s_valid && arc_s_ready;
    wire        line_take = line_s_valid && line_s_ready;
    wire        dispatch_error = head_ok && head_bad;
    assign pop = dispatch_error || (head_ok && head_nop) || arc_take || line_take;

    // ------------------------------------------------------------------
    // Units
    // ------------------------------------------------------------------
    wire          arc_run, arc_loading, arc_ending, arc_next_diagonal, arc_busy, arc_reject;
    wire [1:0]    arc_next_step, arc_next_dir, arc_error;
    wire          line_run, line_loading, line_ending, line_busy, line_reject;
    wire [NA-1:0] line_next_step, line_next_dir;
    wire [1:0]    line_error;
    wire          go;

    wire          unused_arc_move, unused_arc_step_x, unused_arc_step_y;
    wire          unused_arc_dir_x, unused_arc_dir_y;
    wire          unused_arc_done, unused_line_move, unused_line_done;
    wire [W-1:0]  unused_arc_x, unused_arc_y;
    wire [W+1:0]  unused_arc_f;
    wire [NA-1:0] unused_line_step, unused_line_dir;

    halfpoint_arc #(
        .W (W)
    ) u_arc (
        .clk       (clk),
        .rst       (rst),
        .en        (go && arc_run),
        .s_valid   (arc_s_valid),
        .s_ready   (arc_s_ready),
        .s_cw      (head_cw),
        .s_xs      (head_payload[W-1:0]),
        .s_ys      (head_payload[2*W-1:W]),
        .s_xe      (head_payload[3*W-1:2*W]),
        .s_ye      (head_payload[4*W-1:3*W]),
        .busy      (arc_busy),
        .move      (unused_arc_move),
        .step_x    (unused_arc_step_x),
        .step_y    (unused_arc_step_y),
        .dir_x     (unused_arc_dir_x),
        .dir_y     (unused_arc_dir_y),
        .x         (unused_arc_x),
        .y         (unused_arc_y),
        .f         (unused_arc_f),
        .done      (unused_arc_done),
        .reject    (arc_reject),
        .err_code  (arc_error),
        .abort_now (abort_now),
        .start_en  (!line_run || line_ending),
        .running   (arc_run),
        .loading   (arc_loading),
        .ending    (arc_ending),
        .nx_step   (arc_next_step),
        .nx_dir    (arc_next_dir),
        .nx_diag   (arc_next_diagonal)
    );

    halfpoint_line #(
        .NA (NA),
        .W  (W)
    ) u_line (
        .clk       (clk),
        .rst       (rst),
        .en        (go && line_run),
        .s_valid   (line_s_valid),
        .s_ready   (line_s_ready),
        .s_delta   (head_payload[NA*W-1:0]),
        .busy      (line_busy),
        .move      (unused_line_move),
        .step      (unused_line_step),
        .dir       (unused_line_dir),
        .done      (unused_line_done),
        .reject    (line_reject),
        .err_code  (line_error),
        .abort_now (abort_now),
        .start_en  (!arc_run || arc_ending),
        .running   (line_run),
        .loading   (line_loading),
        .ending    (line_ending),
        .nx_step   (line_next_step),
        .nx_dir    (line_next_dir)
    );

    wire unused_ok = &{1'b0, unused_arc_move, unused_arc_step_x, unused_arc_step_y,
                       unused_arc_dir_x, unused_arc_dir_y, unused_arc_done, unused_line_move,
                       unused_line_done, unused_arc_x, unused_arc_y, unused_arc_f,
                       unused_line_step, unused_line_dir, line_error};

    // rate and CONT flag handed over with a command (pending in the unit),
    // and those of the running segment
    reg [31:0] arc_rate_pend_q, line_rate_pend_q, arc_rate_run_q, line_rate_run_q;
    reg        arc_cont_pend_q, line_cont_pend_q, arc_cont_run_q, line_cont_run_q;

    always @(posedge clk) begin
        if (rst || abort_now) begin
            in_flight_q <= 1'b0;
            arc_rate_run_q <= 32'd0;
            line_rate_run_q <= 32'd0;
            arc_cont_run_q <= 1'b0;
            line_cont_run_q <= 1'b0;
        end else begin
            if (arc_take || line_take) begin
                in_flight_q <= 1'b1;
            end else if (arc_loading || line_loading || arc_reject || line_reject) begin
                in_flight_q <= 1'b0;
            end
            if (arc_loading) begin
                arc_rate_run_q <= arc_rate_pend_q;
                arc_cont_run_q <= arc_cont_pend_q;
            end
            if (line_loading) begin
                line_rate_run_q <= line_rate_pend_q;
                line_cont_run_q <= line_cont_pend_q;
            end
        end
        if (arc_take) begin
            arc_rate_pend_q <= head_rate;
            arc_cont_pend_q <= head_cont;
        end
        if (line_take) begin
            line_rate_pend_q <= head_rate;
            line_cont_pend_q <= head_cont;
        end
    end

    // ------------------------------------------------------------------
    // go: step/dir readiness and feed credit
    // ------------------------------------------------------------------
    wire [NA-1:0] next_step = arc_run ? {{(NA-2){1'b0}}, arc_next_step}
                            : line_run ? line_next_step : {NA{1'b0}};
    wire [NA-1:0] next_dir  = arc_run ? {{(NA-2){1'b0}}, arc_next_dir} : line_next_dir;
    wire [NA-1:0] ready_pos, ready_neg, stepgen_busy;
    wire          steps_ready = &(~next_step | (next_dir & ready_pos) | (~next_dir & ready_neg));

    reg  [34:0]   credit_q;
    // override accumulator a (0..99, the model's ov_acc) kept as the two
    // thresholds 100 - a and 200 - a, so that the rate factor k needs
    // compares, not an add; the override input is registered (override_q,
    // clamped to 200) and k for the next clock is computed a clock ahead
    // (factor_q = k(thresholds, override_q)), so that the credit adder
    // starts from a register
    reg  [8:0]    threshold1_q, threshold2_q;
    reg  [7:0]    override_q;
    reg  [1:0]    factor_q;
    wire          diagonal = arc_run && arc_next_diagonal;
    wire          credit_axis_ok = (credit_q >= COST_AXIS);
    wire          credit_diagonal_ok = (credit_q >= COST_DIAGONAL);
    assign go = (arc_run || line_run) && steps_ready &&
                (diagonal ? credit_diagonal_ok : credit_axis_ok) && !abort_now;

    wire [7:0]  override_n = (feed_override > 8'd200) ? 8'd200 : feed_override;
    wire [8:0]  override_back = (factor_q == 2'd2) ? 9'd200 : (factor_q == 2'd1) ? 9'd100 : 9'd0;
    wire [8:0]  threshold1_sum = threshold1_q - {1'b0, override_q} + override_back;
    wire [8:0]  threshold2_sum = threshold2_q - {1'b0, override_q} + override_back;
    // thresholds of the next clock: unchanged across an abort edge
    wire [8:0]  threshold1_n = abort_now ? threshold1_q : threshold1_sum;
    wire [8:0]  threshold2_n = abort_now ? threshold2_q : threshold2_sum;
    wire [1:0]  factor_n = ({1'b0, override_n} >= threshold2_n) ? 2'd2
                         : ({1'b0, override_n} >= threshold1_n) ? 2'd1 : 2'd0;
    wire [31:0] rate = arc_run ? arc_rate_run_q : line_run ? line_rate_run_q : 32'd0;
    wire [34:0] credit_add = (factor_q == 2'd2) ? {2'b00, rate, 1'b0}
                           : (factor_q == 2'd1) ? {3'b000, rate} : 35'd0;
    // credit + credit_add - (go ? cost : 0), as two sums in parallel so that
    // the late `go` only selects: the cost is taken off the credit while the
    // override settles credit_add
    wire [34:0] credit_less_cost = credit_q - (diagonal ? COST_DIAGONAL : COST_AXIS);
    wire [34:0] credit_if_go     = credit_less_cost + credit_add;
    wire [34:0] credit_if_hold   = credit_q + credit_add;
    // value > CREDIT_CAP (= 2^26) for a non-negative value, as a LUT tree
    function over_cap;
        input [34:0] value;
        begin
            over_cap = (|value[34:27]) || (value[26] && (|value[25:0]));
        end
    endfunction
    wire [34:0] credit_n = go ? (over_cap(credit_if_go) ? CREDIT_CAP : credit_if_go)
                              : (over_cap(credit_if_hold) ? CREDIT_CAP : credit_if_hold);

    always @(posedge clk) begin
        if (rst) begin
            credit_q     <= 35'd0;
            threshold1_q <= 9'd100;
            threshold2_q <= 9'd200;
            override_q   <= 8'd0;
            factor_q     <= 2'd0;
        end else begin
            override_q <= override_n;
            factor_q   <= factor_n;
            if (abort_now) begin
                credit_q <= 35'd0;
            end else begin
                credit_q     <= credit_n;
                threshold1_q <= threshold1_sum;
                threshold2_q <= threshold2_sum;
            end
        end
    end

    // ------------------------------------------------------------------
    // STEP/DIR generators and positions
    // ------------------------------------------------------------------
    localparam [W-1:0] POSITION_ONE = {{(W-1){1'b0}}, 1'b1};
    genvar a;
    generate
        for (a = 0; a < NA; a = a + 1) begin : g_axis
            halfpoint_stepgen #(
                .TW (TW)
            ) u_stepgen (
                .clk           (clk),
                .rst           (rst),
                .cfg_steplen   (cfg_steplen[a*TW +: TW]),
                .cfg_stepspace (cfg_stepspace[a*TW +: TW]),
                .cfg_dirsetup  (cfg_dirsetup[a*TW +: TW]),
                .cfg_dirhold   (cfg_dirhold[a*TW +: TW]),
                .cfg_step_inv  (cfg_step_inv[a]),
                .cfg_dir_inv   (cfg_dir_inv[a]),
                .req           (go && next_step[a]),
                .req_dir       (next_dir[a]),
                .ready_pos     (ready_pos[a]),
                .ready_neg     (ready_neg[a]),
                .busy          (stepgen_busy[a]),
                .step_pin      (step_pin[a]),
                .dir_pin       (dir_pin[a])
            );
            always @(posedge clk) begin
                if (rst) begin
                    pos[a*W +: W] <= {W{1'b0}};
                end else if (go && next_step[a]) begin
                    pos[a*W +: W] <= next_dir[a] ? pos[a*W +: W] + POSITION_ONE
                                                 : pos[a*W +: W] - POSITION_ONE;
                end
            end
        end
    endgenerate

    // ------------------------------------------------------------------
    // Status
    // ------------------------------------------------------------------
    assign busy = (count_q != {(INDEX_W+1){1'b0}}) || in_flight_q || arc_busy || line_busy ||
                  (|stepgen_busy);

    wire              ending = arc_ending || line_ending;
    wire              cont   = arc_run ? arc_cont_run_q : line_cont_run_q;
    // the arc unit's reject codes 1, 2, 3
    wire [CODE_W-1:0] arc_code = (arc_error == 2'd1) ? `HALFPOINT_E_ARC_RADIUS
                               : (arc_error == 2'd2) ? `HALFPOINT_E_ARC_RANGE
                               : `HALFPOINT_E_ARC_END;

    always @(posedge clk) begin
        if (rst) begin
            move <= 1'b0;
            err <= 1'b0;
            err_code <= `HALFPOINT_E_NONE;
            underrun <= 1'b0;
        end else begin
            move <= go;
            err  <= !abort_now && (dispatch_error || arc_reject || line_reject);
            if (!abort_now) begin
                if (dispatch_error) begin
                    err_code <= head_bad_opcode ? `HALFPOINT_E_OPCODE : `HALFPOINT_E_FIELD;
                end else if (arc_reject) begin
                    err_code <= arc_code;
                end else if (line_reject) begin
                    err_code <= `HALFPOINT_E_OPCODE;
                end
            end
            if (ending && cont && !arc_loading && !line_loading) underrun <= 1'b1;
        end
    end

endmodule

`default_nettype wire
