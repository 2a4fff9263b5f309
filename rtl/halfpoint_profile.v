// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// ============================================================================
// halfpoint_profile: the motion-profile stage -- speed register, credit,
// exit staircase, feed hold / stop / override
// ============================================================================
// Clock for clock the class ProfileStage of model/halfpoint/spec/profile.py
// (its docstring has the fixed-point table and the rules; this file keeps
// the model's names).  Per clock:
//   * the head move of the move queue pops (pop) when its credit covers its
//     cost (65536 for an axis move, 92682 for a diagonal arc move, the
//     segment's line_cost for a line iteration, BLU x 2^16), every axis it
//     steps is ready, and the stage is not stopped at rest; on the segment's
//     last move the next profile is taken (take) if available, the
//     distance s restarts at 0 and the credit's remainder is carried;
//   * the credit grows by the speed v, capped at twice the segment's largest
//     cost; the earned distance E = s + credit / 2^22 drives the exit
//     staircase: a speed limit that starts at the cruise speed when
//     E >= d_exit (or E >= d_stop with the next profile missing and a
//     non-zero exit speed: the dry queue, sticky flag dry) and steps down
//     by accel each time the earned distance covers one level (2^DIV clocks
//     of its speed), down to the exit speed (to the creep speed accel when
//     the exit speed is 0 or the queue is dry);
//   * the target is 0 under hold or stop, else the cruise speed scaled by
//     the override (a shift-add of 7 terms, no multiplier), limited by the
//     staircase; v steps by accel towards it, two steps in the same
//     direction at least 2^DIV clocks apart;
//   * stop at rest drops the segment and the credit (stopped); abort clears
//     everything but dry at the edge and makes pop, take, stopped and
//     holding 0 during its clock.
//
// pop, take, stopped and holding are combinational (the core uses them in
// the same clock); speed, dry and busy come from registers.
//
// Register widths (every register of the model, its range and why nothing
// overflows; units as in the model: speeds BLU per clock x 2^38, credit and
// ramp_left BLU x 2^38, distances BLU x 2^16):
//   v_q 38         <= the target, which is <= v_cruise x 2^6 < 2^38
//   credit_q 41    <= the cap 2 x (2^18 - 1) x 2^22 < 2^41 after every clock
//                  with a segment (42 bits before the cap: + v < 2^38)
//   s_q W+19       the popped costs of one segment, < 2^(W+19) (the caller's
//                  bound on a segment, as for d_exit); E needs W+20 bits
//   ramp_v_q 38    the cruise speed x 2^6, the exit speed x 2^6 or accel
//   ramp_left_q    signed, RW = max(W+43, DIV+40) bits, not the model
//                  table's DIV+40: see below
//   since_q DIV    clocks since the last speed step, minus 1, saturating at
//                  2^DIV - 1 (the model's 1 .. 2^DIV)
//   ov_target_q 38 the model's ov_q (0 .. 128, registered override) as its
//                  product with the cruise speed, (v_cruise << 6) x ov_q >> 7
//                  <= v_cruise x 2^6 < 2^38, registered at the same edge
//   cur_valid_q, the current profile (v_cruise_q, accel_q, line_cost_q,
//   d_exit_q, d_stop_q; v_exit as exit_speed_q with exit_nonzero_q, and the
//   credit cap cap_q, derived when the profile is taken), last_up_q /
//   last_down_q (the model's last_dir), dry_q, ramp_on_q, ramp_dry_q: as in
//   the model's table and class.
//
// ramp_left: the model's table gives DIV+40 bits (> -1 BLU per clock: one
// clock's gain past a level).  That holds when every level (2^DIV clocks of
// the staircase's speed) is longer than one clock's gain.  With profiles
// not from the host's planner, a segment entered at a speed v above 2^DIV
// times its staircase's speed steps on every clock and the remainder falls
// by about v each clock, for as long as the segment lasts; and on a
// segment's first clock the gain is negative when the carried credit is
// above the new segment's cap (a start then adds up to 2^41).  Bounds:
//   upper: a start gives ramp_v x 2^DIV - gain < 2^(38+DIV) + 2^41; a step
//          gives at most ramp_v x 2^DIV; otherwise it only falls (gain >= 0
//          whenever the staircase already ran on the previous clock, since
//          the credit is then within the segment's own cap);
//   lower: at least minus the sum of the positive gains since its start,
//          i.e. minus (credit at the end + the popped costs x 2^22 + one
//          negative gain) > -(2^41 + 2^(W+41) + 2^41) >= -2^(W+42).
// Both fit max(W+43, DIV+40) bits signed; the model's step decision
// ramp_left <= gain is then exact.
//
// Parameters: see the comment above each (an illegal value stops
// elaboration).
//
// Reset: synchronous, active high (ProfileStage.reset()).
// ============================================================================
module halfpoint_profile #(
    // position width of the core in bits, 8..32; distances are W + 19 bits
    // (profile.distance_bits)
    parameter integer W   = 32,
    // speed-step tick: 2^DIV clocks, 1..24
    parameter integer DIV = 12
) (
    input  wire          clk,
    input  wire          rst,        // synchronous, active high: ProfileStage.reset()
    input  wire          abort,      // ProfileInputs.abort

    /*
     * Head of the move queue
     */
    input  wire          head_valid,
    input  wire [1:0]    head_class, // 0 axis move, 1 diagonal arc move, 2 line iteration
    input  wire          head_last,
    input  wire          ready,      // every axis the head move steps is ready

    /*
     * The next segment's profile (fields of ProfileParams)
     */
    input  wire          next_valid,
    input  wire [31:0]   next_v_cruise,
    input  wire [31:0]   next_v_exit,
    input  wire [33:0]   next_accel,
    input  wire [17:0]   next_line_cost,
    input  wire [W+18:0] next_d_exit,
    input  wire [W+18:0] next_d_stop,

    /*
     * Motion control
     */
    input  wire          hold,
    input  wire          stop,
    input  wire [7:0]    override,   // 1/128 units, above 128 acts as 128

    /*
     * Combinational, during the clock (ProfileView)
     */
    output wire          pop,
    output wire          take,
    output wire          stopped,
    output wire          holding,

    /*
     * Registered (ProfileOutputs)
     */
    output wire [37:0]   speed,      // the speed register v, BLU per clock x 2^38
    output wire          dry,
    output wire          busy
);

    generate
        if (W < 8 || W > 32) begin : g_bad_w
            halfpoint_profile_illegal_parameter_W_must_be_8_to_32 u_bad ();
        end
        if (DIV < 1 || DIV > 24) begin : g_bad_div
            halfpoint_profile_illegal_parameter_DIV_must_be_1_to_24 u_bad ();
        end
    endgenerate

    localparam integer DW = W + 19;                             // distances
    localparam integer RW = (W + 43 > DIV + 40) ? W + 43 : DIV + 40;  // ramp_left
    localparam [17:0] COST_AXIS = 18'd65536;                    // 2^16
    localparam [17:0] COST_DIAGONAL = 18'd92682;                // round(sqrt(2) x 2^16)
    localparam [7:0] OVERRIDE_ONE = 8'd128;
    localparam [DIV-1:0] SINCE_ONE = 1;

    // ------------------------------------------------------------------
    // Registers
    // ------------------------------------------------------------------
    reg           cur_valid_q;      // a segment is current (the model's cur)
    reg  [31:0]   v_cruise_q;       // its fields (v_exit as exit_speed_q below)
    reg  [33:0]   accel_q;          // kept after the segment ends (the model's accel)
    reg  [17:0]   line_cost_q;
    reg  [DW-1:0] d_exit_q;
    reg  [DW-1:0] d_stop_q;
    // derived from the fields when the profile is taken (only their
    // function is used: no compare or OR tree in the clock's paths)
    reg           exit_nonzero_q;   // v_exit != 0
    reg  [37:0]   exit_speed_q;     // v_exit << 6, or the creep speed accel for 0
    reg  [40:0]   cap_q;            // twice the largest cost, x 2^22
    reg  [37:0]   v_q;              // speed
    reg  [40:0]   credit_q;
    reg  [DW-1:0] s_q;              // popped distance in the segment
    reg  [DIV-1:0] since_q;         // clocks since the last speed step - 1, saturating
    reg           last_up_q;        // direction of the last speed step
    reg           last_down_q;
    reg           dry_q;            // sticky: a dry queue forced a deceleration
    reg           ramp_on_q;        // the exit staircase
    reg           ramp_dry_q;
    reg  [37:0]   ramp_v_q;
    reg  [RW-1:0] ramp_left_q;      // two's complement

    // ------------------------------------------------------------------
    // Pop, take, stop, hold (ProfileStage.view)
    // ------------------------------------------------------------------
    wire          v_zero = (v_q == 38'd0);
    wire          at_rest_stop = stop && v_zero;
    reg  [17:0]   cost;             // of the head move (classes above 2 cost a line)
    always @(*) begin
        case (head_class)
            2'd0:    cost = COST_AXIS;
            2'd1:    cost = COST_DIAGONAL;
            default: cost = line_cost_q;
        endcase
    end
    wire [18:0]   credit_whole = credit_q[40:22];              // credit in cost units
    wire          can_pop = cur_valid_q && head_valid && (credit_whole >= {1'b0, cost});
    wire          pop_now = can_pop && ready && !at_rest_stop;
    wire          take_now = next_valid && (cur_valid_q ? (pop_now && head_last) : !stop);
    wire          segment_ends = pop_now && head_last;

    assign pop     = pop_now && !abort;
    assign take    = take_now && !abort;
    assign stopped = at_rest_stop && !abort;
    assign holding = hold && v_zero && !can_pop && !abort;

    // ------------------------------------------------------------------
    // Credit: + v, - the popped cost, capped at twice the largest cost.
    // Both outcomes (the head pops or not) are computed side by side from
    // the registers and the head's cost; pop_now only selects between them,
    // so the pop decision does not sit in front of the adders.
    // ------------------------------------------------------------------
    wire [40:0]   cap = cap_q;
    wire [40:0]   cost_credit = {1'b0, cost, 22'd0};                    // cost x 2^22
    wire [41:0]   credit_sum = {1'b0, credit_q} + {4'd0, v_q};         // < 2^41 + 2^38
    wire [41:0]   cap_plus_cost = {1'b0, cap} + {1'b0, cost_credit};   // < 2^42
    // capped: credit - spent + v > cap, i.e. credit + v > cap + spent
    wire          capped_keep = (credit_sum > {1'b0, cap});
    wire          capped_pop = (credit_sum > cap_plus_cost);
    wire          capped = pop_now ? capped_pop : capped_keep;
    // credit - cost + v when it pops (spent <= credit_q: a pop needs
    // credit_whole >= cost); used only uncapped, so below the cap < 2^41
    wire [40:0]   credit_popped = credit_sum[40:0] - cost_credit;
    wire [40:0]   credit_new = capped ? cap : (pop_now ? credit_popped : credit_sum[40:0]);
    // the earned distance grows by gain = credit_new - (credit - spent): v, or
    // the headroom cap - (credit - spent) when capped; negative only on a
    // segment's first clock (carried credit above the new cap), > -2^41: 42
    // bits two's complement
    wire [41:0]   headroom_keep = {1'b0, cap} - {1'b0, credit_q};
    wire [41:0]   headroom_pop = cap_plus_cost - {1'b0, credit_q};
    wire [41:0]   headroom = pop_now ? headroom_pop : headroom_keep;
    wire [41:0]   gain = capped ? headroom : {4'd0, v_q};
    wire [RW-1:0] gain_wide = {{(RW-42){gain[41]}}, gain};
    // ramp_left <= gain, each outcome compared on its own
    wire          left_le_v = ($signed(ramp_left_q) <= $signed({{(RW-38){1'b0}}, v_q}));
    wire          left_le_keep = ($signed(ramp_left_q)
                                  <= $signed({{(RW-42){headroom_keep[41]}}, headroom_keep}));
    wire          left_le_pop = ($signed(ramp_left_q)
                                 <= $signed({{(RW-42){headroom_pop[41]}}, headroom_pop}));
    wire          left_le_gain = !capped ? left_le_v : (pop_now ? left_le_pop : left_le_keep);

    // earned distance E = s + credit / 2^22 (W + 20 bits: no carry lost)
    wire [DW:0]   earned = {1'b0, s_q} + {{(DW-18){1'b0}}, credit_whole};
    wire          past_exit = (earned >= {1'b0, d_exit_q});
    wire          past_stop = (earned >= {1'b0, d_stop_q});

    // ------------------------------------------------------------------
    // Exit staircase (ProfileStage._ramp)
    // ------------------------------------------------------------------
    // ov_target_q: the override applied to the cruise speed, registered
    // (see below); every candidate for the staircase's speed is compared
    // with it side by side
    reg  [37:0]   ov_target_q;
    wire          exit_nonzero = exit_nonzero_q;
    wire [37:0]   exit_speed = exit_speed_q;
    wire [37:0]   cruise = {v_cruise_q, 6'd0};
    wire          dry_condition = !next_valid && exit_nonzero;
    // a step happens only while the staircase runs on (ramp_on_q, and not
    // returning from the dry mode), where its speed is ramp_v_q and the
    // floor is the one of ramp_dry_q: the stepped speed comes from registers
    wire [37:0]   floor_held = ramp_dry_q ? {4'd0, accel_q} : exit_speed;
    wire [38:0]   ramp_down = {1'b0, ramp_v_q} - {5'd0, accel_q};
    wire          ramp_below = ramp_down[38] || (ramp_down[37:0] < floor_held);
    wire [37:0]   ramp_stepped = ramp_below ? floor_held : ramp_down[37:0];
    wire          stepped_under = (ramp_stepped < ov_target_q);
    wire          cruise_under = (cruise < ov_target_q);
    wire          held_under = (ramp_v_q < ov_target_q);
    wire          exit_under = (exit_speed < ov_target_q);
    reg           ramp_on_n;        // after this edge (before the segment's end clears it)
    reg           ramp_dry_n;
    reg           ramp_start;
    reg           ramp_step;
    reg  [37:0]   ramp_v_a;         // the staircase's speed unless it steps
    reg           ramp_a_under;     // ramp_v_a < ov_target_q
    always @(*) begin
        ramp_on_n    = ramp_on_q;
        ramp_dry_n   = ramp_dry_q;
        ramp_start   = 1'b0;
        ramp_step    = 1'b0;
        ramp_v_a     = ramp_v_q;
        ramp_a_under = held_under;
        if (!ramp_on_q) begin
            if (past_exit) begin
                ramp_on_n    = 1'b1;
                ramp_start   = 1'b1;
                ramp_v_a     = cruise;
                ramp_a_under = cruise_under;
            end else if (past_stop && dry_condition) begin
                ramp_on_n    = 1'b1;
                ramp_start   = 1'b1;
                ramp_dry_n   = 1'b1;
                ramp_v_a     = cruise;
                ramp_a_under = cruise_under;
            end
        end else if (ramp_dry_q && !dry_condition) begin
            // the next profile came: back to the plan
            ramp_dry_n = 1'b0;
            if (!past_exit) begin
                ramp_on_n = 1'b0;
            end else if (exit_speed > ramp_v_q) begin
                ramp_v_a     = exit_speed;
                ramp_a_under = exit_under;
            end
        end else begin
            // this clock ends the level
            ramp_step = left_le_gain;
        end
    end
    wire [37:0]   ramp_v_n = ramp_step ? ramp_stepped : ramp_v_a;
    wire          ramp_under = ramp_step ? stepped_under : ramp_a_under;
    // distance left in the level; a level is 2^DIV clocks of its speed
    wire [RW-1:0] level_start = {{(RW-38){1'b0}}, ramp_v_a} << DIV;
    wire [RW-1:0] level_next = {{(RW-38){1'b0}}, ramp_stepped} << DIV;
    wire [RW-1:0] ramp_left_n = (ramp_start ? level_start : ramp_left_q) - gain_wide
                                + (ramp_step ? level_next : {RW{1'b0}});
    wire          dry_now = cur_valid_q && ramp_on_n && ramp_dry_n;

    // ------------------------------------------------------------------
    // Target: the override on the cruise speed, the staircase, hold/stop
    // ------------------------------------------------------------------
    // The model's (v_cruise << 6) * ov_q >> 7, with ov_q the override of the
    // previous clock and v_cruise the current segment's, computed at the
    // edge that registers ov_q (from the override input, clipped at 128) and
    // loads v_cruise (on take): ov_target_q holds it during the clock.  With
    // ov <= 128: ov = 128 gives the cruise speed; else the sum of
    // v_cruise << b over the set bits b < 7 (< 127 x 2^32 < 2^39), shifted
    // left by 6 and right by 7, i.e. halved.  Only the b = 0 term has a bit
    // 0, so the half is exact term by term: v_cruise >> 1 for b = 0,
    // v_cruise << (b - 1) for the others; the sum is < 2^38.
    wire [7:0]    ov_n = (override > OVERRIDE_ONE) ? OVERRIDE_ONE : override;
    wire [31:0]   cruise_n = take_now ? next_v_cruise : v_cruise_q;
    wire [37:0]   ov_term0 = ov_n[0] ? {7'd0, cruise_n[31:1]} : 38'd0;
    wire [37:0]   ov_term1 = ov_n[1] ? {6'd0, cruise_n}       : 38'd0;
    wire [37:0]   ov_term2 = ov_n[2] ? {5'd0, cruise_n, 1'b0} : 38'd0;
    wire [37:0]   ov_term3 = ov_n[3] ? {4'd0, cruise_n, 2'd0} : 38'd0;
    wire [37:0]   ov_term4 = ov_n[4] ? {3'd0, cruise_n, 3'd0} : 38'd0;
    wire [37:0]   ov_term5 = ov_n[5] ? {2'd0, cruise_n, 4'd0} : 38'd0;
    wire [37:0]   ov_term6 = ov_n[6] ? {1'd0, cruise_n, 5'd0} : 38'd0;
    wire [37:0]   ov_half = ((ov_term0 + ov_term1) + (ov_term2 + ov_term3))
                            + ((ov_term4 + ov_term5) + ov_term6);
    wire [37:0]   ov_target_n = ov_n[7] ? {cruise_n, 6'd0} : ov_half;
    wire [37:0]   limited = (ramp_on_n && ramp_under) ? ramp_v_n : ov_target_q;
    wire [37:0]   target = (!cur_valid_q || hold || stop) ? 38'd0 : limited;

    // ------------------------------------------------------------------
    // Speed: one step of accel towards the target, same-direction steps a
    // tick apart
    // ------------------------------------------------------------------
    wire          tick_done = &since_q;
    wire          step_up = (target > v_q) && (!last_up_q || tick_done);
    wire          step_down = (target < v_q) && (!last_down_q || tick_done);
    wire [38:0]   v_plus = {1'b0, v_q} + {5'd0, accel_q};
    wire [38:0]   v_minus = {1'b0, v_q} - {5'd0, accel_q};
    wire [37:0]   v_up = (v_plus > {1'b0, target}) ? target : v_plus[37:0];
    wire [37:0]   v_down = (v_minus[38] || v_minus[37:0] < target) ? target : v_minus[37:0];
    wire [37:0]   v_n = step_up ? v_up : (step_down ? v_down : v_q);

    wire          cur_valid_n = take_now || (cur_valid_q && !at_rest_stop && !segment_ends);

    always @(posedge clk) begin
        if (rst || abort) begin
            cur_valid_q <= 1'b0;
            accel_q     <= 34'd0;
            v_q         <= 38'd0;
            credit_q    <= 41'd0;
            s_q         <= {DW{1'b0}};
            since_q     <= {DIV{1'b1}};
            last_up_q   <= 1'b0;
            last_down_q <= 1'b0;
            ramp_on_q   <= 1'b0;
            ramp_dry_q  <= 1'b0;
            ramp_v_q    <= 38'd0;
            ramp_left_q <= {RW{1'b0}};
        end else begin
            // speed and its cadence; no segment after this edge: the speed is 0
            v_q <= cur_valid_n ? v_n : 38'd0;
            if (step_up || step_down) begin
                last_up_q   <= step_up;
                last_down_q <= step_down;
                since_q     <= {DIV{1'b0}};
            end else if (!tick_done) begin
                since_q <= since_q + SINCE_ONE;
            end
            // credit and distance
            if (at_rest_stop) begin
                credit_q <= 41'd0;
                s_q      <= {DW{1'b0}};
            end else if (cur_valid_q) begin
                credit_q <= credit_new;
                if (segment_ends) begin
                    s_q <= {DW{1'b0}};
                end else if (pop_now) begin
                    s_q <= s_q + {{(DW-18){1'b0}}, cost};
                end
            end
            // the exit staircase; it ends with its segment
            if (cur_valid_q && ramp_on_n && !segment_ends && !at_rest_stop) begin
                ramp_on_q   <= 1'b1;
                ramp_dry_q  <= ramp_dry_n;
                ramp_left_q <= ramp_left_n;
            end else begin
                ramp_on_q   <= 1'b0;
                ramp_dry_q  <= 1'b0;
                ramp_left_q <= {RW{1'b0}};
            end
            ramp_v_q <= cur_valid_q ? ramp_v_n : 38'd0;
            // the segment
            cur_valid_q <= cur_valid_n;
            if (take_now) accel_q <= next_accel;
        end
    end

    // the current profile's fields: loaded on take, meaningless without a segment
    always @(posedge clk) begin
        if (take_now && !rst && !abort) begin
            v_cruise_q  <= next_v_cruise;
            line_cost_q <= next_line_cost;
            d_exit_q    <= next_d_exit;
            d_stop_q    <= next_d_stop;
            exit_nonzero_q <= (next_v_exit != 32'd0);
            exit_speed_q   <= (next_v_exit != 32'd0) ? {next_v_exit, 6'd0} : {4'd0, next_accel};
            cap_q <= {(next_line_cost != 18'd0) ? next_line_cost : COST_DIAGONAL, 23'd0};
        end
    end

    // dry survives abort
    always @(posedge clk) begin
        if (rst) begin
            dry_q <= 1'b0;
        end else if (dry_now && !abort) begin
            dry_q <= 1'b1;
        end
    end

    // the override target of the next clock, on every edge (the model's ov_q
    // is registered on every edge, abort included; without a segment the
    // value is not used, and the edge that takes one computes it afresh)
    always @(posedge clk) begin
        ov_target_q <= ov_target_n;
    end

    assign speed = v_q;
    assign dry   = dry_q;
    assign busy  = cur_valid_q || !v_zero;

endmodule

`default_nettype wire
