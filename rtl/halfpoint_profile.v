// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// ============================================================================
// halfpoint_profile: the motion-profile stage -- speed register, credit,
// exit staircase, feed hold / stop / override
// ============================================================================
// Clock for clock the class ProfileStage of model/halfpoint/spec/profile.py
// (its docstring has the fixed-point table and the rules; this file keeps
// the model's names).  Every register's next value is at most one carry
// chain (with carry-save levels in front where three or four operands
// meet) away from registers; the pop is the one decision taken in the clock.
// Per clock:
//   * the head move of the move queue pops (pop) when its credit covers its
//     cost (65536 for an axis move, 92682 for a diagonal arc move, the
//     segment's line_cost for a line iteration, BLU x 2^16; the three
//     compares from registers, the head's class selects), every axis it
//     steps is ready, and the stage is neither stopped nor held at rest
//     (at rest under hold nothing pops, not even a move the credit covers:
//     holding = hold and v = 0, no step until the release); on the segment's
//     last move the next profile is taken (take) if available, the
//     distance s restarts at 0 and the credit's remainder is carried;
//   * the credit grows by the gain: v, or 0 when it was at its cap (twice
//     the segment's largest cost) a clock ago; the earned distance
//     E = s + credit / 2^22 is compared with d_exit and d_stop and the
//     results registered (past_exit_q, past_stop_q);
//   * the exit staircase starts at the cruise speed on a clock with
//     past_exit_q (or past_stop_q with the next profile missing and a
//     non-zero exit speed: the dry queue; its first step sets the sticky
//     dry) and steps down by accel on each clock that starts with its
//     remainder ramp_left_q negative, unless it started, stepped or returned
//     from the dry queue at the edge before (ramp_changed_q: its next level
//     is made from its registers a clock after they change), down to the exit
//     speed (to the creep speed accel when the exit speed is 0 or the queue is
//     dry); the remainder falls by the gain and a step adds the next level,
//     (stepped << DIV) + 4 x the step;
//   * the target of the next clock is registered: 0 under hold or stop or
//     without a segment, else the least of the override's product, the
//     cruise speed and the running staircase; v steps by accel towards
//     target_q, two steps in the same direction at least 2^DIV clocks apart;
//   * stop at rest drops the segment and the credit (stopped); abort_now
//     clears everything but dry at the edge and makes pop, take, stopped
//     and holding 0 during its clock.
//
// pop, take, stopped and holding are combinational (the core uses them in
// the same clock); speed, dry and busy come from registers.
//
// Register widths (every register of the model, its range and why nothing
// overflows; units as in the model: speeds BLU per clock x 2^38, credit and
// ramp_left BLU x 2^38, distances BLU x 2^16):
//   v_q, target_q 38   <= v_cruise x 2^6 < 2^38
//   credit_q 42    < cap + 2 v < 2^41 + 2^39 (v is still added on the clock
//                  after the credit reached the cap; no gain at or above
//                  2^41 whatever the segment, so also across takes)
//   gain_q 38      the model's 0-if-full-else-v, registered with v_q
//   s_q W+19       the popped costs of one segment, < 2^(W+19) (the caller's
//                  bound on a segment, as for d_exit); E needs W+20 bits
//   ramp_v_q 38    the cruise speed x 2^6, the exit speed x 2^6 or accel
//   ramp_left_q    DIV+42 bits signed: a level is < 2^(DIV+38) + 2^40 and is
//                  added only to a negative remainder; saturates at
//                  -2^(DIV+40) (profile.ramp_left_floor); not cleared while
//                  the staircase is off (a start loads it)
//   since_q DIV    clocks since the last speed step, minus 1, saturating at
//                  2^DIV - 1 (the model's 1 .. 2^DIV)
//   ov_q 8, ov_acc_q 38, ov_count_q 4, ov_target_q 38: the override
//                  clipped at 128 and its product with v_cruise_q, bit by bit
//                  (ov_acc <= v_cruise x 2^6, see there; ov_target <=
//                  v_cruise x 2^6)
//   cruise_level_q, accel_level_q, exit_level_q DIV+42: cruise x (2^DIV-1),
//                  accel x (2^DIV-4), exit speed x (2^DIV-4), signed; with
//                  exit_speed_q, exit_plus_accel_q and exit_nonzero_q
//                  derived on every edge from the current fields (v_cruise_q,
//                  accel_q, v_exit_q), right from a segment's second clock,
//                  the first the staircase can start on; cap_q is loaded
//                  with the fields
//   Kept beside the model's registers, so that each decision comes from the
//   sign of a register or one carry chain from registers (the test checks
//   each against the model's values every clock it is meaningful):
//   covers_axis_q, covers_diagonal_q: credit >= cost << 22 for the axis
//                  and the diagonal cost; over_line_q 21 signed: (credit >>
//                  22) - line_cost (> -2^18, < 2^20), the whole part of credit
//                  - (line_cost << 22), whose fraction bits are the credit's;
//                  the three are the pop's compares
//   tick_done_q    since_q at its top
//   ramp_down_level_q, ramp_floor_level_q DIV+42 signed, ramp_below_q: the
//                  level the staircase adds at its next step, stepping down
//                  by accel ((ramp_v << DIV) - accel_level) or to the floor
//                  (floor_level + 4 ramp_v), and which way it steps (ramp_v <
//                  floor + accel); made on every edge from ramp_v_q,
//                  ramp_dry_q and the segment's level constants, so they are
//                  the staircase's a clock after it moves, when it may step
//                  again (ramp_changed_q, the model's ramp_changed: it
//                  started, stepped or returned at the edge before)
//   cur_valid_q, v_cruise_q, accel_q (both kept after the segment),
//   line_cost_q, d_exit_q, d_stop_q, v_exit_q, last_up_q / last_down_q (the
//   model's last_dir), dry_q, past_exit_q, past_stop_q, ramp_on_q,
//   ramp_dry_q: as in the model's table and class.
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
    input  wire          abort_now,  // ProfileInputs.abort

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
    // ProfileInputs.override: 1/128 units, above 128 acts as 128
    input  wire [7:0]    feed_override,

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
    localparam integer RW = DIV + 42;                           // ramp_left
    localparam integer VW = 38;                                 // speeds
    localparam integer HW = 21;                                 // credit less a cost, whole
    localparam [17:0] COST_AXIS = 18'd65536;                    // 2^16
    localparam [17:0] COST_DIAGONAL = 18'd92682;                // round(sqrt(2) x 2^16)
    localparam [7:0] OVERRIDE_ONE = 8'd128;
    localparam [19:0] DIAGONAL_WHOLE = {2'd0, COST_DIAGONAL};    // credit_whole covering it
    localparam [DIV-1:0] SINCE_ONE = 1;
    localparam [DIV-1:0] SINCE_LAST = {DIV{1'b1}} - SINCE_ONE;  // the count before the top

    // ------------------------------------------------------------------
    // Registers
    // ------------------------------------------------------------------
    reg           cur_valid_q;      // a segment is current (the model's cur)
    reg  [31:0]   v_cruise_q;       // its fields, v_cruise and accel kept after it ends
    reg  [33:0]   accel_q;
    reg  [17:0]   line_cost_q;
    reg  [DW-1:0] d_exit_q;
    reg  [DW-1:0] d_stop_q;
    reg  [31:0]   v_exit_q;
    // the cap, twice the largest cost x 2^22, over 2^23 (its bits below are 0):
    // the largest cost, loaded with them
    reg  [17:0]   cap_q;
    // derived from the fields on the clock after the take
    reg           exit_nonzero_q;   // v_exit != 0
    reg  [37:0]   exit_speed_q;     // v_exit << 6, or the creep speed accel for 0
    reg  [38:0]   exit_plus_accel_q;    // exit_speed + accel
    reg  [RW-1:0] cruise_level_q;   // (v_cruise << 6) x (2^DIV - 1): the first level
    reg  [RW-1:0] accel_level_q;    // accel x (2^DIV - 4), signed
    reg  [RW-1:0] exit_level_q;     // exit_speed x (2^DIV - 4), signed
    reg  [37:0]   v_q;              // speed
    reg  [37:0]   target_q;         // its target, a clock ahead
    reg  [41:0]   credit_q;
    // the compares of the credit with the three costs, kept beside it: credit
    // >= 65536 << 22 and >= 92682 << 22, and (credit >> 22) - line_cost, HW
    // bits signed, whose sign is the third (updated as the credit, with the
    // line cost the next segment's from a take on).  A cost has no fraction
    // bits, so credit - (cost << 22) has the credit's 22 fraction bits and the
    // whole part (credit >> 22) - cost: only that part is kept
    reg           covers_axis_q;
    reg           covers_diagonal_q;
    reg  [HW-1:0] over_line_q;
    // the credit's gain: 0 when the credit was at its cap a clock ago (the
    // model's full), else v (a copy of v_q for the credit's paths)
    reg  [37:0]   gain_q;
    reg  [DW-1:0] s_q;              // popped distance in the segment
    reg  [DIV-1:0] since_q;         // clocks since the last speed step - 1, saturating
    reg           tick_done_q;      // since_q is at its top (a tick since the last step)
    reg           last_up_q;        // direction of the last speed step
    reg           last_down_q;
    reg           dry_q;            // sticky: a dry queue forced a deceleration
    reg  [7:0]    ov_q;             // the override, clipped at 128
    reg  [37:0]   ov_acc_q;         // the override's product so far
    reg  [3:0]    ov_count_q;       // its steps still to go, 8 .. 0
    reg  [37:0]   ov_target_q;
    reg           past_exit_q;      // E >= d_exit a clock ago
    reg           past_stop_q;      // E >= d_stop a clock ago
    reg           ramp_on_q;        // the exit staircase
    reg           ramp_dry_q;
    reg  [37:0]   ramp_v_q;
    reg  [RW-1:0] ramp_left_q;      // two's complement
    // the staircase's next level, ready for either way of its next step:
    // (ramp_v << DIV) - accel_level (a step down by accel) and floor_level +
    // 4 ramp_v (a step to the floor), floor_level that of the floor it heads
    // for; and ramp_v < floor + accel (which way).  Made from the staircase's
    // speed and floor of the clock before: read only when it has not moved
    // since (ramp_changed_q low)
    reg  [RW-1:0] ramp_down_level_q;
    reg  [RW-1:0] ramp_floor_level_q;
    reg           ramp_below_q;
    reg           ramp_changed_q;   // it started, stepped or returned at the edge before

    // ------------------------------------------------------------------
    // Pop, take, stop, hold (ProfileStage.view)
    // ------------------------------------------------------------------
    // v_q == 0, registered with v_q (so that stop / hold at rest, which the core
    // fans out to its flush, start from a flip-flop)
    reg           v_zero_q;
    wire          v_zero = v_zero_q;
    wire          at_rest_stop = stop && v_zero;
    reg  [17:0]   cost;             // of the head move (classes above 2 cost a line)
    always @(*) begin
        case (head_class)
            2'd0:    cost = COST_AXIS;
            2'd1:    cost = COST_DIAGONAL;
            default: cost = line_cost_q;
        endcase
    end
    wire [19:0]   credit_whole = credit_q[41:22];              // credit in cost units
    // the credit against each cost from registers alone (two compares and
    // the sign of the credit less the line cost, kept beside it); the head's
    // class selects among them, so the inputs only meet the last LUTs
    wire          covers_axis = covers_axis_q;
    wire          covers_diagonal = covers_diagonal_q;
    wire          covers_line = !over_line_q[HW-1];
    reg           covers;
    always @(*) begin
        case (head_class)
            2'd0:    covers = covers_axis;
            2'd1:    covers = covers_diagonal;
            default: covers = covers_line;
        endcase
    end
    // everything else of pop and take, side by side with the compares
    wire          at_rest_hold = hold && v_zero;
    wire          pop_ok = cur_valid_q && head_valid && ready && !at_rest_stop &&
                           !at_rest_hold;
    wire          take_last = next_valid && head_last;
    wire          take_idle = next_valid && !cur_valid_q && !stop;
    wire          pop_now = covers && pop_ok;
    // what the pop decides, as the last select (a pop means a segment, not
    // stopped at rest, and no take without one)
    wire          segment_runs = cur_valid_q && !at_rest_stop;
    wire          take_now = pop_now ? take_last : take_idle;

    assign pop     = covers && pop_ok && !abort_now;
    assign take    = ((covers && pop_ok && take_last) || take_idle) && !abort_now;
    assign stopped = at_rest_stop && !abort_now;
    assign holding = at_rest_hold && !abort_now;

    // ------------------------------------------------------------------
    // Credit: + v unless it was at its cap a clock ago, - the popped cost;
    // both outcomes side by side, pop_now selects
    // ------------------------------------------------------------------
    wire [37:0]   gain = gain_q;
    wire [41:0]   credit_keep = credit_q + {4'd0, gain};
    // credit + gain - (cost << 22): one carry-save level, the +1 of the
    // negated cost in the free bit 0 of the carries
    wire [41:0]   cp_a = credit_q;
    wire [41:0]   cp_b = {4'd0, gain};
    wire [41:0]   cp_c = ~{2'd0, cost, 22'd0};
    wire [41:0]   cp_sum = cp_a ^ cp_b ^ cp_c;
    wire [40:0] cp_maj = (cp_a[40:0] & cp_b[40:0]) | (cp_a[40:0] & cp_c[40:0])
                         | (cp_b[40:0] & cp_c[40:0]);
    wire [41:0]   credit_popped = cp_sum + {cp_maj, 1'b1};
    // without a pop: 0 when stopped at rest, + gain with a segment, else
    // kept (and the line cost the next segment's on a take); a pop selects
    // last
    wire [41:0]   credit_rest = at_rest_stop ? 42'd0
                                : (cur_valid_q ? credit_keep : credit_q);
    // the compares with the axis and the diagonal cost after this edge, for
    // both outcomes of the pop: credit >= 2^38 is a set bit among the top
    // four; the diagonal cost is compared with the whole part
    wire          axis_keep = |credit_keep[41:38];
    wire          axis_popped = |credit_popped[41:38];
    wire          diagonal_keep = (credit_keep[41:22] >= DIAGONAL_WHOLE);
    wire          diagonal_popped = (credit_popped[41:22] >= DIAGONAL_WHOLE);
    wire          axis_rest = !at_rest_stop && (cur_valid_q ? axis_keep : covers_axis_q);
    wire          diagonal_rest = !at_rest_stop && (cur_valid_q ? diagonal_keep
                                                               : covers_diagonal_q);
    // the credit less the line cost, whole part: the same sums on HW bits,
    // the gain's whole part with the carry out of the fraction bits (credit +
    // gain there) as carry-in: {a, c} + {b, c} is 2 (a + b + c) + 0; - cost
    // and the +1 of its negation in a carry-save level
    wire          gain_carry = credit_keep[22] ^ credit_q[22] ^ gain[22];
    wire [HW-1:0] gain_whole = {{(HW-16){1'b0}}, gain[37:22]};
    wire [HW-1:0] cost_neg = ~{{(HW-18){1'b0}}, cost};
    wire [HW:0]   ol_keep_c = {over_line_q, gain_carry} + {gain_whole, gain_carry};
    wire [HW-1:0] ol_keep = ol_keep_c[HW:1];
    wire [HW-1:0] ol_x = over_line_q ^ gain_whole ^ cost_neg;
    wire [HW-2:0] ol_m = (over_line_q[HW-2:0] & gain_whole[HW-2:0])
                         | (over_line_q[HW-2:0] & cost_neg[HW-2:0])
                         | (gain_whole[HW-2:0] & cost_neg[HW-2:0]);
    wire [HW:0]   ol_popped_c = {ol_x, gain_carry} + {ol_m, 1'b1, gain_carry};
    wire [HW-1:0] ol_popped = ol_popped_c[HW:1];
    // a take on the segment's last move: credit + gain - cost - next line
    // cost, two carry-save levels; a take without a segment: credit - next
    // line cost; stop at rest: 0 - line cost
    wire [HW-1:0] credit_high = {1'b0, credit_whole};
    wire [HW-1:0] next_line_neg = ~{{(HW-18){1'b0}}, next_line_cost};
    wire [HW-1:0] ot_x = credit_high ^ gain_whole ^ cost_neg;
    wire [HW-2:0] ot_m = (credit_high[HW-2:0] & gain_whole[HW-2:0])
                         | (credit_high[HW-2:0] & cost_neg[HW-2:0])
                         | (gain_whole[HW-2:0] & cost_neg[HW-2:0]);
    wire [HW-1:0] ot_y = {ot_m, 1'b1};
    wire [HW-1:0] ot_x2 = ot_x ^ ot_y ^ next_line_neg;
    wire [HW-2:0] ot_m2 = (ot_x[HW-2:0] & ot_y[HW-2:0]) | (ot_x[HW-2:0] & next_line_neg[HW-2:0])
                          | (ot_y[HW-2:0] & next_line_neg[HW-2:0]);
    wire [HW:0]   ol_take_c = {ot_x2, gain_carry} + {ot_m2, 1'b1, gain_carry};
    wire [HW-1:0] ol_take = ol_take_c[HW:1];
    // bit 0 of the three sums with a carry-in is 0 and not used
    wire          unused_carry_in_bits = ol_keep_c[0] ^ ol_popped_c[0] ^ ol_take_c[0];
    wire [HW-1:0] ol_idle = credit_high - {{(HW-18){1'b0}}, next_line_cost};
    wire [HW-1:0] ol_stop = {HW{1'b0}} - {{(HW-18){1'b0}}, line_cost_q};
    wire [HW-1:0] ol_rest = at_rest_stop ? ol_stop
                            : (cur_valid_q ? ol_keep : (take_idle ? ol_idle : over_line_q));
    wire [DW-1:0] s_plus = s_q + {{(DW-18){1'b0}}, cost};
    wire [DW-1:0] s_rest = at_rest_stop ? {DW{1'b0}} : s_q;
    // the cap has no bits below 2^23 (a cost x 2^23): only the bits above compare
    wire          at_cap = (credit_q[41:23] >= {1'b0, cap_q});

    // earned distance E = s + credit / 2^22 against d_exit and d_stop:
    // s + credit_whole - d >= 0, one carry-save level and one carry chain each
    wire [DW+1:0] e_s = {2'd0, s_q};
    wire [DW+1:0] e_c = {{(DW-18){1'b0}}, credit_whole};
    wire [DW+1:0] ex_d = ~{2'd0, d_exit_q};
    wire [DW+1:0] ex_sum = e_s ^ e_c ^ ex_d;
    wire [DW:0]   ex_maj = (e_s[DW:0] & e_c[DW:0]) | (e_s[DW:0] & ex_d[DW:0])
                           | (e_c[DW:0] & ex_d[DW:0]);
    wire [DW+1:0] ex_diff = ex_sum + {ex_maj, 1'b1};
    wire [DW+1:0] st_d = ~{2'd0, d_stop_q};
    wire [DW+1:0] st_sum = e_s ^ e_c ^ st_d;
    wire [DW:0]   st_maj = (e_s[DW:0] & e_c[DW:0]) | (e_s[DW:0] & st_d[DW:0])
                           | (e_c[DW:0] & st_d[DW:0]);
    wire [DW+1:0] st_diff = st_sum + {st_maj, 1'b1};
    wire          earned_past_exit = !ex_diff[DW+1];
    wire          earned_past_stop = !st_diff[DW+1];

    // ------------------------------------------------------------------
    // Exit staircase (ProfileStage._ramp): every decision from registers
    // ------------------------------------------------------------------
    wire [37:0]   cruise = {v_cruise_q, 6'd0};
    wire          dry_condition = !next_valid && exit_nonzero_q;
    wire [37:0]   floor_held = ramp_dry_q ? {4'd0, accel_q} : exit_speed_q;
    wire [38:0]   floor_plus_accel = ramp_dry_q ? {4'd0, accel_q, 1'b0} : exit_plus_accel_q;
    wire [37:0]   ramp_down = ramp_v_q - {4'd0, accel_q};
    wire [37:0]   ramp_stepped = ramp_below_q ? floor_held : ramp_down;
    wire          exit_above = (exit_speed_q > ramp_v_q);
    reg           ramp_on_n;        // after this edge (before the segment's end clears it)
    reg           ramp_dry_n;
    reg           ramp_start;
    reg           ramp_step;
    reg  [37:0]   ramp_v_a;         // the staircase's speed unless it steps
    always @(*) begin
        ramp_on_n  = ramp_on_q;
        ramp_dry_n = ramp_dry_q;
        ramp_start = 1'b0;
        ramp_step  = 1'b0;
        ramp_v_a   = ramp_v_q;
        if (!ramp_on_q) begin
            if (past_exit_q) begin
                ramp_on_n  = 1'b1;
                ramp_start = 1'b1;
                ramp_v_a   = cruise;
            end else if (past_stop_q && dry_condition) begin
                ramp_on_n  = 1'b1;
                ramp_start = 1'b1;
                ramp_dry_n = 1'b1;
                ramp_v_a   = cruise;
            end
        end else if (ramp_dry_q && !dry_condition) begin
            // the next profile came: back to the plan
            ramp_dry_n = 1'b0;
            if (!past_exit_q) begin
                ramp_on_n = 1'b0;
            end else if (exit_above) begin
                ramp_v_a = exit_speed_q;
            end
        end else begin
            // the level ran out on an earlier clock, and the level registers
            // are of the staircase as it is (it did not move at the edge before)
            ramp_step = ramp_left_q[RW-1] && !ramp_changed_q;
        end
    end
    wire [37:0]   ramp_v_n = ramp_step ? ramp_stepped : ramp_v_a;
    // the next level for the staircase as it is now, for either way of its
    // next step, and which way it goes (ramp_below: ramp_v < floor + accel),
    // each one carry chain from registers; registered, they are read from the
    // clock after, and only if the staircase did not move at that edge
    // (ramp_changed_q), so they are always those of its speed and floor
    wire          dry_return = ramp_on_q && ramp_dry_q && !dry_condition;
    wire [RW-1:0] ramp_v_wide = {{(RW-38){1'b0}}, ramp_v_q};
    // floor x (2^DIV - 4): accel's when dry, else the exit speed's
    wire [RW-1:0] floor_level = ramp_dry_q ? accel_level_q : exit_level_q;
    // (ramp_v - accel) << DIV + 4 accel, and floor << DIV + 4 (ramp_v - floor)
    wire [RW-1:0] ramp_down_level_n = (ramp_v_wide << DIV) - accel_level_q;
    wire [RW-1:0] ramp_floor_level_n = floor_level + (ramp_v_wide << 2);
    wire          ramp_below_n = ({1'b0, ramp_v_q} < floor_plus_accel);
    // the remainder: - gain every clock; a step adds the next level,
    // (stepped << DIV) + 4 x (ramp_v - stepped), i.e. (ramp_v << DIV) -
    // accel x (2^DIV - 4) unclamped and floor x (2^DIV - 4) + (ramp_v << 2)
    // at the floor; each as two carry-save levels and one carry chain
    wire [RW-1:0] gain_wide = {{(RW-38){1'b0}}, gain};
    wire [RW-1:0] gain_neg = ~gain_wide;                        // -gain - 1
    // the remainder held: - gain; while the staircase is off it is loaded
    // with the first level (its value there is not used), so a start needs
    // no candidate of its own
    wire [RW-1:0] left_base = ramp_on_q ? ramp_left_q : cruise_level_q;
    wire [RW-1:0] left_held = left_base - gain_wide;
    // a step: - gain + the level, kept ready in two registers for the two
    // ways the step can go (ramp_down_level_q, ramp_floor_level_q); one
    // carry-save level and one carry chain each
    wire [RW-1:0] sd_x = ramp_left_q ^ gain_neg ^ ramp_down_level_q;
    wire [RW-2:0] sd_m = (ramp_left_q[RW-2:0] & gain_neg[RW-2:0])
                         | (ramp_left_q[RW-2:0] & ramp_down_level_q[RW-2:0])
                         | (gain_neg[RW-2:0] & ramp_down_level_q[RW-2:0]);
    wire [RW-1:0] left_step_down = sd_x + {sd_m, 1'b1};
    wire [RW-1:0] sf_x = ramp_left_q ^ gain_neg ^ ramp_floor_level_q;
    wire [RW-2:0] sf_m = (ramp_left_q[RW-2:0] & gain_neg[RW-2:0])
                         | (ramp_left_q[RW-2:0] & ramp_floor_level_q[RW-2:0])
                         | (gain_neg[RW-2:0] & ramp_floor_level_q[RW-2:0]);
    wire [RW-1:0] left_step_floor = sf_x + {sf_m, 1'b1};
    wire [RW-1:0] left_sum = !ramp_step ? left_held
                             : (ramp_below_q ? left_step_floor : left_step_down);
    // saturating at -2^(DIV+40) (profile.ramp_left_floor): below it the top
    // two bits are 10
    wire          left_under = left_sum[RW-1] && !left_sum[RW-2];
    wire [RW-1:0] ramp_left_n = left_under ? {2'b11, {(RW-2){1'b0}}} : left_sum;
    // dry is set when the dry staircase steps down (not when a next profile
    // arrives before its first step)
    wire          dry_now = cur_valid_q && ramp_on_n && ramp_dry_n && ramp_step;

    // ------------------------------------------------------------------
    // Target of the next clock: the least of the cruise speed, the override
    // on it (below 128 only: ov_q[7] is ov_q = 128) and the running
    // staircase; 0 under hold or stop or without a segment
    // ------------------------------------------------------------------
    wire          ov_under_cruise = !ov_q[7] && (ov_target_q < cruise);
    wire          ramp_under_ov = (ramp_v_q < ov_target_q);
    wire          ramp_under_cruise = (ramp_v_q < cruise);
    wire [37:0]   target_base = ov_under_cruise ? ov_target_q : cruise;
    wire          ramp_limits = ramp_on_q && (ov_under_cruise ? ramp_under_ov
                                                              : ramp_under_cruise);
    wire [37:0]   target_n = (!cur_valid_q || hold || stop) ? 38'd0
                             : (ramp_limits ? ramp_v_q : target_base);

    // The override's product (v_cruise << 6) x ov_q >> 7 = v_cruise x ov_q
    // >> 1 (ov_q <= 128), bit by bit from the top, one add a clock (Horner):
    // ov_acc = 2 ov_acc + v_cruise where the override's bit is set, 8 steps.
    // An edge that changes ov_q, or takes a segment while ov_q < 128 (at 128
    // the target does not read the product), restarts it; the eighth step
    // writes ov_target (profile.OVERRIDE_STEPS) and leaves ov_acc.  After
    // k < 8 steps ov_acc is v_cruise x (ov_q's top k bits) <= v_cruise x 2^6
    // < 2^38 (ov_q <= 128); the last sum, < 2^39, goes to ov_target halved.
    wire [7:0]    ov_n = (feed_override > OVERRIDE_ONE) ? OVERRIDE_ONE : feed_override;
    wire          ov_restart = (ov_n != ov_q) || (take_now && !ov_q[7]);
    wire [2:0]    ov_bit_index = ov_count_q[2:0] - 3'd1;
    wire [38:0]   ov_addend = ov_q[ov_bit_index] ? {7'd0, v_cruise_q} : 39'd0;
    wire [38:0]   ov_acc_n = {ov_acc_q, 1'b0} + ov_addend;

    // ------------------------------------------------------------------
    // Speed: one step of accel towards the registered target, same-direction
    // steps a tick apart
    // ------------------------------------------------------------------
    wire          tick_done = tick_done_q;
    wire          may_step_up = !last_up_q || tick_done;
    wire          may_step_down = !last_down_q || tick_done;
    wire          step_up = (target_q > v_q) && may_step_up;
    wire          step_down = (target_q < v_q) && may_step_down;
    wire [37:0]   v_plus = v_q + {4'd0, accel_q};
    wire [37:0]   v_minus = v_q - {4'd0, accel_q};
    // v + accel > target: v + accel + ~target >= 0 (40 bits signed; the
    // same as v + accel - target - 1 >= 0), one carry-save level, one chain
    wire [39:0]   up_a = {2'd0, v_q};
    wire [39:0]   up_b = {6'd0, accel_q};
    wire [39:0]   up_c = ~{2'd0, target_q};
    wire [39:0]   up_x = up_a ^ up_b ^ up_c;
    wire [38:0] up_m = (up_a[38:0] & up_b[38:0]) | (up_a[38:0] & up_c[38:0])
                       | (up_b[38:0] & up_c[38:0]);
    wire [VW+1:0] up_diff = up_x + {up_m, 1'b0};
    wire          up_clamp = !up_diff[VW+1];
    // v - accel < target: target + accel + ~v >= 0
    wire [39:0]   dn_a = {2'd0, target_q};
    wire [39:0]   dn_b = {6'd0, accel_q};
    wire [39:0]   dn_c = ~{2'd0, v_q};
    wire [39:0]   dn_x = dn_a ^ dn_b ^ dn_c;
    wire [38:0] dn_m = (dn_a[38:0] & dn_b[38:0]) | (dn_a[38:0] & dn_c[38:0])
                       | (dn_b[38:0] & dn_c[38:0]);
    wire [VW+1:0] dn_diff = dn_x + {dn_m, 1'b0};
    wire          down_clamp = !dn_diff[VW+1];
    wire [37:0]   v_up = up_clamp ? target_q : v_plus;
    wire [37:0]   v_down = down_clamp ? target_q : v_minus;
    wire [37:0]   v_n = step_up ? v_up : (step_down ? v_down : v_q);

    wire          cur_valid_n = pop_now ? (!head_last || next_valid) : (segment_runs || take_idle);
    wire          same_segment = pop_now ? !head_last : segment_runs;
    wire [37:0]   v_next = cur_valid_n ? v_n : 38'd0;
    // the credit's gain is 0 after this edge without a segment or at the cap,
    // and whatever the segment at or above 2^41 (profile.CREDIT_CEILING, above
    // every cap: a take would otherwise gain unchecked)
    wire          gain_zero = (pop_now ? (head_last ? !next_valid : at_cap)
                                       : (segment_runs ? at_cap : !take_idle))
                              || credit_q[41];
    // v_next == 0 without the pop in front of a 38-bit compare: whether v_n is 0
    // comes from registers, the pop ends with one gate; and without the speed
    // step's compares and clamps: with the target at 0 the speed can only fall,
    // by accel or (clamped) to 0, so it reaches 0 exactly when it may step down
    // and v <= accel; with the target above 0 a step down stops at the target
    // or above it, and a step up from 0 is to min(accel, target), so v_n is 0
    // exactly when v is 0 and does not step up by a non-zero accel
    wire          target_zero = (target_q == 38'd0);
    wire          accel_zero = (accel_q == 34'd0);
    wire          v_le_accel = (v_q <= {4'd0, accel_q});
    wire          v_n_zero = target_zero ? (v_zero_q || (may_step_down && v_le_accel))
                                         : (v_zero_q && !(may_step_up && !accel_zero));

    always @(posedge clk) begin
        if (rst || abort_now) begin
            cur_valid_q <= 1'b0;
            v_cruise_q  <= 32'd0;
            accel_q     <= 34'd0;
            v_q         <= 38'd0;
            v_zero_q    <= 1'b1;
            target_q    <= 38'd0;
            credit_q    <= 42'd0;
            covers_axis_q <= 1'b0;
            covers_diagonal_q <= 1'b0;
            over_line_q <= {HW{1'b0}};
            gain_q      <= 38'd0;
            s_q         <= {DW{1'b0}};
            since_q     <= {DIV{1'b1}};
            tick_done_q <= 1'b1;
            last_up_q   <= 1'b0;
            last_down_q <= 1'b0;
            ov_acc_q    <= 38'd0;
            ov_count_q  <= 4'd0;
            ov_target_q <= 38'd0;
            past_exit_q <= 1'b0;
            past_stop_q <= 1'b0;
            ramp_on_q   <= 1'b0;
            ramp_dry_q  <= 1'b0;
            ramp_v_q    <= 38'd0;
            ramp_changed_q <= 1'b0;
        end else begin
            // speed and its cadence; no segment after this edge: the speed is 0
            v_q <= v_next;
            v_zero_q <= !cur_valid_n || v_n_zero;
            gain_q <= gain_zero ? 38'd0 : v_n;
            target_q <= target_n;
            if (step_up || step_down) begin
                last_up_q   <= step_up;
                last_down_q <= step_down;
                since_q     <= {DIV{1'b0}};
                tick_done_q <= 1'b0;
            end else if (!tick_done) begin
                since_q <= since_q + SINCE_ONE;
                tick_done_q <= (since_q == SINCE_LAST);
            end
            // the override's product
            // the override's product, one bit a clock
            if (ov_restart) begin
                ov_count_q <= 4'd8;
                ov_acc_q   <= 38'd0;
            end else if (ov_count_q != 4'd0) begin
                ov_count_q <= ov_count_q - 4'd1;
                if (ov_count_q == 4'd1) begin
                    ov_target_q <= ov_acc_n[38:1];
                end else begin
                    ov_acc_q <= ov_acc_n[37:0];
                end
            end
            // credit and distance
            credit_q        <= pop_now ? credit_popped : credit_rest;
            covers_axis_q     <= pop_now ? axis_popped : axis_rest;
            covers_diagonal_q <= pop_now ? diagonal_popped : diagonal_rest;
            over_line_q     <= pop_now ? (head_last && next_valid ? ol_take : ol_popped)
                                       : ol_rest;
            s_q             <= pop_now ? (head_last ? {DW{1'b0}} : s_plus) : s_rest;
            // compares of this clock's registers, for the next clock
            past_exit_q <= same_segment && earned_past_exit;
            past_stop_q <= same_segment && earned_past_stop;
            // the exit staircase; it ends with its segment
            if (same_segment && ramp_on_n) begin
                ramp_on_q   <= 1'b1;
                ramp_dry_q  <= ramp_dry_n;
            end else begin
                ramp_on_q   <= 1'b0;
                ramp_dry_q  <= 1'b0;
            end
            ramp_v_q <= cur_valid_q ? ramp_v_n : 38'd0;
            ramp_changed_q <= ramp_start || ramp_step || dry_return;
            // the segment
            cur_valid_q <= cur_valid_n;
            if (take_now) begin
                accel_q    <= next_accel;
                v_cruise_q <= next_v_cruise;
            end
        end
    end

    // the staircase's remainder: used only while the staircase runs, and a
    // start loads it afresh, so it is computed on every edge without a reset
    // or a clear (the model's 0 while the staircase is off is not held)
    always @(posedge clk) begin
        ramp_left_q        <= ramp_left_n;
        ramp_down_level_q  <= ramp_down_level_n;
        ramp_floor_level_q <= ramp_floor_level_n;
        ramp_below_q       <= ramp_below_n;
    end

    // the current profile's fields: loaded on take (also under rst or
    // abort_now, which end the segment), meaningless without a segment
    always @(posedge clk) begin
        if (take_now) begin
            line_cost_q       <= next_line_cost;
            d_exit_q          <= next_d_exit;
            d_stop_q          <= next_d_stop;
            v_exit_q          <= next_v_exit;
            cap_q             <= (next_line_cost != 18'd0) ? next_line_cost : COST_DIAGONAL;
        end
    end
    // what the staircase derives from them, registered on every edge from
    // the current segment's registers: right from a segment's second clock,
    // the first the staircase can start on (past_exit_q and past_stop_q are
    // low on a segment's first clock), so that a take loads only the fields
    wire [37:0]   exit_speed_n = (v_exit_q != 32'd0) ? {v_exit_q, 6'd0} : {4'd0, accel_q};
    wire [RW-1:0] accel_n_wide = {{(RW-34){1'b0}}, accel_q};
    wire [RW-1:0] exit_n_wide = {{(RW-38){1'b0}}, exit_speed_n};
    wire [RW-1:0] cruise_n_wide = {{(RW-38){1'b0}}, cruise};
    always @(posedge clk) begin
        exit_nonzero_q    <= (v_exit_q != 32'd0);
        exit_speed_q      <= exit_speed_n;
        exit_plus_accel_q <= {1'b0, exit_speed_n} + {5'd0, accel_q};
        cruise_level_q    <= (cruise_n_wide << DIV) - cruise_n_wide;
        accel_level_q     <= (accel_n_wide << DIV) - (accel_n_wide << 2);
        exit_level_q      <= (exit_n_wide << DIV) - (exit_n_wide << 2);
    end

    // dry survives abort; the override is registered on every edge
    always @(posedge clk) begin
        if (rst) begin
            dry_q <= 1'b0;
            ov_q  <= OVERRIDE_ONE;
        end else begin
            if (dry_now && !abort_now) begin
                dry_q <= 1'b1;
            end
            ov_q <= ov_n;
        end
    end

    assign speed = v_q;
    assign dry   = dry_q;
    assign busy  = cur_valid_q || !v_zero;

`ifdef FORMAL
    // ========================================================================
    // Formal properties (SymbiYosys: formal/halfpoint_profile.sby, run by
    // python -m halfpoint.flows.formal).  Verilator, Icarus and the cocotb
    // builds do not define FORMAL, so they see the module above unchanged.
    // ========================================================================
    // Every input is free on every clock (rst high on the first), except that
    // a next profile obeys the rules the core's validator enforces before it
    // reaches this stage (HALFPOINT_E_PROFILE_FIELD, assumed): accel != 0,
    // v_exit <= v_cruise, d_stop <= d_exit.  Any head class under any profile
    // (F_HEAD_OF_ITS_KIND, for the bounded check, assumes the core's rule),
    // any line cost.  (This proof first closed only with a line cost of at
    // least one BLU assumed; without it, it found the credit growing without
    // bound across takes, now stopped at 2^41, profile.CREDIT_CEILING.)
    // Asserted (a_* the contract, i_* the invariants that let k-induction
    // close):
    //   pop      only for a present head move whose axes are ready, inside a
    //            segment, never under abort_now, and only when the credit
    //            covers the head's cost (credit >= cost x 2^22);
    //   take     only of a present profile, on the segment's last pop or with
    //            no segment (and no stop); never under abort_now;
    //   speed    across any edge without rst or abort_now the speed changes by
    //            at most accel (the value in force before the edge), except
    //            that it falls to 0 when the segment ends with no next one;
    //            two changes in the same direction are at least 2^DIV clocks
    //            apart (the acceleration limit of the README's profile stage);
    //   hold     from the second clock of a hold (or stop) on, the speed never
    //            rises; while it is above 0 it falls at least once every
    //            2^DIV + 1 clocks (so a hold reaches rest: at most
    //            ceil(v / accel) (2^DIV + 1) clocks); at rest under hold it
    //            stays at rest (from the hold's second clock: on its first the
    //            target is the one registered before it), and at rest under
    //            hold no move pops;
    //   stop     a stop at rest (stopped) ends the segment and clears the
    //            credit on its edge;
    //   abort    pop, take, stopped and holding are 0 during abort_now, and
    //            the edge leaves the speed at 0 and no segment;
    //   kept     v_zero_q is v == 0; tick_done_q is since_q at its top;
    //            covers_axis_q, covers_diagonal_q (always) are the credit's
    //            compares with their costs x 2^22 and over_line_q (with a
    //            segment) the credit's whole part less it; gain_q is 0
    //            or v_q; target_q is 0 after a clock of hold or stop; the
    //            credit below F_CREDIT_B (it never wraps), cap_q its segment's.
    // F_CONTRACT_ONLY leaves out the kept registers' invariants (i_*: what
    // k-induction needs), so that a bounded check from reset reports which
    // rule of the contract (a_*) a broken design breaks.
    reg f_past_valid;
    initial f_past_valid = 1'b0;
    always @(posedge clk)
        f_past_valid <= 1'b1;
    always @(*)
        if (!f_past_valid)
            assume(rst);

    // the next profile's rules (the core's validator), from the clock after
    // the first reset on (during it nothing is read), named f_rule_*: the
    // core's composed proof (formal/halfpoint_core.sby, compose_*) turns them
    // into assertions, obligations of the core
    always @(*)
        if (f_past_valid && next_valid) begin
            f_rule_accel: assume(next_accel != 34'd0);
            f_rule_exit: assume(next_v_exit <= next_v_cruise);
            f_rule_stop: assume(next_d_stop <= next_d_exit);
        end

`ifdef F_HEAD_OF_ITS_KIND
    // the head move is of its segment's kind (the core's E_PROFILE: a line
    // iteration under a line's profile, axis and diagonal moves under an
    // arc's): assumed by the bounded contract check only, which is much
    // faster with it; the induction proofs do not need it
    always @(*)
        if (head_valid && cur_valid_q)
            assume((head_class == 2'd2) == (line_cost_q != 18'd0) && head_class != 2'd3);
`endif
`ifdef F_LINE_COST_BLU
    // line costs of at least one BLU (not a rule of the core: a Z line is
    // cheaper when Z's BLU is finer than X's): for the bounded check only,
    // whose step 9 ran past 10 minutes without it
    always @(*)
        if (next_valid)
            assume(next_line_cost == 18'd0 || next_line_cost >= COST_AXIS);
`endif

    localparam integer F_GW = DIV + 2;                      // clock counters
    localparam [41:0] F_CREDIT_B = (42'd1 << 41) + (42'd1 << 39);
    localparam [F_GW-1:0] F_TICK = 1 << DIV;                // 2^DIV
    localparam [F_GW-1:0] F_GAP_MAX = F_TICK + 1;           // saturation

    // the edge before was an ordinary one (no rst, no abort_now)
    reg  f_ordinary;
    initial f_ordinary = 1'b0;
    always @(posedge clk)
        f_ordinary <= !rst && !abort_now;

    // ------------------------------------------------------------------
    // The kept registers against what they stand for
    // ------------------------------------------------------------------
`ifndef F_CONTRACT_ONLY
    always @(*)
        if (f_past_valid) begin
            i_v_zero: assert(v_zero_q == (v_q == 38'd0));
            i_tick: assert(tick_done_q == (since_q == {DIV{1'b1}}));
            i_covers_axis: assert(covers_axis_q == (credit_q >= {2'd0, COST_AXIS, 22'd0}));
            i_covers_diagonal: assert(covers_diagonal_q
                                      == (credit_q >= {2'd0, COST_DIAGONAL, 22'd0}));
            if (cur_valid_q)
                i_over_line: assert(over_line_q
                                    == {1'b0, credit_q[41:22]} - {{(HW-18){1'b0}}, line_cost_q});
            i_gain: assert(gain_q == 38'd0 || gain_q == v_q);
            // the credit never wraps: below 2^41 + 2^39, and below 2^41 + 2^38
            // when it gains on the next edge (a gain is < 2^38 and follows a
            // clock with the credit below 2^41)
            i_credit: assert(credit_q < F_CREDIT_B);
            if (gain_q != 38'd0)
                i_credit_gaining: assert(credit_q < F_CREDIT_B - (42'd1 << 38));
            i_cap: assert(!cur_valid_q || cap_q == ((line_cost_q != 18'd0) ? line_cost_q
                                                                          : COST_DIAGONAL));
            if (!cur_valid_q)
                i_no_segment_no_speed: assert(gain_q == 38'd0);
        end
    always @(posedge clk)
        if (f_past_valid && $past(f_past_valid) && ($past(hold) || $past(stop)
                                                     || !$past(cur_valid_q)))
            i_target_held: assert(target_q == 38'd0);

`endif

    // ------------------------------------------------------------------
    // Pop and take
    // ------------------------------------------------------------------
    always @(*)
        if (f_past_valid) begin
            if (pop) begin
                a_pop_present: assert(head_valid && ready && cur_valid_q);
                a_pop_paid: assert(credit_q >= {2'd0, cost, 22'd0});
            end
            if (take) begin
                a_take_present: assert(next_valid);
                a_take_when: assert((pop && head_last) || (!cur_valid_q && !stop));
            end
            if (abort_now)
                a_abort_quiet: assert(!pop && !take && !stopped && !holding);
        end

    // ------------------------------------------------------------------
    // Speed: at most accel per edge, same-direction changes 2^DIV apart
    // ------------------------------------------------------------------
    reg  [F_GW-1:0] f_gap_q;        // edges since the speed last changed, saturating
    reg             f_last_up_q;    // that change was a rise
    reg             f_last_down_q;  // that change was a fall
    reg  [37:0]     f_v_before_q;   // v_q a clock ago ($past(v_q), also in assigns)
    always @(posedge clk)
        f_v_before_q <= v_q;
    wire            f_rise = f_ordinary && (v_q > f_v_before_q);
    wire            f_fall = f_ordinary && (v_q < f_v_before_q);
    always @(posedge clk)
        if (rst || abort_now) begin
            f_gap_q       <= F_GAP_MAX;
            f_last_up_q   <= 1'b0;
            f_last_down_q <= 1'b0;
        end else if (v_q != v_next) begin
            f_gap_q       <= {F_GW{1'b0}};
            f_last_up_q   <= (v_next > v_q);
            f_last_down_q <= (v_next < v_q);
        end else if (f_gap_q != F_GAP_MAX) begin
            f_gap_q <= f_gap_q + 1'b1;
        end
    always @(posedge clk)
        if (f_ordinary) begin
            if ($past(cur_valid_n)) begin
                a_rise_by_accel: assert({1'b0, v_q} <= {1'b0, f_v_before_q}
                                                       + {5'd0, $past(accel_q)});
                a_fall_by_accel: assert({1'b0, v_q} + {5'd0, $past(accel_q)}
                                        >= {1'b0, f_v_before_q});
            end else begin
                a_no_segment_rest: assert(v_q == 38'd0 && !cur_valid_q);
            end
            // f_gap_q before the edge counts the edges after the last change
            // but this one: a change on this edge is f_gap + 1 edges after it
            if (f_rise && $past(f_last_up_q))
                a_rise_cadence: assert($past(f_gap_q) + 1'b1 >= F_TICK);
            if (f_fall && $past(f_last_down_q) && $past(cur_valid_n))
                a_fall_cadence: assert($past(f_gap_q) + 1'b1 >= F_TICK);
        end
`ifndef F_CONTRACT_ONLY
    // the step generator's own cadence registers against the monitor: after
    // a rise the last step was up, no longer ago than the rise; after a fall
    // likewise down, unless the fall was the drop to 0 at a segment's end
    // (not a step), after which only a rise can follow
    always @(*)
        if (f_past_valid) begin
            if (cur_valid_q)
                i_accel: assert(accel_q != 34'd0);
            if (f_last_up_q)
                i_gap_up: assert(last_up_q && !last_down_q && f_gap_q >= {2'd0, since_q});
            if (f_last_down_q && v_q != 38'd0)
                i_gap_down: assert(last_down_q && !last_up_q
                                   && f_gap_q >= {2'd0, since_q});
            i_gap_one_way: assert(!(f_last_up_q && f_last_down_q));
            i_gap_range: assert(f_gap_q <= F_GAP_MAX && f_wait_q <= F_GAP_MAX);
            if (f_last_up_q)
                i_risen: assert(v_q != 38'd0);
            // two or more clocks of hold without a fall: the target is 0, so
            // only the cadence of the last fall holds the next one back
            if (f_wait_q >= 2)
                i_hold_wait: assert(target_q == 38'd0 && v_q != 38'd0 && last_down_q
                                    && f_wait_q <= {2'd0, since_q} + 1'b1);
        end
`endif

    // ------------------------------------------------------------------
    // Hold and stop: no rise from their second clock, a fall every 2^DIV + 1
    // clocks while moving, at rest stays at rest
    // ------------------------------------------------------------------
    reg  [F_GW-1:0] f_wait_q;       // clocks of hold without a fall while moving
    always @(posedge clk)
        if (rst || abort_now || !hold || v_next < v_q || v_next == 38'd0)
            f_wait_q <= {F_GW{1'b0}};
        else if (f_wait_q != F_GAP_MAX)
            f_wait_q <= f_wait_q + 1'b1;
    always @(posedge clk)
        if (f_ordinary && $past(f_past_valid) && $past(!rst && !abort_now, 2)) begin
            if (($past(hold) && $past(hold, 2)) || ($past(stop) && $past(stop, 2)))
                a_held_no_rise: assert(v_q <= f_v_before_q);
            if ($past(holding) && $past(hold, 2))
                a_holding_stays: assert(v_q == 38'd0);
        end
    always @(*)
        if (f_past_valid && hold) begin
            a_hold_falls: assert(f_wait_q <= F_TICK);
            // at rest under hold no move pops (not even one the credit covers)
            if (v_q == 38'd0)
                a_hold_rest_no_pop: assert(!pop);
        end

    // ------------------------------------------------------------------
    // Stop at rest and abort
    // ------------------------------------------------------------------
    always @(posedge clk)
        if (f_past_valid && $past(f_past_valid) && !$past(rst)) begin
            if ($past(stopped))
                a_stop_drops: assert(!cur_valid_q && credit_q == 42'd0 && v_q == 38'd0);
            if ($past(abort_now))
                a_abort_rest: assert(!cur_valid_q && v_q == 38'd0 && credit_q == 42'd0);
        end

    // ------------------------------------------------------------------
    // Reachability (cover): a segment accelerates to a second step, a hold
    // brings a moving segment to rest, holding with a move pending, a stop
    // drops a segment, a take on the last pop
    // ------------------------------------------------------------------
    always @(posedge clk)
        if (f_ordinary) begin
            c_second_rise: cover(f_rise && $past(f_last_up_q));
            c_holding: cover(holding && head_valid);
            c_hold_to_rest: cover(hold && $past(hold) && cur_valid_q && v_q == 38'd0
                                  && f_v_before_q != 38'd0);
            c_stopped: cover($past(stopped) && $past(v_q) == 38'd0 && $past(cur_valid_q));
            c_take_last: cover(take && pop);
        end
`endif

endmodule

`default_nettype wire
