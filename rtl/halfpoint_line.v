// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// ============================================================================
// halfpoint_line: N-axis straight-line interpolator (seed 001, difference
// method)
// ============================================================================
// One command = one straight segment given by signed per-axis deltas (BLU).
// Max = max |d_i| iterations; in each, every axis i accumulates |d_i| and
// steps when twice its deviation exceeds Max (strictly), so the longest axis
// steps every iteration and every axis stays within 0.5 BLU of the ideal line
// and ends exactly on its delta.  One iteration ("move") per clock while `en`
// is high, from one segment to the next without an idle clock.
//
// Per axis the run stage keeps E_i = 2(F_i + |d_i|) - Max - 1 and two
// prepared increments, so the loop is: sign(E_i) -> select -> one add.
//
// Command (valid/ready, taken when s_valid & s_ready):
//   s_delta   NA signed W-bit deltas, axis 0 in the least significant bits
// Validator: NA + 2 clocks (magnitudes, running maximum, increments), then a
// pending slot that, while start_en is high, enters the run stage at the edge
// of the running segment's last move, or at once when the run stage is idle.
// The sequencing outputs (running, loading, ending, nx_*) are combinational
// views of the run stage for the motion core.  A segment with all
// deltas zero is rejected (reject pulse, err_code = 1) and makes no move.
//
// Outputs (registered; in the clock after a move edge): move = 1, step[i] =
// axis i stepped, dir[i] = direction of axis i's latest step (1 = positive,
// held between steps), done = it was the segment's last move.
// busy = a segment is running, pending or being validated.
//
// Parameters: see the comment above each (an illegal value stops
// elaboration).
//
// Register names: registers end in _q, the value they take at the next edge
// in _n; cmd_* hold the command being validated, pend_* the pending slot.
// e_q is E_i of every axis, e_add_step_q / e_add_hold_q the increments E_i
// receives on an iteration in which axis i steps / does not step.
//
// abort_now: at the next edge no move is made and the running, pending and
// validating segments are dropped (no reject for them); s_ready is low while
// abort_now is high.
//
// Reset: synchronous, active high, clears control state and outputs.
// ============================================================================
module halfpoint_line #(
    // number of axes, 1..6
    parameter integer NA = 3,
    // delta width in bits, 8..32 (signed deltas); the datapath is W+2 bits
    parameter integer W  = 32
) (
    input  wire            clk,
    input  wire            rst,
    // move enable: one iteration per clock while high
    input  wire            en,

    /*
     * Command stream (valid/ready): NA signed deltas, axis 0 in the least
     * significant bits
     */
    input  wire            s_valid,
    output wire            s_ready,
    input  wire [NA*W-1:0] s_delta,

    /*
     * Status and per-clock outputs (registered)
     */
    output wire            busy,
    output reg             move,
    output reg  [NA-1:0]   step,
    output reg  [NA-1:0]   dir,
    output reg             done,
    output reg             reject,
    output reg  [1:0]      err_code,

    /*
     * Sequencing (for the motion core; tie start_en high when used alone)
     */
    // drop the running, pending and validated segments now
    input  wire            abort_now,
    // the pending segment may enter the run stage
    input  wire            start_en,
    // a segment is in the run stage
    output wire            running,
    // a validated segment waits in the pending slot (registered)
    output wire            pending,
    // the pending segment enters the run stage at this edge
    output wire            loading,
    // the running segment makes its last move at this edge
    output wire            ending,
    // the next move (if en): axes that step, and their directions (1 = positive)
    output wire [NA-1:0]   nx_step,
    output wire [NA-1:0]   nx_dir
);

    generate
        if (NA < 1 || NA > 6) begin : g_bad_na
            halfpoint_line_illegal_parameter_NA_must_be_1_to_6 u_bad ();
        end
        if (W < 8 || W > 32) begin : g_bad_w
            halfpoint_line_illegal_parameter_W_must_be_8_to_32 u_bad ();
        end
    endgenerate

    localparam integer DATA_W = W + 2;      // datapath width
    // validator states
    localparam [1:0] STATE_IDLE = 2'd0;
    localparam [1:0] STATE_MAX  = 2'd1;
    localparam [1:0] STATE_INIT = 2'd2;
    localparam [1:0] STATE_HOLD = 2'd3;
    localparam integer AXIS_LAST = NA - 1;
    localparam [W-1:0] ONE_W = {{(W-1){1'b0}}, 1'b1};
    localparam [DATA_W-1:0] ONE_D = {{(DATA_W-1){1'b0}}, 1'b1};

    reg  [1:0]          validator_state_q;
    reg  [2:0]          axis_index_q;
    reg  [NA*W-1:0]     cmd_abs_q;              // |d_i|
    reg  [NA-1:0]       cmd_negative_q;         // d_i < 0
    reg  [W-1:0]        max_abs_q;              // running maximum of |d_i|
    reg  [NA*DATA_W-1:0] pend_e_q, pend_e_add_step_q, pend_e_add_hold_q;
    reg  [W-1:0]        pend_moves_q;

    assign s_ready = (validator_state_q == STATE_IDLE) && !abort_now;
    wire   accept   = s_valid && s_ready;
    wire   all_zero = (max_abs_q == {W{1'b0}});
    wire   load;

    wire [W-1:0] abs_selected = cmd_abs_q[axis_index_q*W +: W];

    always @(posedge clk) begin
        if (rst || abort_now) begin
            validator_state_q <= STATE_IDLE;
        end else begin
            case (validator_state_q)
                STATE_IDLE: if (accept) validator_state_q <= STATE_MAX;
                STATE_MAX:  if (axis_index_q == AXIS_LAST[2:0]) validator_state_q <= STATE_INIT;
                STATE_INIT: validator_state_q <= all_zero ? STATE_IDLE : STATE_HOLD;
                STATE_HOLD: if (load) validator_state_q <= STATE_IDLE;
                default:    validator_state_q <= STATE_IDLE;
            endcase
        end
    end

    always @(posedge clk) begin
        if (accept) begin
            axis_index_q <= 3'd0;
            max_abs_q    <= {W{1'b0}};
        end
        if (validator_state_q == STATE_MAX) begin
            axis_index_q <= axis_index_q + 3'd1;
            if (abs_selected > max_abs_q) max_abs_q <= abs_selected;
        end
        if (validator_state_q == STATE_INIT) pend_moves_q <= max_abs_q;
    end

    genvar i;
    generate
        for (i = 0; i < NA; i = i + 1) begin : g_in
            wire [W-1:0]      delta     = s_delta[i*W +: W];
            wire [DATA_W-1:0] abs_twice = {1'b0, cmd_abs_q[i*W +: W], 1'b0};     // 2|d_i|
            wire [DATA_W-1:0] max_wide  = {2'b00, max_abs_q};
            always @(posedge clk) begin
                if (accept) begin
                    cmd_negative_q[i] <= delta[W-1];
                    cmd_abs_q[i*W +: W] <= delta[W-1] ? (~delta + ONE_W) : delta;
                end
                if (validator_state_q == STATE_INIT) begin
                    // E_0 (F = 0)
                    pend_e_q[i*DATA_W +: DATA_W]          <= abs_twice - max_wide - ONE_D;
                    // after a step
                    pend_e_add_step_q[i*DATA_W +: DATA_W] <= abs_twice - (max_wide << 1);
                    // no step
                    pend_e_add_hold_q[i*DATA_W +: DATA_W] <= abs_twice;
                end
            end
        end
    endgenerate

    // ------------------------------------------------------------------
    // Run stage
    // ------------------------------------------------------------------
    reg                  run_q;
    reg  [W-1:0]         moves_left_q;
    reg  [NA-1:0]        negative_q;
    reg  [NA*DATA_W-1:0] e_q, e_add_step_q, e_add_hold_q;
    wire [NA-1:0]        steps;

    wire advance = run_q && en && !abort_now;           // a move at this edge
    wire last    = advance && (moves_left_q == ONE_W);
    assign load = (validator_state_q == STATE_HOLD) && start_en && !abort_now && (!run_q || last);

    assign running = run_q;
    assign pending = (validator_state_q == STATE_HOLD);
    assign loading = load;
    assign ending  = last;
    assign nx_step = steps;
    assign nx_dir  = ~negative_q;
    assign busy    = run_q || (validator_state_q != STATE_IDLE);

    generate
        for (i = 0; i < NA; i = i + 1) begin : g_axis
            wire [DATA_W-1:0] e_axis = e_q[i*DATA_W +: DATA_W];
            assign steps[i] = !e_axis[DATA_W-1];
            wire [DATA_W-1:0] e_add = steps[i] ? e_add_step_q[i*DATA_W +: DATA_W]
                                               : e_add_hold_q[i*DATA_W +: DATA_W];
            always @(posedge clk) begin
                if (load) begin
                    e_q[i*DATA_W +: DATA_W]          <= pend_e_q[i*DATA_W +: DATA_W];
                    e_add_step_q[i*DATA_W +: DATA_W] <= pend_e_add_step_q[i*DATA_W +: DATA_W];
                    e_add_hold_q[i*DATA_W +: DATA_W] <= pend_e_add_hold_q[i*DATA_W +: DATA_W];
                end else if (advance) begin
                    e_q[i*DATA_W +: DATA_W] <= e_axis + e_add;
                end
            end
        end
    endgenerate

    always @(posedge clk) begin
        if (rst || abort_now) begin
            run_q <= 1'b0;
        end else if (load) begin
            run_q <= 1'b1;
        end else if (last) begin
            run_q <= 1'b0;
        end
    end

    always @(posedge clk) begin
        if (load) begin
            moves_left_q <= pend_moves_q;
            negative_q   <= cmd_negative_q;
        end else if (advance) begin
            moves_left_q <= moves_left_q - ONE_W;
        end
    end

    wire rejecting = (validator_state_q == STATE_INIT) && all_zero && !abort_now;

    always @(posedge clk) begin
        if (rst) begin
            move     <= 1'b0;
            step     <= {NA{1'b0}};
            dir      <= {NA{1'b0}};
            done     <= 1'b0;
            reject   <= 1'b0;
            err_code <= 2'd0;
        end else begin
            move   <= advance;
            step   <= advance ? steps : {NA{1'b0}};
            if (advance) dir <= (dir & ~steps) | (~negative_q & steps);
            done   <= last;
            reject <= rejecting;
            if (rejecting) err_code <= 2'd1;
        end
    end

endmodule

`default_nettype wire
