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
// Per axis the run stage keeps E_i = 2(F_i + |d_i|) - Max - 1 and the two
// increments, halved (|d_i| and |d_i| - Max), so the loop is: sign(E_i) ->
// select -> one add.
//
// Command (valid/ready, taken when s_valid & s_ready):
//   s_delta   NA signed W-bit deltas, axis 0 in the least significant bits
// Validator: NA + 2 clocks (magnitudes, running maximum, the zero check),
// then a pending slot (the validator's |d_i|, signs and Max, held) that, while
// start_en is high, enters the run stage at the edge of the running segment's
// last move, or at once when the run stage is idle; E_i and the increments
// are computed from the slot as it enters.
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
// in _n; cmd_* hold the command being validated or pending.  e_q is E_i of
// every axis; E_i receives 2 * e_half_step_q on an iteration in which axis i
// steps, 2 * e_half_hold_q on one in which it does not.  Every register is as
// wide as its bound (stated beside it; |d_i| <= Max <= 2^(W-1)).
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
    // delta width in bits, 8..32 (signed deltas); E_i is W+1 bits
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

    // E_i in [2|d_i| - 2 Max, 2|d_i| - 1], within [-2^W, 2^W - 1]: W+1 bits signed
    localparam integer DATA_W = W + 1;
    // validator states
    localparam [1:0] STATE_IDLE = 2'd0;
    localparam [1:0] STATE_MAX  = 2'd1;
    localparam [1:0] STATE_INIT = 2'd2;
    localparam [1:0] STATE_HOLD = 2'd3;
    localparam integer AXIS_LAST = NA - 1;
    localparam [W-1:0] ONE_W = {{(W-1){1'b0}}, 1'b1};
    localparam [DATA_W-1:0] ONE_D = {{(DATA_W-1){1'b0}}, 1'b1};

    reg  [1:0]          validator_state_q;
    reg  [2:0]          axis_index_q;           // 0..NA-1
    reg  [NA*W-1:0]     cmd_abs_q;              // |d_i|, 0..2^(W-1)
    reg  [NA-1:0]       cmd_negative_q;         // d_i < 0
    reg  [W-1:0]        max_abs_q;              // running maximum of |d_i|, 0..2^(W-1)

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
    end

    genvar i;
    generate
        for (i = 0; i < NA; i = i + 1) begin : g_in
            wire [W-1:0]      delta     = s_delta[i*W +: W];
            always @(posedge clk) begin
                if (accept) begin
                    cmd_negative_q[i] <= delta[W-1];
                    cmd_abs_q[i*W +: W] <= delta[W-1] ? (~delta + ONE_W) : delta;
                end
            end
        end
    endgenerate

    // ------------------------------------------------------------------
    // Run stage
    // ------------------------------------------------------------------
    reg                  run_q;
    reg  [W-1:0]         moves_left_q;          // 1..Max while running
    reg  [NA-1:0]        negative_q;
    reg  [NA*DATA_W-1:0] e_q;                   // E_i, -2^W..2^W-1 (signed)
    reg  [NA*W-1:0]      e_half_step_q;         // |d_i| - Max, -2^(W-1)..0 (signed)
    reg  [NA*W-1:0]      e_half_hold_q;         // |d_i|, 0..2^(W-1)
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

    // The increments 2|d_i| - 2 Max (a step) and 2|d_i| (no step) are even:
    // kept halved.  E_i + 2|d_i| is computed modulo 2^(W+1) (2^W, at |d_i| =
    // 2^(W-1), reads as -2^W): exact, since the sum is within E_i's bounds.
    generate
        for (i = 0; i < NA; i = i + 1) begin : g_axis
            wire [DATA_W-1:0] e_axis = e_q[i*DATA_W +: DATA_W];
            wire [W-1:0]      abs    = cmd_abs_q[i*W +: W];
            assign steps[i] = !e_axis[DATA_W-1];
            wire [W-1:0]      e_half = steps[i] ? e_half_step_q[i*W +: W]
                                                : e_half_hold_q[i*W +: W];
            wire [DATA_W-1:0] e_add  = {e_half, 1'b0};
            always @(posedge clk) begin
                if (load) begin
                    // E_0 = 2|d_i| - Max - 1 (F = 0), from the pending slot
                    e_q[i*DATA_W +: DATA_W] <= {abs, 1'b0} - {1'b0, max_abs_q} - ONE_D;
                    e_half_step_q[i*W +: W] <= abs - max_abs_q;
                    e_half_hold_q[i*W +: W] <= abs;
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
            moves_left_q <= max_abs_q;
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

`ifdef FORMAL
    // ========================================================================
    // Formal properties (SymbiYosys: formal/halfpoint_line.sby, run by
    // python -m halfpoint.flows.formal).  Verilator, Icarus and the cocotb
    // builds do not define FORMAL, so they see the module above unchanged.
    // ========================================================================
    // A monitor follows every command from acceptance to its end: the slot
    // (f_slot_*: the command being validated or pending) and the running
    // segment (f_run_*: its |d_i|, signs, Max = max |d_i|, the moves made n and
    // the steps made s_i per axis), and asserts:
    //   handshake  s_ready only when idle and not aborting; the master holds
    //              s_valid and s_delta until taken (assumed, valid/ready);
    //   no loss    a taken command is validated, then either rejected (iff all
    //              its deltas are zero, reject + err_code 1) or loaded and run
    //              to its done; only abort_now or rst drops it; validation
    //              takes NA + 2 clocks; busy iff a command is held anywhere;
    //   moves      the segment makes exactly Max moves, the last with done;
    //   steps      at most one step per axis per move (step only with move),
    //              in the sign of d_i (dir), dir held while an axis does not
    //              step; the longest axis steps on every move;
    //   error      after every move the deviation F_i from the ideal line
    //              (kept by the monitor: + |d_i| per move, - Max per step)
    //              obeys -Max < 2 F_i <= Max (within 0.5 BLU), and the error
    //              term E_i = 2 F_i + 2|d_i| - Max - 1 stays within its bounds
    //              [2|d_i| - 2 Max, 2|d_i| - 1];
    //   ends       (F_ENDS) at done, every axis has made exactly |d_i| steps,
    //              never more before.  Proved (sby tasks endsp_*) by the product
    //              invariant F_i = r_i Max - m |d_i| (r_i, m: steps and moves
    //              left), its products free values under lemmas that true
    //              products obey (see the F_ENDS block in the axis loop); the
    //              task ends_na1_w8 also checks it bounded (bmc);
    //   outputs    move, step, done, reject are the registered views of the
    //              edge before.
    // Labels: a_* the contract, i_* invariants that tie the RTL state to the
    // monitor so that k-induction closes (E_i in terms of F_i, the increments,
    // the validator's running maximum); in the
    // generate loop the label is the comment after `assert(` (Yosys would
    // see one label many times).  rst and abort_now are free (rst high on the
    // first clock).
    localparam integer F_PW = 2 * W + 4;         // the monitor's F, 2F, E_i and bounds
    // |d_i| <= 2^(W-1): the bound that sizes E_i (W+1 bits) and the increments
    localparam [W-1:0] F_ABS_BOUND = {1'b1, {(W-1){1'b0}}};

    reg f_past_valid;
    initial f_past_valid = 1'b0;
    always @(posedge clk)
        f_past_valid <= 1'b1;
    always @(*)
        if (!f_past_valid)
            assume(rst);

    // valid/ready: a command offered and not taken stays offered, unchanged
    // (named f_rule_*: the core's composed proofs, formal/halfpoint_core.sby
    // compose_*, turn them into assertions, obligations of the core)
    always @(posedge clk)
        if (f_past_valid && !$past(rst) && $past(s_valid && !s_ready)) begin
            f_rule_offer: assume(s_valid);
            f_rule_offer_data: assume(s_delta == $past(s_delta));
        end

    // the command as taken: |d_i| (W bits hold |-2^(W-1)|) and signs
    reg  [NA*W-1:0] f_in_abs;
    reg  [NA-1:0]   f_in_neg;
    integer f_k, f_m, f_n;
    always @(*)
        for (f_k = 0; f_k < NA; f_k = f_k + 1) begin
            f_in_neg[f_k] = s_delta[f_k*W + W - 1];
            f_in_abs[f_k*W +: W] = f_in_neg[f_k] ? (~s_delta[f_k*W +: W] + ONE_W)
                                                   : s_delta[f_k*W +: W];
        end

    // the slot: the command being validated or pending
    reg             f_slot_valid;
    reg  [NA*W-1:0] f_slot_abs;
    reg  [NA-1:0]   f_slot_neg;
    reg  [3:0]      f_slot_age;                  // clocks since taken (saturating)
    reg  [W-1:0]    f_slot_max;                  // max |d_i|
    reg  [W-1:0]    f_slot_prefix_max;           // max |d_i| of the axes i < axis_index_q
    always @(*) begin
        f_slot_max = {W{1'b0}};
        f_slot_prefix_max = {W{1'b0}};
        for (f_m = 0; f_m < NA; f_m = f_m + 1) begin
            if (f_slot_abs[f_m*W +: W] > f_slot_max) f_slot_max = f_slot_abs[f_m*W +: W];
            if (f_m < axis_index_q && f_slot_abs[f_m*W +: W] > f_slot_prefix_max)
                f_slot_prefix_max = f_slot_abs[f_m*W +: W];
        end
    end

    // the running segment
    reg             f_run_valid;
    reg  [NA*W-1:0] f_run_abs;
    reg  [NA-1:0]   f_run_neg;
    reg  [W-1:0]    f_run_max;
    reg  [W-1:0]    f_moves;                     // n
    reg  [NA*W-1:0] f_steps;                     // s_i

    always @(posedge clk) begin
        if (rst || abort_now) begin
            f_slot_valid <= 1'b0;
            f_run_valid  <= 1'b0;
        end else begin
            if (f_slot_age != 4'hf) f_slot_age <= f_slot_age + 4'd1;
            if (rejecting || load) f_slot_valid <= 1'b0;
            if (accept) begin
                f_slot_valid <= 1'b1;
                f_slot_abs   <= f_in_abs;
                f_slot_neg   <= f_in_neg;
                f_slot_age   <= 4'd0;
            end
            if (advance) begin
                f_moves <= f_moves + ONE_W;
                for (f_n = 0; f_n < NA; f_n = f_n + 1)
                    f_steps[f_n*W +: W] <= f_steps[f_n*W +: W] + {{(W-1){1'b0}}, steps[f_n]};
            end
            if (last) f_run_valid <= 1'b0;
            if (load) begin
                f_run_valid <= 1'b1;
                f_run_abs   <= f_slot_abs;
                f_run_neg   <= f_slot_neg;
                f_run_max   <= f_slot_max;
                f_moves     <= {W{1'b0}};
                f_steps     <= {NA*W{1'b0}};
            end
        end
    end

    // ---- handshake, no loss, sequencing (combinational, every clock) ----
    always @(*)
        if (f_past_valid && !rst) begin
            a_ready_idle: assert(!s_ready || (validator_state_q == STATE_IDLE && !abort_now));
            a_slot_held:  assert(f_slot_valid == (validator_state_q != STATE_IDLE));
            a_run_held:   assert(f_run_valid == run_q);
            a_busy:       assert(busy == (f_slot_valid || f_run_valid));
            if (rejecting) begin
                a_reject_empty: assert(f_slot_max == {W{1'b0}});
            end
            if (load) begin
                a_load_pending: assert(validator_state_q == STATE_HOLD && f_slot_valid);
                a_load_nonzero: assert(f_slot_max != {W{1'b0}});
            end
            // validation: NA clocks of maximum, one of init, then pending
            if (validator_state_q == STATE_MAX) begin
                a_max_time:  assert(f_slot_age == {1'b0, axis_index_q});
                i_max_part:  assert(max_abs_q == f_slot_prefix_max);
                i_axis_last: assert(axis_index_q <= AXIS_LAST[2:0]);
            end
            if (validator_state_q == STATE_INIT) begin
                a_init_time: assert(f_slot_age == NA);
                i_max_init:  assert(max_abs_q == f_slot_max);
            end
            if (validator_state_q == STATE_HOLD) begin
                a_hold_time: assert(f_slot_age >= NA + 1);
            end
        end

    // ---- moves, steps, ends, error ----
    genvar f_i;
    generate
        for (f_i = 0; f_i < NA; f_i = f_i + 1) begin : g_formal_axis
            wire [W-1:0]      f_abs   = f_run_abs[f_i*W +: W];
            wire [W-1:0]      f_s     = f_steps[f_i*W +: W];
            wire [DATA_W-1:0] f_e     = e_q[f_i*DATA_W +: DATA_W];
            wire [W-1:0]      f_hstep = e_half_step_q[f_i*W +: W];
            wire [W-1:0]      f_hhold = e_half_hold_q[f_i*W +: W];
            wire [F_PW-1:0] f_ewide = {{(F_PW-DATA_W){f_e[DATA_W-1]}}, f_e};
            // the increments 2 (|d| - Max) and 2 |d|, at the monitor's width
            wire [F_PW-1:0] f_estep = {{(F_PW-W-1){f_hstep[W-1]}}, f_hstep, 1'b0};
            wire [F_PW-1:0] f_ehold = {{(F_PW-W-1){1'b0}}, f_hhold, 1'b0};
            wire [F_PW-1:0] f_maxw  = {{(W+4){1'b0}}, f_run_max};
            wire [F_PW-1:0] f_absw  = {{(W+4){1'b0}}, f_abs};
`ifdef F_ENDS
            // The "ends" induction.  With m = Max - n moves and r = |d| - s steps
            // left, F = n|d| - s Max = B - A, A = m |d|, B = r Max (i_dev_ab).  Then
            // r = 0 at m >= 1 gives F = -A <= -|d|: no step (a_steps_le); at the last
            // move A = |d| and F + |d| - step Max = Max (r - step), within
            // (-Max/2, Max/2] (from E's bounds), so r = step (a_ends).  The products
            // are the only nonlinear part: a bit-blasted multiplier kept k-induction
            // from closing ((m - 1) |d| = m |d| - |d| across a clock), so A and B
            // are free values (anyseq) constrained only by facts every true product
            // obeys (lemmas below; an over-approximation, so sound).
            // Ghost copies of m, r, |d|, Max at 2W bits, updated on every clock from
            // the next-state values f_*_nx that the lemmas name (tied to the monitor
            // by i_gm, i_gr, i_gd, i_gmax).
            wire [2*W-1:0] f_slot_abs2 = {{W{1'b0}}, f_slot_abs[f_i*W +: W]};
            wire [2*W-1:0] f_slot_max2 = {{W{1'b0}}, f_slot_max};
            wire [2*W-1:0] f_step2     = {{(2*W-1){1'b0}}, steps[f_i]};
            reg  [2*W-1:0] f_gm, f_gr, f_gd, f_gmax;
            wire [2*W-1:0] f_gm_nx   = load ? f_slot_max2 : advance ? f_gm - 1'b1 : f_gm;
            wire [2*W-1:0] f_gr_nx   = load ? f_slot_abs2 : advance ? f_gr - f_step2 : f_gr;
            wire [2*W-1:0] f_gd_nx   = load ? f_slot_abs2 : f_gd;
            wire [2*W-1:0] f_gmax_nx = load ? f_slot_max2 : f_gmax;
            always @(posedge clk) begin
                f_gm   <= f_gm_nx;
                f_gr   <= f_gr_nx;
                f_gd   <= f_gd_nx;
                f_gmax <= f_gmax_nx;
            end
            // the products (2W bits, modulo 2^2W): A = gm gd and B = gmax gr of the
            // registers, of their next-state values, Max |d| of the slot at load,
            // and B after this clock's move (without a load)
            (* anyseq *) wire [2*W-1:0] f_prod_a;
            (* anyseq *) wire [2*W-1:0] f_prod_b;
            (* anyseq *) wire [2*W-1:0] f_prod_a_nx;
            (* anyseq *) wire [2*W-1:0] f_prod_b_nx;
            (* anyseq *) wire [2*W-1:0] f_prod_load;
            (* anyseq *) wire [2*W-1:0] f_prod_b_move;   // Max (r - step), a move's B
            wire [2*W-1:0] f_gr_move = f_gr - f_step2;
            localparam [2*W-1:0] F_LIM2 = {{(W-1){1'b0}}, 1'b1, {W{1'b0}}};  // 2^W
            always @(*) begin
                // distributivity of the next-state products: (m - 1) |d| = m |d| - |d|,
                // Max (r - step) = r Max - step Max; at load both are Max |d|
                assume(f_prod_a_nx == (load ? f_prod_load
                                       : advance ? f_prod_a - f_gd : f_prod_a));
                assume(f_prod_b_nx == (load ? f_prod_load
                                       : advance ? f_prod_b - (steps[f_i] ? f_gmax : 0)
                                       : f_prod_b));
                // x y >= y for x >= 1 (x, y < 2^W: no overflow), 1 y = y, 0 y = 0
                if (f_gm >= 1 && f_gm < F_LIM2 && f_gd < F_LIM2)
                    assume(f_prod_a >= f_gd);
                if (f_gr_nx >= 1 && f_gr_nx < F_LIM2 && f_gmax_nx < F_LIM2)
                    assume(f_prod_b_nx >= f_gmax_nx);
                if (f_gm == 1) assume(f_prod_a == f_gd);
                assume(f_prod_b_move == f_prod_b - (steps[f_i] ? f_gmax : 0));
                if (f_gr_move >= 1 && f_gr_move < F_LIM2 && f_gmax < F_LIM2)
                    assume(f_prod_b_move >= f_gmax);
                if (f_gm == 0) assume(f_prod_a == 0);
                if (f_gr == 0) assume(f_prod_b == 0);
                if (f_gr_nx == 0) assume(f_prod_b_nx == 0);
                if (f_gm_nx == 0) assume(f_prod_a_nx == 0);
            end
            // congruence: a product of the registers is the product of their
            // next-state values a clock before
            always @(posedge clk)
                if (f_past_valid) begin
                    assume(f_prod_a == $past(f_prod_a_nx));
                    assume(f_prod_b == $past(f_prod_b_nx));
                end
`endif
            // F, the deviation from the ideal line after n moves, kept by adding
            // |d| on every move and subtracting Max on every step
            reg  [F_PW-1:0] f_dev;
            always @(posedge clk)
                if (load) f_dev <= {F_PW{1'b0}};
                else if (advance) f_dev <= f_dev + f_absw - (steps[f_i] ? f_maxw : {F_PW{1'b0}});
            always @(*)
                if (f_past_valid && !rst && run_q) begin
                    // the run stage holds the loaded segment's values
                    assert(f_hhold == f_abs);  // i_hold
                    assert(f_hstep == f_abs - f_run_max);  // i_step
                    assert(negative_q[f_i] == f_run_neg[f_i]);  // i_negative
                    assert(f_ewide == (f_dev << 1) + (f_absw << 1) - f_maxw - 1'b1);  // i_e
                    assert($signed(f_ewide) >= $signed(f_estep));  // a_e_low
                    assert($signed(f_ewide) < $signed(f_ehold));  // a_e_high
                    assert($signed(f_dev << 1) > -$signed(f_maxw)  // a_error
                           && $signed(f_dev << 1) <= $signed(f_maxw));
                    assert(f_abs <= f_run_max);  // i_abs_le_max
                    if (f_abs == f_run_max) begin
                        assert(steps[f_i]);  // a_longest
                    end
`ifdef F_ENDS
                    // the ghosts are m, Max, |d| and r (r >= 0 by a_steps_le) ...
                    assert(f_gm == {{W{1'b0}}, f_run_max - f_moves});  // i_gm
                    assert(f_gmax == {{W{1'b0}}, f_run_max});  // i_gmax
                    assert(f_gd == {{W{1'b0}}, f_abs});  // i_gd
                    assert(f_gr == {{W{1'b0}}, f_abs - f_s});  // i_gr
                    // ... and F = r Max - m |d| (the product invariant, linear in A, B)
                    assert(f_dev == {{(F_PW-2*W){1'b0}}, f_prod_b}
                                    - {{(F_PW-2*W){1'b0}}, f_prod_a});  // i_dev_ab
                    assert(f_s <= f_abs);  // a_steps_le
                    if (last) begin
                        assert(f_s + {{(W-1){1'b0}}, steps[f_i]} == f_abs);  // a_ends
                    end
`endif
                    if (last && f_i == 0) begin
                        assert(f_moves + ONE_W == f_run_max);  // a_last_move
                    end
                end
            always @(*)
                if (f_past_valid && !rst && validator_state_q != STATE_IDLE) begin
                    // the validator holds the command taken
                    assert(cmd_abs_q[f_i*W +: W] == f_slot_abs[f_i*W +: W]);  // i_cmd_abs
                    assert(f_slot_abs[f_i*W +: W] <= F_ABS_BOUND);  // i_slot_abs_bound
                    assert(cmd_negative_q[f_i] == f_slot_neg[f_i]);  // i_cmd_neg
                end
            // registered outputs: the step of the move before, in its direction
            always @(posedge clk)
                if (f_past_valid && !$past(rst) && !rst && $past(advance) && step[f_i]) begin
                    assert(dir[f_i] == !$past(f_run_neg[f_i]));  // a_dir
                end
            always @(posedge clk)
                if (f_past_valid && !$past(rst) && !rst && !step[f_i]) begin
                    assert(dir[f_i] == $past(dir[f_i]));  // a_dir_held
                end
        end
    endgenerate

    always @(*)
        if (f_past_valid && !rst && run_q) begin
            i_moves_left: assert(moves_left_q == f_run_max - f_moves);
            i_max_bound:  assert(f_run_max <= F_ABS_BOUND);
            a_moves:      assert(f_moves < f_run_max);
        end
    always @(*)
        if (f_past_valid && !rst && validator_state_q == STATE_HOLD) begin
            i_pend_live:  assert(f_slot_max != {W{1'b0}});
            i_pend_max:   assert(max_abs_q == f_slot_max);
        end

    always @(posedge clk)
        if (f_past_valid && !$past(rst) && !rst) begin
            a_move:   assert(move == $past(advance));
            a_step:   assert(step == ($past(advance) ? $past(steps) : {NA{1'b0}}));
            a_done:   assert(done == $past(last));
            a_reject: assert(reject == $past(rejecting));
            if (reject) begin
                a_err_code: assert(err_code == 2'd1);
            end
        end

    // ---- reachability (sby task cover) ----
    always @(posedge clk)
        if (f_past_valid && !rst) begin
            c_done:         cover(done);
            c_reject:       cover(reject);
            c_back_to_back: cover(load && last);
            // a segment whose last axis is neither the longest nor still
            c_short_axis:   cover(last && f_run_abs[(NA-1)*W +: W] != f_run_max
                                  && f_run_abs[(NA-1)*W +: W] != {W{1'b0}});
        end
`endif

endmodule

`default_nettype wire
