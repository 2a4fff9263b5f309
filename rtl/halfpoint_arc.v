// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// ============================================================================
// halfpoint_arc: half-point minimum-deviation circular interpolator (seed 000)
// ============================================================================
// Interpolates one circular arc per command on the integer lattice (1 BLU per
// axis step), one lattice move per clock while `en` is high, through every
// quadrant crossing and from one command to the next without an idle clock.
//
// Command (valid/ready, taken when s_valid & s_ready):
//   s_cw            1 = clockwise (G2), 0 = counter-clockwise (G3)
//   s_xs, s_ys      start point relative to the centre (signed, W bits)
//   s_xe, s_ye      end point relative to the centre (signed, W bits)
// The radius is defined by the start point (F = 0 there).  A start = end
// command is a full circle.
//
// Each command goes through a validator (W+5 clocks, shift-and-add squaring,
// no multiplier) and waits in a pending slot; while start_en is high it
// enters the run stage at the clock edge of the previous arc's last move, or
// at once when the run stage is idle.  The sequencing outputs (running,
// loading, ending, nx_*) are combinational views of the run stage for a
// motion core that paces `en` and orders segments across units.  The
// validator rejects (reject pulse, err_code, no move):
//   1 radius zero, 2 circle does not fit W bits (R^2 > (M-1)(M-2), M=2^(W-1)),
//   3 end point off the circle: |xe^2+ye^2-R^2| > 2*max(|xs|,|ys|).
//
// Run stage, per enabled clock, for the current point (u, v in the frame of
// its quadrant, see README):  D1 >= 0 -> B; else D2 >= 0 -> A; else C.
// D1, D2 and F are registers; the increments each move adds to them are
// registers too, prepared one clock ahead, so the loop is
//   sign(D1), sign(D2), u==1  ->  select  ->  one add.
// End detection compares (u, v) with the end point's frame in its quadrant's
// progress order (see README, "Termination contract").
//
// Register names: the increments P1..P5, Q1, Q2, Q4, G1..G3 of the README's
// pipeline table are named after what they add to and after which move:
// d1_add_b (P1), d1_add_c (P2), d_add_a (P3, to D1 and D2), d1_add_b_cross
// (P4), d_add_a_cross (P5), d2_add_b (Q1), d2_add_c (Q2), d2_add_b_cross
// (Q4), f_add_b (G1), f_add_c (G2), f_add_a (G3).  Registers end in _q, the
// value they take at the next edge in _n; pend_* is the pending slot, quad
// a quadrant (0..3 = I..IV), ue/ve the end point in its quadrant's frame,
// and a flag such as v_plus1_eq_ue_q holds "v + 1 == ue" for the current v.
//
// Outputs are registered.  In the clock after a move edge: move=1, step_x/y
// and dir_x/y (1 = positive) for that move, x/y/f = the point reached and its
// deviation F = x^2+y^2-R^2, done=1 if it was the arc's last move.  x/y/f
// also show the start point (F=0) when an arc is loaded into an idle run
// stage.  busy = an arc is running, pending or being validated.
//
// Parameters: see the comment above each (an illegal value stops
// elaboration).
//
// abort_now: at the next edge no move is made and the running, pending and
// validating arcs are dropped (no reject is reported for them); outputs x, y,
// f keep the last point; s_ready is low while abort_now is high.
//
// Reset: synchronous, active high, clears control state and outputs.
// ============================================================================
module halfpoint_arc #(
    // coordinate width in bits, 8..32 (signed coordinates); the datapath
    // (D1, D2, F and their increments) is W+2 bits wide
    parameter integer W = 32
) (
    input  wire         clk,
    input  wire         rst,
    // move enable: one lattice move per clock while high
    input  wire         en,

    /*
     * Command stream (valid/ready)
     */
    input  wire         s_valid,
    output wire         s_ready,
    // 1 = clockwise (G2), 0 = counter-clockwise (G3)
    input  wire         s_cw,
    // start and end point relative to the centre (signed)
    input  wire [W-1:0] s_xs,
    input  wire [W-1:0] s_ys,
    input  wire [W-1:0] s_xe,
    input  wire [W-1:0] s_ye,

    /*
     * Status and per-clock outputs (registered)
     */
    output wire         busy,
    output reg          move,
    output reg          step_x,
    output reg          step_y,
    output reg          dir_x,
    output reg          dir_y,
    output wire [W-1:0] x,
    output wire [W-1:0] y,
    output wire [W+1:0] f,
    output reg          done,
    output reg          reject,
    output reg  [1:0]   err_code,

    /*
     * Sequencing (for the motion core; tie start_en high when used alone)
     */
    // drop the running, pending and validated arcs now
    input  wire         abort_now,
    // the pending arc may enter the run stage
    input  wire         start_en,
    // an arc is in the run stage
    output wire         running,
    // a validated arc waits in the pending slot (registered)
    output wire         pending,
    // the pending arc enters the run stage at this edge
    output wire         loading,
    // the running arc makes its last move at this edge
    output wire         ending,
    // the next move (if en): steps X (bit 0) and Y (bit 1), their directions
    // (1 = positive), and whether it is a diagonal move (A)
    output wire [1:0]   nx_step,
    output wire [1:0]   nx_dir,
    output wire         nx_diag
);

    // ------------------------------------------------------------------
    // Parameter check: an illegal width stops elaboration.
    // ------------------------------------------------------------------
    generate
        if (W < 8 || W > 32) begin : g_bad_width
            halfpoint_arc_illegal_parameter_W_must_be_8_to_32 u_bad ();
        end
    endgenerate

    localparam integer DATA_W = W + 2;      // datapath width
    // validator accumulator: R^2 <= 2^(2W-1) and |F_e| < 2^(2W), as are the
    // partial sums of the shift-and-add passes (each a sum of at most four
    // terms c * (c >> k), |c| <= 2^(W-1)), so 2W+2 bits signed hold them
    localparam integer ACC_W = 2 * W + 2;
    // small signed constants at datapath width
    localparam [DATA_W-1:0] ZERO_D        = {DATA_W{1'b0}};
    localparam [DATA_W-1:0] ONE_D         = {{(DATA_W-4){1'b0}}, 4'd1};
    localparam [DATA_W-1:0] TWO_D         = {{(DATA_W-4){1'b0}}, 4'd2};
    localparam [DATA_W-1:0] THREE_D       = {{(DATA_W-4){1'b0}}, 4'd3};
    localparam [DATA_W-1:0] FOUR_D        = {{(DATA_W-4){1'b0}}, 4'd4};
    localparam [DATA_W-1:0] FIVE_D        = {{(DATA_W-4){1'b0}}, 4'd5};
    localparam [DATA_W-1:0] SEVEN_D       = {{(DATA_W-4){1'b0}}, 4'd7};
    localparam [DATA_W-1:0] MINUS_THREE_D = ~TWO_D;
    localparam [W-1:0]      ONE_W         = {{(W-1){1'b0}}, 1'b1};
    localparam [W-1:0]      TWO_W         = {{(W-2){1'b0}}, 2'd2};
    localparam integer      MSB_INDEX     = W - 1;
    localparam [4:0]        BIT_MSB       = MSB_INDEX[4:0];
    // validator states
    localparam [2:0] STATE_IDLE   = 3'd0;
    localparam [2:0] STATE_SQUARE = 3'd1;
    localparam [2:0] STATE_CHECK  = 3'd2;
    localparam [2:0] STATE_DECIDE = 3'd3;
    localparam [2:0] STATE_HOLD   = 3'd4;
    // Largest accepted R^2: (M-1)(M-2) = M^2 - 3M + 2, M = 2^(W-1).
    localparam [ACC_W-1:0] ONE_ACC = {{(ACC_W-1){1'b0}}, 1'b1};
    localparam [ACC_W-1:0] THREE_ACC = {{(ACC_W-2){1'b0}}, 2'b11};
    localparam [ACC_W-1:0] RADIUS_SQUARE_MAX =
        (ONE_ACC << (2*W-2)) - (THREE_ACC << (W-1)) + (ONE_ACC << 1);

    // Quadrant (0..3 = I..IV) of a non-origin point for a direction; a point
    // on an axis belongs to the quadrant the motion enters.
    function [1:0] quadrant_of;
        input          cw;
        input [W-1:0]  px;
        input [W-1:0]  py;
        reg xn, yn, xz, yz;
        begin
            xn = px[W-1]; yn = py[W-1];
            xz = (px == {W{1'b0}}); yz = (py == {W{1'b0}});
            if (!cw) begin
                if (!xn && !xz && !yn)             quadrant_of = 2'd0;  // x>0, y>=0
                else if ((xn || xz) && !yn && !yz) quadrant_of = 2'd1;  // x<=0, y>0
                else if (xn && (yn || yz))         quadrant_of = 2'd2;  // x<0, y<=0
                else                               quadrant_of = 2'd3;  // x>=0, y<0
            end else begin
                if (!xn && !yn && !yz)             quadrant_of = 2'd0;  // x>=0, y>0
                else if (xn && !yn)                quadrant_of = 2'd1;  // x<0, y>=0
                else if ((xn || xz) && yn)         quadrant_of = 2'd2;  // x<=0, y<0
                else                               quadrant_of = 2'd3;  // x>0, y<=0
            end
        end
    endfunction

    function [W-1:0] magnitude;
        input [W-1:0] a;
        begin
            magnitude = a[W-1] ? (~a + ONE_W) : a;
        end
    endfunction

    // bit `index` of a (a W:1 multiplexer)
    function bit_at;
        input [W-1:0] a;
        input [4:0]   index;
        integer       k;
        begin
            bit_at = 1'b0;
            for (k = 0; k < W; k = k + 1)
                if ({27'd0, index} == k) bit_at = a[k];
        end
    endfunction

    // ------------------------------------------------------------------
    // Validator: one adder, shift-and-add over 6W + 4 clocks.
    //   SQUARE, first pass (2 clocks per bit, MSB first):  acc = R^2 = xs^2 + ys^2
    //   SQUARE, second pass (4 clocks per bit): acc = F_e = xe^2 + ye^2 - xs^2 - ys^2
    //     (Horner: the first operand of each bit doubles acc; a coordinate's own
    //     bits select it, its sign bit with weight -2^(W-1)); the first clock of
    //     the second pass registers R^2 > (M-1)(M-2) from the first pass's acc
    //   CHECK (4 clocks): F_e -/+ 2xs and F_e -/+ 2ys, their signs -> code 3
    //   DECIDE: reject (codes 1..3) or HOLD
    // ------------------------------------------------------------------
    reg  [2:0]       validator_state_q;
    // validator_state_q == STATE_HOLD, as a flip-flop of its own (it gates
    // the frame set-up and the load)
    reg              hold_q;
    reg              second_pass_q;     // 0: R^2 pass, 1: F_e pass
    reg  [4:0]       bit_q;             // bit of the pass, W-1 down to 0
    reg  [1:0]       operand_q;         // operand of the bit, or step of CHECK
    reg              cmd_cw_q;
    reg  [W-1:0]     cmd_xs_q, cmd_ys_q, cmd_xe_q, cmd_ye_q;   // raw coordinates
    reg  [ACC_W-1:0] accumulator_q;
    // the checks: R^2 too big; CHECK's first sign of each pair; |F_e| > 2|xs|, > 2|ys|
    reg              radius_too_big_q, first_sign_q, end_off_x_q, end_off_y_q;

    assign s_ready = (validator_state_q == STATE_IDLE) && !abort_now;
    wire   accept  = s_valid && s_ready;

    wire checking = (validator_state_q == STATE_CHECK);
    localparam integer TERM_W = W + 1;  // an operand: 0, +/-c or +/-2c, |c| <= 2^(W-1)

    // The counters of the next clock and the operand (term) it adds, fetched
    // a clock ahead into term_q / carry_q, so that the adder sees registers.
    wire       last_operand = second_pass_q ? (operand_q == 2'd3) : (operand_q == 2'd1);
    wire       second_next  = second_pass_q || (last_operand && bit_q == 5'd0);
    wire [4:0] bit_next     = !last_operand ? bit_q
                            : (bit_q == 5'd0) ? BIT_MSB : (bit_q - 5'd1);
    wire [1:0] operand_next = last_operand ? 2'd0 : (operand_q + 2'd1);
    // the next clock is a CHECK clock
    wire       checking_next = checking ? (operand_q != 2'd3)
                             : (second_pass_q && last_operand && bit_q == 5'd0);
    // operand coordinate: 0 xe, 1 ye, 2 xs, 3 ys
    wire [1:0] index_next   = checking_next ? {1'b1, operand_next[1]}
                            : second_next ? operand_next : {1'b1, operand_next[0]};
    reg  [W-1:0] coordinate_next;
    always @(*) begin
        case (index_next)
            2'd0:    coordinate_next = cmd_xe_q;
            2'd1:    coordinate_next = cmd_ye_q;
            2'd2:    coordinate_next = cmd_xs_q;
            default: coordinate_next = cmd_ys_q;
        endcase
    end
    // SQUARE: the coordinate's bit selects it; negative for the sign bit (two's
    // complement weight) and for xs, ys in the second pass, not for both.
    // CHECK step 0/2: ~2c (and a carry if c < 0); step 1/3: +2c
    wire              bit_value_next = bit_at(coordinate_next, bit_next);
    wire              subtract_next  = (bit_next == BIT_MSB) ^ (second_next && operand_next[1]);
    wire [TERM_W-1:0] single_next    = {coordinate_next[W-1], coordinate_next};
    wire [TERM_W-1:0] twice_next     = {coordinate_next, 1'b0};
    wire [TERM_W-1:0] term_next =
        checking_next ? (operand_next[0] ? twice_next : ~twice_next)
        : !bit_value_next ? {TERM_W{1'b0}} : subtract_next ? ~single_next : single_next;
    wire carry_next = checking_next ? (!operand_next[0] && coordinate_next[W-1])
                                    : (bit_value_next && subtract_next);
    reg  [TERM_W-1:0] term_q;
    reg               carry_q;
    reg               bit_msb_q;        // bit_q == W - 1

    // SQUARE: the first operand of a bit doubles acc (clears it on the first bit)
    wire first_operand = (operand_q == 2'd0);
    wire [ACC_W-1:0] square_base =
        !first_operand ? accumulator_q
        : bit_msb_q ? {ACC_W{1'b0}} : {accumulator_q[ACC_W-2:0], 1'b0};
    wire [ACC_W-1:0] sum = (checking ? accumulator_q : square_base)
                         + {{(ACC_W-TERM_W){term_q[TERM_W-1]}}, term_q}
                         + {{(ACC_W-1){1'b0}}, carry_q};
    wire sum_sign = sum[ACC_W-1];
    wire sum_zero = (sum == {ACC_W{1'b0}});
    // |F_e| > 2|c|: c >= 0: F_e - 2c - 1 >= 0 or F_e + 2c < 0;
    //               c <  0: F_e - 2c < 0 or F_e + 2c > 0
    wire check_negative = operand_q[1] ? cmd_ys_q[W-1] : cmd_xs_q[W-1];
    wire end_off = check_negative ? (first_sign_q || (!sum_sign && !sum_zero))
                                  : (!first_sign_q || sum_sign);

    wire radius_zero  = (cmd_xs_q == {W{1'b0}}) && (cmd_ys_q == {W{1'b0}});
    wire [1:0] decide_error = radius_zero ? 2'd1 : radius_too_big_q ? 2'd2
                            : (end_off_x_q && end_off_y_q) ? 2'd3 : 2'd0;

    // run-stage handshake (defined below)
    wire       load;

    always @(posedge clk) begin
        if (rst || abort_now) begin
            hold_q <= 1'b0;
        end else if (validator_state_q == STATE_DECIDE && decide_error == 2'd0) begin
            hold_q <= 1'b1;
        end else if (load) begin
            hold_q <= 1'b0;
        end
    end

    always @(posedge clk) begin
        if (rst || abort_now) begin
            validator_state_q <= STATE_IDLE;
        end else begin
            case (validator_state_q)
                STATE_IDLE:   if (accept) validator_state_q <= STATE_SQUARE;
                STATE_SQUARE: if (last_operand && bit_q == 5'd0 && second_pass_q)
                                  validator_state_q <= STATE_CHECK;
                STATE_CHECK:  if (operand_q == 2'd3) validator_state_q <= STATE_DECIDE;
                STATE_DECIDE: validator_state_q <= (decide_error != 2'd0) ? STATE_IDLE
                                                                          : STATE_HOLD;
                STATE_HOLD:   if (load) validator_state_q <= STATE_IDLE;
                default:      validator_state_q <= STATE_IDLE;
            endcase
        end
    end

    // validator datapath (no reset needed: qualified by validator_state_q)
    always @(posedge clk) begin
        if (accept) begin
            cmd_cw_q      <= s_cw;
            cmd_xs_q      <= s_xs;
            cmd_ys_q      <= s_ys;
            cmd_xe_q      <= s_xe;
            cmd_ye_q      <= s_ye;
            second_pass_q <= 1'b0;
            bit_q         <= BIT_MSB;
            operand_q     <= 2'd0;
            // the first operand: xs if its sign bit is set, negative
            term_q        <= s_xs[W-1] ? ~{s_xs[W-1], s_xs} : {TERM_W{1'b0}};
            carry_q       <= s_xs[W-1];
            bit_msb_q     <= 1'b1;
        end
        if (validator_state_q == STATE_SQUARE || checking) begin
            term_q        <= term_next;
            carry_q       <= carry_next;
        end
        if (validator_state_q == STATE_SQUARE) begin
            accumulator_q <= sum;
            second_pass_q <= second_next;
            bit_q         <= bit_next;
            operand_q     <= operand_next;
            bit_msb_q     <= (bit_next == BIT_MSB);
            if (second_pass_q && first_operand && bit_msb_q)
                radius_too_big_q <= (accumulator_q > RADIUS_SQUARE_MAX);
        end
        if (checking) begin
            operand_q <= operand_q + 2'd1;
            if (!operand_q[0]) first_sign_q <= sum_sign;
            if (operand_q == 2'd1) end_off_x_q <= end_off;
            if (operand_q == 2'd3) end_off_y_q <= end_off;
        end
    end

    // ------------------------------------------------------------------
    // Frame set-up: a validated arc (HOLD) and an idle run stage.  Three
    // clocks write the run-stage registers, each doing at most one add or
    // compare per register; the third edge also loads the arc (run_q) when
    // start_en is high, else the arc waits, prepared, for start_en.
    //   FRAME: quadrants, u, v; ue and ve into ue_minus2_q / ve_minus2_q
    //   TERMS: increments from u, v; 3v and 2(v - u) into P4 / P3; flags
    //   SUMS:  D1, D2, P3, G3, P4, Q4; ue - 2, ve - 2
    // ------------------------------------------------------------------
    reg  [1:0] prepare_q;               // 0 FRAME, 1 TERMS, 2 SUMS, 3 prepared
    wire       run_idle;                // defined with the run stage
    wire       preparing     = hold_q && run_idle;
    wire       prepare_frame = preparing && (prepare_q == 2'd0);
    wire       prepare_terms = preparing && (prepare_q == 2'd1);
    wire       prepare_sums  = preparing && (prepare_q == 2'd2);
    assign load = preparing && prepare_q[1] && start_en && !abort_now;

    always @(posedge clk) begin
        if (rst || abort_now || load) begin
            prepare_q <= 2'd0;
        end else if (preparing && prepare_q != 2'd3) begin
            prepare_q <= prepare_q + 2'd1;
        end
    end

    wire [1:0]   start_quad   = quadrant_of(cmd_cw_q, cmd_xs_q, cmd_ys_q);
    wire [1:0]   end_quad     = quadrant_of(cmd_cw_q, cmd_xe_q, cmd_ye_q);
    wire         start_u_is_x = (start_quad[0] == cmd_cw_q);
    wire         end_u_is_x   = (end_quad[0] == cmd_cw_q);

    // ------------------------------------------------------------------
    // Run stage
    // ------------------------------------------------------------------
    reg               run_q, cw_q, armed_q, first_octant_q, ve_zero_q;
    reg  [1:0]        quad_q, end_quad_q;
    reg  [W-1:0]      u_q, v_q, ue_plus1_q;
    reg  [W-1:0]      point_x_q, point_y_q;                 // current point
    reg  [DATA_W-1:0] d1_q, d2_q, f_q;
    // increments, see the register names in the header; the other five are
    // one of these plus the adder's carry-in, or come from v_q:
    //   P1 = Q1 + 1, P2 = G2 + 1, G2 = 2v + 1 = {v, 1}, P4 = Q4 + 1, P5 = ~v + 1
    reg  [DATA_W-1:0] d_add_a_q;            // P3 = -2u + 2v + 5
    reg  [DATA_W-1:0] d2_add_b_q;           // Q1 = -2u + 2
    reg  [DATA_W-1:0] d2_add_c_q;           // Q2 = 2v + 3
    reg  [DATA_W-1:0] d2_add_b_cross_q;     // Q4 = -3v
    reg  [DATA_W-1:0] f_add_b_q;            // G1 = -2u + 1
    reg  [DATA_W-1:0] f_add_a_q;            // G3 = -2u + 2v + 2
    // end-point constants beyond ue + 1, ue - 1, ve - 1 (for the look-ahead)
    reg  [W-1:0]      ue_plus2_q, ue_minus2_q, ve_minus2_q;
    reg               ve_one_q, ue_zero_q, ue_one_q;
    // comparison flags of the current (u, v) with the end point, kept one
    // clock ahead (look-ahead): each register equals the comparison its name
    // states for the current u_q, v_q, so that no comparator sits between
    // the decision and the end detection (see "end detection" below)
    reg               u_one_q;                                    // u == 1
    reg               v_gt_ve_q, v_eq_ve_q, v_plus1_eq_ve_q;      // v + 1 == ve: and ve != 0
    reg               u_lt_ue_q, u_eq_ue_q, u_eq_ue_plus1_q;
    reg               v_lt_ue_q, v_eq_ue_q, v_plus1_eq_ue_q;

    // decision: sign bits -> move
    wire move_b   = !d1_q[DATA_W-1];
    wire move_a   = d1_q[DATA_W-1] && !d2_q[DATA_W-1];
    wire move_c   = d1_q[DATA_W-1] && d2_q[DATA_W-1];
    wire u_down   = move_b || move_a;                   // u shrinks
    wire v_up     = move_a || move_c;                   // v grows
    wire crossing = u_one_q && u_down;                  // u reaches 0: next quadrant

    wire advance  = run_q && en && !abort_now;          // a move at this edge

    // 2v + 1 (G2) and ~v (-v - 1) at datapath width, from v_q
    wire [DATA_W-1:0] v_twice_plus1 = {1'b0, v_q, 1'b1};
    wire [DATA_W-1:0] v_inverted    = ~{2'b00, v_q};

    // the loop: select one prepared increment, one add per register, the
    // carry-in making P1, P2, P4, P5 from Q1, G2, Q4, ~v
    wire [DATA_W-1:0] d1_add = crossing ? (move_b ? d2_add_b_cross_q : v_inverted)
                             : (move_b ? d2_add_b_q : move_a ? d_add_a_q : v_twice_plus1);
    wire              d1_carry = crossing || !move_a;
    wire [DATA_W-1:0] d2_add = crossing ? (move_b ? d2_add_b_cross_q : v_inverted)
                             : (move_b ? d2_add_b_q : move_a ? d_add_a_q : d2_add_c_q);
    wire              d2_carry = crossing && move_a;
    wire [DATA_W-1:0] f_add  = move_b ? f_add_b_q : move_a ? f_add_a_q : v_twice_plus1;
    wire [DATA_W-1:0] d1_n   = d1_q + d1_add + {{(DATA_W-1){1'b0}}, d1_carry};
    wire [DATA_W-1:0] d2_n   = d2_q + d2_add + {{(DATA_W-1){1'b0}}, d2_carry};

    // next increments: register + constant, or ~(2v + 1) + constant on a
    // crossing (u' = v or v + 1, v' = 0; ~(2v + 1) = -2v - 2); see README
    // registers whose term is -2u gain 2 on every move that lowers u
    wire [DATA_W-1:0] u_term_add = u_down ? TWO_D : ZERO_D;
    wire [DATA_W-1:0] v_crossed  = ~v_twice_plus1;
    // one adder per register: on a crossing ~(2v + 1) plus a constant,
    // else the register plus a constant
    wire [DATA_W-1:0] d_add_a_n  = (crossing ? v_crossed : d_add_a_q)
        + (crossing ? (move_b ? SEVEN_D : FIVE_D) : (move_a ? FOUR_D : TWO_D));
    wire [DATA_W-1:0] d2_add_b_n = (crossing ? v_crossed : d2_add_b_q)
        + (crossing ? (move_b ? FOUR_D : TWO_D) : u_term_add);
    wire [DATA_W-1:0] d2_add_c_n = crossing ? THREE_D : (d2_add_c_q + (v_up ? TWO_D : ZERO_D));
    wire [DATA_W-1:0] d2_add_b_cross_n =
        crossing ? ZERO_D : (d2_add_b_cross_q + (v_up ? MINUS_THREE_D : ZERO_D));
    wire [DATA_W-1:0] f_add_b_n  = (crossing ? v_crossed : f_add_b_q)
        + (crossing ? (move_b ? THREE_D : ONE_D) : u_term_add);
    wire [DATA_W-1:0] f_add_a_n  = (crossing ? v_crossed : f_add_a_q)
        + (crossing ? (move_b ? FOUR_D : TWO_D) : (move_a ? FOUR_D : TWO_D));

    // u' = v or v + 1 on a crossing, else u - 1 or u (one adder)
    wire [W-1:0] u_n    = (crossing ? v_q : u_q)
                        + (crossing ? {{(W-1){1'b0}}, move_a} : {W{u_down}});
    wire [W-1:0] v_n    = crossing ? {W{1'b0}} : (v_q + {{(W-1){1'b0}}, v_up});
    wire [1:0]   quad_crossed = cw_q ? quad_q - 2'd1 : quad_q + 2'd1;   // the next quadrant
    wire [1:0]   quad_n = crossing ? quad_crossed : quad_q;

    // physical steps: u steps toward the axis, v away from it
    wire u_is_x      = (quad_q[0] == cw_q);
    wire x_positive  = (quad_q == 2'd0) || (quad_q == 2'd3);  // x >= 0 in this quadrant
    wire y_positive  = !quad_q[1];                            // y >= 0 in this quadrant
    wire x_steps     = u_is_x ? u_down : v_up;
    wire y_steps     = u_is_x ? v_up : u_down;
    wire x_direction = u_is_x ? !x_positive : x_positive;     // 1 = positive
    wire y_direction = u_is_x ? y_positive : !y_positive;
    // point + 1, - 1 (all ones) or + 0: one adder per axis
    wire [W-1:0] point_x_n = point_x_q
                           + {{(W-1){x_steps && !x_direction}}, x_steps};
    wire [W-1:0] point_y_n = point_y_q
                           + {{(W-1){y_steps && !y_direction}}, y_steps};

    // end detection for the point after this move (progress order of E),
    // from the registered comparison flags
    wire v_ge_ve       = v_gt_ve_q || v_eq_ve_q;
    wire v_plus1_ge_ve = v_ge_ve || v_plus1_eq_ve_q;
    wire u_le_ue       = u_lt_ue_q || u_eq_ue_q;
    wire u_le_ue_plus1 = u_le_ue || u_eq_ue_plus1_q;

    // look-ahead: the flags for the point after this move, from the flags of
    // this point, the move, and equality tests of this point with constants
    // (they end at the flag registers, not in the enable path)
    wire v_eq_ve_minus2 = (v_q == ve_minus2_q);
    wire v_eq_ue_minus2 = (v_q == ue_minus2_q);
    wire u_eq_ue_plus2  = (u_q == ue_plus2_q);
    wire v_eq_ue_plus1  = (v_q == ue_plus1_q);
    wire u_eq_2         = (u_q == {{(W-2){1'b0}}, 2'd2});
    wire v_eq_1         = (v_q == ONE_W);
    wire v_eq_0         = (v_q == {W{1'b0}});
    // on a crossing u' = v + (A ? 1 : 0) and v' = 0
    wire v_gt_ve_n       = crossing ? 1'b0 : v_up ? (v_gt_ve_q || v_eq_ve_q) : v_gt_ve_q;
    wire v_eq_ve_n       = crossing ? ve_zero_q : v_up ? v_plus1_eq_ve_q : v_eq_ve_q;
    wire v_plus1_eq_ve_n = crossing ? ve_one_q
                         : v_up ? (!ve_zero_q && v_eq_ve_minus2) : v_plus1_eq_ve_q;
    wire u_lt_ue_n       = crossing ? (move_a ? (v_lt_ue_q && !v_plus1_eq_ue_q) : v_lt_ue_q)
                         : u_down ? (u_lt_ue_q || u_eq_ue_q) : u_lt_ue_q;
    wire u_eq_ue_n       = crossing ? (move_a ? v_plus1_eq_ue_q : v_eq_ue_q)
                         : u_down ? u_eq_ue_plus1_q : u_eq_ue_q;
    wire u_eq_ue_plus1_n = crossing ? (move_a ? v_eq_ue_q : v_eq_ue_plus1)
                         : u_down ? u_eq_ue_plus2 : u_eq_ue_plus1_q;
    wire v_lt_ue_n       = crossing ? !ue_zero_q
                         : v_up ? (v_lt_ue_q && !v_plus1_eq_ue_q) : v_lt_ue_q;
    wire v_eq_ue_n       = crossing ? ue_zero_q : v_up ? v_plus1_eq_ue_q : v_eq_ue_q;
    wire v_plus1_eq_ue_n = crossing ? ue_one_q : v_up ? v_eq_ue_minus2 : v_plus1_eq_ue_q;
    wire u_one_n         = crossing ? (move_a ? v_eq_0 : v_eq_1)
                         : u_down ? u_eq_2 : u_one_q;

    // The stop test for each of the three moves, from registers only; the
    // move's sign bits then select one (a single LUT level before `ending`).
    // past_same_*: the point after the move (same quadrant) is at or past E
    wire past_same_b = first_octant_q ? (v_gt_ve_q || (v_eq_ve_q && u_le_ue_plus1))   // (v, -u)
                                      : (u_le_ue || (u_eq_ue_plus1_q && v_ge_ve));     // (-u, v)
    wire past_same_c = first_octant_q ? (v_ge_ve || (v_plus1_eq_ve_q && u_le_ue))
                                      : (u_lt_ue_q || (u_eq_ue_q && v_plus1_ge_ve));
    wire past_same_a = first_octant_q ? (v_ge_ve || (v_plus1_eq_ve_q && u_le_ue_plus1))
                                      : (u_le_ue || (u_eq_ue_plus1_q && v_plus1_ge_ve));
    // past_entry_*: entering E's quadrant at (u', 0) with u' = v (B) or v + 1 (A)
    wire past_entry_b = first_octant_q ? (ve_zero_q && (v_lt_ue_q || v_eq_ue_q)) : v_lt_ue_q;
    wire past_entry_a = first_octant_q ? (ve_zero_q && v_lt_ue_q)
                                       : (v_lt_ue_q && !v_plus1_eq_ue_q);
    wire in_end_quad    = (quad_q == end_quad_q);
    wire enters_end     = (quad_crossed == end_quad_q);
    // a B or A move from u == 1 crosses into the next quadrant (stop if it
    // leaves E's quadrant or enters it past E); a C move never crosses
    wire stop_b = armed_q && (u_one_q ? (in_end_quad || (enters_end && past_entry_b))
                                      : (in_end_quad && past_same_b));
    wire stop_a = armed_q && (u_one_q ? (in_end_quad || (enters_end && past_entry_a))
                                      : (in_end_quad && past_same_a));
    wire stop_c = armed_q && in_end_quad && past_same_c;
    wire stop   = move_b ? stop_b : move_a ? stop_a : stop_c;
    wire last = advance && stop;

    assign run_idle = !run_q;

    assign running = run_q;
    assign pending = hold_q;
    assign loading = load;
    assign ending  = last;
    assign nx_step = {y_steps, x_steps};
    assign nx_dir  = {y_direction, x_direction};
    assign nx_diag = move_a;
    assign busy    = run_q || (validator_state_q != STATE_IDLE);

    always @(posedge clk) begin
        if (rst || abort_now) begin
            run_q <= 1'b0;
        end else if (load) begin
            run_q <= 1'b1;
        end else if (last) begin
            run_q <= 1'b0;
        end
    end

    // frame set-up terms (TERMS and SUMS read the registers FRAME and TERMS wrote)
    wire [W-1:0]      setup_ue = ue_minus2_q;               // ue, until SUMS
    wire [W-1:0]      setup_ve = ve_minus2_q;               // ve, until SUMS
    wire [W-1:0]      setup_ue_plus1 = setup_ue + ONE_W;
    wire [W-1:0]      setup_v_plus1  = v_q + ONE_W;
    wire [DATA_W-1:0] setup_u = {2'b00, u_q};
    wire [DATA_W-1:0] setup_v = {2'b00, v_q};
    wire setup_first_octant = (setup_ve <= setup_ue);
    wire setup_v_before = (v_q < setup_ve) || (v_q == setup_ve && u_q > setup_ue);
    wire setup_u_before = (u_q > setup_ue) || (u_q == setup_ue && v_q < setup_ve);
    wire setup_before   = setup_first_octant ? setup_v_before : setup_u_before;
    wire setup_ve_zero  = (setup_ve == {W{1'b0}});

    always @(posedge clk) begin
        if (prepare_frame) begin
            cw_q        <= cmd_cw_q;
            quad_q      <= start_quad;
            end_quad_q  <= end_quad;
            u_q         <= magnitude(start_u_is_x ? cmd_xs_q : cmd_ys_q);
            v_q         <= magnitude(start_u_is_x ? cmd_ys_q : cmd_xs_q);
            ue_minus2_q <= magnitude(end_u_is_x ? cmd_xe_q : cmd_ye_q);
            ve_minus2_q <= magnitude(end_u_is_x ? cmd_ye_q : cmd_xe_q);
        end
        if (prepare_terms) begin
            // F = 0 at the start point
            d2_add_b_q       <= TWO_D - (setup_u << 1);                 // Q1
            d2_add_c_q       <= (setup_v << 1) + THREE_D;               // Q2
            f_add_b_q        <= ONE_D - (setup_u << 1);                 // G1
            d2_add_b_cross_q <= setup_v + (setup_v << 1);               // 3v, until SUMS
            d_add_a_q        <= (setup_v - setup_u) << 1;               // 2(v - u), until SUMS
            first_octant_q   <= setup_first_octant;
            armed_q          <= !((quad_q == end_quad_q) && !setup_before);
            ue_plus1_q       <= setup_ue_plus1;
            ue_plus2_q       <= setup_ue + TWO_W;
            ve_zero_q        <= setup_ve_zero;
            ve_one_q         <= (setup_ve == ONE_W);
            ue_zero_q        <= (setup_ue == {W{1'b0}});
            ue_one_q         <= (setup_ue == ONE_W);
            u_one_q          <= (u_q == ONE_W);
            v_gt_ve_q        <= (v_q > setup_ve);
            v_eq_ve_q        <= (v_q == setup_ve);
            v_plus1_eq_ve_q  <= (setup_v_plus1 == setup_ve);
            u_lt_ue_q        <= (u_q < setup_ue);
            u_eq_ue_q        <= (u_q == setup_ue);
            u_eq_ue_plus1_q  <= (u_q == setup_ue_plus1);
            v_lt_ue_q        <= (v_q < setup_ue);
            v_eq_ue_q        <= (v_q == setup_ue);
            v_plus1_eq_ue_q  <= (setup_v_plus1 == setup_ue);
        end
        if (prepare_sums) begin
            d1_q             <= setup_v + f_add_b_q;                    // F - 2u + v + 1
            d2_q             <= v_twice_plus1 - setup_u;                // F - u + 2v + 1
            d_add_a_q        <= d_add_a_q + FIVE_D;                     // P3
            f_add_a_q        <= d_add_a_q + TWO_D;                      // G3
            d2_add_b_cross_q <= ZERO_D - d2_add_b_cross_q;              // Q4
            ue_minus2_q      <= ue_minus2_q - TWO_W;
            ve_minus2_q      <= ve_minus2_q - TWO_W;
        end
        if (advance) begin
            quad_q           <= quad_n;
            u_q              <= u_n;
            v_q              <= v_n;
            armed_q          <= armed_q || crossing;
            u_one_q          <= u_one_n;
            v_gt_ve_q        <= v_gt_ve_n;
            v_eq_ve_q        <= v_eq_ve_n;
            v_plus1_eq_ve_q  <= v_plus1_eq_ve_n;
            u_lt_ue_q        <= u_lt_ue_n;
            u_eq_ue_q        <= u_eq_ue_n;
            u_eq_ue_plus1_q  <= u_eq_ue_plus1_n;
            v_lt_ue_q        <= v_lt_ue_n;
            v_eq_ue_q        <= v_eq_ue_n;
            v_plus1_eq_ue_q  <= v_plus1_eq_ue_n;
            d1_q             <= d1_n;
            d2_q             <= d2_n;
            d_add_a_q        <= d_add_a_n;
            d2_add_b_q       <= d2_add_b_n;
            d2_add_c_q       <= d2_add_c_n;
            d2_add_b_cross_q <= d2_add_b_cross_n;
            f_add_b_q        <= f_add_b_n;
            f_add_a_q        <= f_add_a_n;
        end
    end

    // ------------------------------------------------------------------
    // Registered outputs; x, y and f are the run stage's point and F
    // registers themselves (an arc is loaded only into an idle run stage, so
    // they change only with a move or a load)
    // ------------------------------------------------------------------
    wire rejecting = (validator_state_q == STATE_DECIDE) && (decide_error != 2'd0) && !abort_now;

    assign x = point_x_q;
    assign y = point_y_q;
    assign f = f_q;

    always @(posedge clk) begin
        if (rst) begin
            move      <= 1'b0;
            step_x    <= 1'b0;
            step_y    <= 1'b0;
            dir_x     <= 1'b0;
            dir_y     <= 1'b0;
            point_x_q <= {W{1'b0}};
            point_y_q <= {W{1'b0}};
            f_q       <= {DATA_W{1'b0}};
            done      <= 1'b0;
            reject    <= 1'b0;
            err_code  <= 2'd0;
        end else begin
            move   <= advance;
            step_x <= advance && x_steps;
            step_y <= advance && y_steps;
            if (advance && x_steps) dir_x <= x_direction;
            if (advance && y_steps) dir_y <= y_direction;
            if (advance) begin
                point_x_q <= point_x_n;
                point_y_q <= point_y_n;
                f_q       <= f_q + f_add;
            end else if (load) begin
                point_x_q <= cmd_xs_q;
                point_y_q <= cmd_ys_q;
                f_q       <= {DATA_W{1'b0}};
            end
            done   <= last;
            reject <= rejecting;
            if (rejecting) err_code <= decide_error;
        end
    end

endmodule

`default_nettype wire
