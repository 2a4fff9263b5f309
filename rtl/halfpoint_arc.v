// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// ============================================================================
// halfpoint_arc: half-point minimum-deviation circular interpolator (seed 000)
// ============================================================================
// Interpolates one circular arc per command on the integer lattice (1 BLU per
// axis step), one lattice move per clock while `en` is high, through every
// quadrant crossing, with one clock without a move from one arc to the next.
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
// enters the run stage when that is idle (the edge after the previous arc's
// last move, not that edge: the end test feeds no load).  The outputs (running,
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
// Register names: of the increments P1..P5, Q1, Q2, Q4, G1..G3 of the README's
// pipeline table six are registers, named after what they add to and after
// which move: d_add_a (P3, to D1 and D2), d2_add_b (Q1), d2_add_c (Q2),
// d2_add_b_cross (Q4), f_add_b (G1), f_add_a (G3); the other five come from
// them and from v through the adders' carry-in: P1 = Q1 + 1, P4 = Q4 + 1,
// G2 = 2v + 1 (v_q with a 1 appended), P2 = G2 + 1, P5 = ~v + 1.  Registers end in _q, the
// value they take at the next edge in _n; pend_* is the pending slot, quad
// a quadrant (0..3 = I..IV), ue/ve the end point in its quadrant's frame,
// and a flag such as v_plus1_eq_ue_q holds "v + 1 == ue" for the current v.
//
// Outputs are registered (x, y, f are the run stage's own point and F
// registers).  In the clock after a move edge: move=1, step_x/y
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
    localparam integer SQUARE_W = 2 * W;    // width of a square
    // small signed constants at datapath width
    localparam [DATA_W-1:0] ZERO_D        = {DATA_W{1'b0}};
    localparam [DATA_W-1:0] ONE_D         = {{(DATA_W-4){1'b0}}, 4'd1};
    localparam [DATA_W-1:0] TWO_D         = {{(DATA_W-4){1'b0}}, 4'd2};
    localparam [DATA_W-1:0] THREE_D       = {{(DATA_W-4){1'b0}}, 4'd3};
    localparam [DATA_W-1:0] FOUR_D        = {{(DATA_W-4){1'b0}}, 4'd4};
    localparam [DATA_W-1:0] FIVE_D        = {{(DATA_W-4){1'b0}}, 4'd5};
    localparam [DATA_W-1:0] SIX_D         = {{(DATA_W-4){1'b0}}, 4'd6};
    localparam [DATA_W-1:0] SEVEN_D       = {{(DATA_W-4){1'b0}}, 4'd7};
    localparam [DATA_W-1:0] MINUS_THREE_D = ~TWO_D;
    localparam [W-1:0]      ONE_W         = {{(W-1){1'b0}}, 1'b1};
    localparam [W-1:0]      TWO_W         = {{(W-2){1'b0}}, 2'd2};
    localparam integer SQUARE_LAST = W - 1;
    // validator states
    localparam [2:0] STATE_IDLE   = 3'd0;
    localparam [2:0] STATE_SQUARE = 3'd1;
    localparam [2:0] STATE_SUM    = 3'd2;
    localparam [2:0] STATE_CHECK  = 3'd3;
    localparam [2:0] STATE_DECIDE = 3'd4;
    localparam [2:0] STATE_INIT   = 3'd5;
    localparam [2:0] STATE_HOLD   = 3'd6;
    // Largest accepted R^2: (M-1)(M-2) = M^2 - 3M + 2, M = 2^(W-1).
    localparam [SQUARE_W+1:0] ONE_SQUARE = {{(SQUARE_W+1){1'b0}}, 1'b1};
    localparam [SQUARE_W+1:0] THREE_SQUARE = {{(SQUARE_W){1'b0}}, 2'b11};
    localparam [SQUARE_W+1:0] RADIUS_SQUARE_MAX =
        (ONE_SQUARE << (2*W-2)) - (THREE_SQUARE << (W-1)) + (ONE_SQUARE << 1);

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

    // ------------------------------------------------------------------
    // Validator: capture, square by shift-and-add, check, prepare.
    // ------------------------------------------------------------------
    reg  [2:0]          validator_state_q;
    // validator_state_q == STATE_HOLD, as a flip-flop of its own (it gates
    // the load of the pending arc)
    reg                 hold_q;
    reg  [5:0]          square_count_q;
    reg                 cmd_cw_q;
    // raw start point (the end point is kept as magnitudes and its quadrant,
    // pend_end_quad_q, taken at the accepting edge)
    reg  [W-1:0]        cmd_xs_q, cmd_ys_q;
    reg  [W-1:0]        abs_xs_q, abs_ys_q, abs_xe_q, abs_ye_q;   // magnitudes
    // R^2 = xs^2 + ys^2 and |E|^2 = xe^2 + ye^2, each by one shift-and-add
    // register {high W+1 bits, low W bits}: the low half starts as |xs|
    // (|xe|) and shifts the product's bits in as the multiplier's bits go
    // out; the multiplier bit of |ys| (|ye|) is registered a clock ahead from
    // the magnitude (multiplier_*_bit_q: bit k at count k).
    // Each clock adds 0, |xs|, |ys| or both to the high half: that sum is
    // below 2^W + 2^W, so after the shift the high half stays below 2^W and
    // the pair ends as the sum of squares (< 2^(2W-1) + 2^(2W-2)), 2W+1 bits.
    reg  [SQUARE_W:0]   radius_square_q, end_square_q;            // R^2 and |E|^2
    reg                 multiplier_ys_bit_q, multiplier_ye_bit_q;
    reg  [W:0]          tolerance_q;                              // 2 max(|xs|, |ys|)
    // the checks: R = 0, R^2 too big, |E|^2 - R^2 > tolerance, R^2 - |E|^2 > tolerance
    reg                 radius_zero_q, radius_too_big_q, end_outside_q, end_inside_q;
    // the frame comparator's last difference (see prepare below), W + 1 bits
    // signed: both operands are magnitudes below 2^W
    reg  [W:0]          compare_difference_q;

    // pending command: the quadrants, the magnitudes (abs_*_q) and the end
    // test's flags; D1, D2 and the six increments, each one carry chain from
    // u and v, are computed by the load (see the run stage)
    reg  [1:0]        pend_quad_q, pend_end_quad_q;
    // the start's and the end's u (the other magnitude is v), from their
    // quadrants at the accepting edge; the magnitudes stay in abs_*_q, which
    // hold the command until it leaves the pending slot
    reg               start_u_is_x_q, end_u_is_x_q;
    wire [W-1:0]      pend_u  = start_u_is_x_q ? abs_xs_q : abs_ys_q;
    wire [W-1:0]      pend_v  = start_u_is_x_q ? abs_ys_q : abs_xs_q;
    wire [W-1:0]      pend_ue = end_u_is_x_q ? abs_xe_q : abs_ye_q;
    wire [W-1:0]      pend_ve = end_u_is_x_q ? abs_ye_q : abs_xe_q;
    reg               pend_armed_q, pend_first_octant_q, pend_ve_zero_q;
    reg               pend_ve_one_q, pend_ue_zero_q, pend_ue_one_q, pend_u_one_q;
    // the run stage's comparison flags for the start point (see the run stage)
    reg               pend_v_gt_ve_q, pend_v_eq_ve_q, pend_v_plus1_eq_ve_q;
    reg               pend_u_lt_ue_q, pend_u_eq_ue_q, pend_u_eq_ue_plus1_q;
    reg               pend_v_lt_ue_q, pend_v_eq_ue_q, pend_v_plus1_eq_ue_q;

    assign s_ready = (validator_state_q == STATE_IDLE) && !abort_now;
    wire   accept  = s_valid && s_ready;

    function [W-1:0] magnitude;
        input [W-1:0] a;
        begin
            magnitude = a[W-1] ? (~a + {{(W-1){1'b0}}, 1'b1}) : a;
        end
    endfunction

    // bit i of a (0 for i >= W): a multiplexer
    function bit_at;
        input [W-1:0] a;
        input [5:0]   i;
        reg   [63:0]  padded;
        begin
            padded = {{(64-W){1'b0}}, a};
            bit_at = padded[i];
        end
    endfunction

    // one shift-and-add step of a sum of two squares: P = {hi, lo};
    // hi += (lo[0] ? a : 0) + (b_bit ? b : 0), then P shifts right by one
    function [SQUARE_W:0] squares_step;
        input [SQUARE_W:0] p;
        input [W-1:0]      a;
        input              b_bit;
        input [W-1:0]      b;
        reg   [W+1:0]      s;
        begin
            s = {1'b0, p[SQUARE_W:W]} + (p[0] ? {2'b00, a} : {(W+2){1'b0}})
                + (b_bit ? {2'b00, b} : {(W+2){1'b0}});
            squares_step = {s, p[W-1:1]};
        end
    endfunction

    // The validator's work is spread so that each clock does at most one
    // add (of three operands, in SQUARE) or compare: the frame set-up of the
    // pending slot runs in the first seven squaring clocks (W >= 8 of them;
    // the pending slot is free then, as a command is taken only when the
    // previous one has left it), the squaring registers end as the sums of
    // squares (SUM is an idle clock, kept for the timing at the ports), and
    // CHECK registers the three checks.  By squaring clock (count):
    //   0: R = 0   1: the end point's and u's constant flags
    // and one subtractor, the comparator, takes one pair per clock
    //   1: v - ve   2: u - ue   3: v - ue   4: ve - ue   5: |xs| - |ys|
    // with the flags registered from its difference a clock later (counts
    // 2 to 6; the armed flag, which needs them all, at 6).
    wire       squaring      = (validator_state_q == STATE_SQUARE);
    wire [5:0] square_next   = square_count_q + 6'd1;
    wire       prepare_at_0  = squaring && (square_count_q == 6'd0);
    wire       prepare_at_1  = squaring && (square_count_q == 6'd1);
    wire       prepare_at_2  = squaring && (square_count_q == 6'd2);
    wire       prepare_at_3  = squaring && (square_count_q == 6'd3);
    wire       prepare_at_4  = squaring && (square_count_q == 6'd4);
    wire       prepare_at_5  = squaring && (square_count_q == 6'd5);
    wire       prepare_at_6  = squaring && (square_count_q == 6'd6);

    // CHECK: a - b > t, as the sign of a + ~b + ~t + 1 = a - b - t - 1, with
    // the three operands reduced to two by a carry-save step (one LUT level
    // before a single carry chain)
    localparam integer CHECK_W = SQUARE_W + 3;
    function exceeds;
        input [SQUARE_W:0] a;
        input [SQUARE_W:0] b;
        input [W:0]        t;
        reg   [CHECK_W-1:0] first, second, third, half_sum, carries, total;
        begin
            first    = {2'b00, a};
            second   = ~{2'b00, b};
            third    = ~{{(CHECK_W-W-1){1'b0}}, t};
            half_sum = first ^ second ^ third;
            carries  = {((first[CHECK_W-2:0] & second[CHECK_W-2:0]) |
                         (first[CHECK_W-2:0] & third[CHECK_W-2:0]) |
                         (second[CHECK_W-2:0] & third[CHECK_W-2:0])), 1'b1};
            total    = half_sum + carries;
            exceeds  = !total[CHECK_W-1];
        end
    endfunction

    // the start's and the end's quadrant, taken at the accepting edge
    wire [1:0] accept_start_quad = quadrant_of(s_cw, s_xs, s_ys);
    wire [1:0] accept_end_quad   = quadrant_of(s_cw, s_xe, s_ye);
    wire [1:0] decide_error = radius_zero_q ? 2'd1 : radius_too_big_q ? 2'd2
                            : (end_outside_q || end_inside_q) ? 2'd3 : 2'd0;

    // the comparator (schedule above) and what its difference tells
    wire [W-1:0] compare_a = (square_count_q == 6'd2) ? pend_u
                           : (square_count_q == 6'd4) ? pend_ve
                           : (square_count_q == 6'd5) ? abs_xs_q
                           : pend_v;
    wire [W-1:0] compare_b = (square_count_q == 6'd1) ? pend_ve
                           : (square_count_q == 6'd5) ? abs_ys_q
                           : pend_ue;
    wire         compare_negative = compare_difference_q[W];
    wire         compare_zero     = (compare_difference_q == {(W+1){1'b0}});
    wire         compare_minus1   = (compare_difference_q == {(W+1){1'b1}});
    wire         compare_plus1    = (compare_difference_q == {{W{1'b0}}, 1'b1});

    // frame set-up: armed flag from the progress order, from the flags
    // (v < ve, u > ue: neither of the other two)
    wire       init_v_before = (!pend_v_gt_ve_q && !pend_v_eq_ve_q) ||
                               (pend_v_eq_ve_q && !pend_u_lt_ue_q && !pend_u_eq_ue_q);
    wire       init_u_before = (!pend_u_lt_ue_q && !pend_u_eq_ue_q) ||
                               (pend_u_eq_ue_q && !pend_v_gt_ve_q && !pend_v_eq_ve_q);
    wire       init_before   = pend_first_octant_q ? init_v_before : init_u_before;

    // run-stage handshake with the pending slot (defined below)
    wire       load;

    always @(posedge clk) begin
        if (rst || abort_now) begin
            hold_q <= 1'b0;
        end else if (validator_state_q == STATE_INIT) begin
            hold_q <= 1'b1;
        end else if (load) begin
            hold_q <= 1'b0;
        end
    end

    always @(posedge clk) begin
        if (rst || abort_now) begin
            validator_state_q <= STATE_IDLE;
            square_count_q    <= 6'd0;
        end else begin
            case (validator_state_q)
                STATE_IDLE: if (accept) begin
                    validator_state_q <= STATE_SQUARE;
                    square_count_q    <= 6'd0;
                end
                STATE_SQUARE: begin
                    square_count_q <= square_count_q + 6'd1;
                    if (square_count_q == SQUARE_LAST[5:0]) validator_state_q <= STATE_SUM;
                end
                STATE_SUM:    validator_state_q <= STATE_CHECK;
                STATE_CHECK:  validator_state_q <= STATE_DECIDE;
                STATE_DECIDE: validator_state_q <= (decide_error != 2'd0) ? STATE_IDLE : STATE_INIT;
                STATE_INIT:   validator_state_q <= STATE_HOLD;
                STATE_HOLD:   if (load) validator_state_q <= STATE_IDLE;
                default:      validator_state_q <= STATE_IDLE;
            endcase
        end
    end

    // validator datapath (no reset needed: qualified by validator_state_q)
    always @(posedge clk) begin
        if (accept) begin
            cmd_cw_q <= s_cw;
            cmd_xs_q <= s_xs;
            cmd_ys_q <= s_ys;
            // the pending slot is free at an accepting edge (the previous
            // command has left it), so the quadrants go there at once
            pend_quad_q     <= accept_start_quad;
            pend_end_quad_q <= accept_end_quad;
            start_u_is_x_q  <= (accept_start_quad[0] == s_cw);
            end_u_is_x_q    <= (accept_end_quad[0] == s_cw);
            abs_xs_q <= magnitude(s_xs);
            abs_ys_q <= magnitude(s_ys);
            abs_xe_q <= magnitude(s_xe);
            abs_ye_q <= magnitude(s_ye);
            radius_square_q <= {{(W+1){1'b0}}, magnitude(s_xs)};
            end_square_q    <= {{(W+1){1'b0}}, magnitude(s_xe)};
            // bit 0 of a magnitude is the number's own bit 0
            multiplier_ys_bit_q <= s_ys[0];
            multiplier_ye_bit_q <= s_ye[0];
        end
        if (squaring) begin
            radius_square_q <= squares_step(radius_square_q, abs_xs_q, multiplier_ys_bit_q,
                                            abs_ys_q);
            end_square_q    <= squares_step(end_square_q, abs_xe_q, multiplier_ye_bit_q,
                                            abs_ye_q);
            multiplier_ys_bit_q <= bit_at(abs_ys_q, square_next);
            multiplier_ye_bit_q <= bit_at(abs_ye_q, square_next);
        end
        if (squaring)
            compare_difference_q <= {1'b0, compare_a} - {1'b0, compare_b};
        if (prepare_at_0)
            radius_zero_q   <= (abs_xs_q == {W{1'b0}}) && (abs_ys_q == {W{1'b0}});
        if (prepare_at_1) begin
            pend_ve_zero_q        <= (pend_ve == {W{1'b0}});
            pend_ve_one_q         <= (pend_ve == ONE_W);
            pend_ue_zero_q        <= (pend_ue == {W{1'b0}});
            pend_ue_one_q         <= (pend_ue == ONE_W);
            pend_u_one_q          <= (pend_u == ONE_W);
        end
        // magnitudes are at most 2^(W-1): the differences do not wrap, and
        // v + 1 == ve (a difference of -1) implies ve != 0
        if (prepare_at_2) begin
            pend_v_gt_ve_q        <= !compare_negative && !compare_zero;    // v - ve
            pend_v_eq_ve_q        <= compare_zero;
            pend_v_plus1_eq_ve_q  <= compare_minus1;
        end
        if (prepare_at_3) begin
            pend_u_lt_ue_q        <= compare_negative;                      // u - ue
            pend_u_eq_ue_q        <= compare_zero;
            pend_u_eq_ue_plus1_q  <= compare_plus1;
        end
        if (prepare_at_4) begin
            pend_v_lt_ue_q        <= compare_negative;                      // v - ue
            pend_v_eq_ue_q        <= compare_zero;
            pend_v_plus1_eq_ue_q  <= compare_minus1;
        end
        if (prepare_at_5)
            pend_first_octant_q   <= compare_negative || compare_zero;      // ve <= ue
        if (prepare_at_6) begin
            tolerance_q           <= {(!compare_negative && !compare_zero) ? abs_xs_q
                                                                          : abs_ys_q, 1'b0};
            pend_armed_q          <= !((pend_quad_q == pend_end_quad_q) && !init_before);
        end
        if (validator_state_q == STATE_CHECK) begin
            radius_too_big_q <= ({1'b0, radius_square_q} > RADIUS_SQUARE_MAX);
            end_outside_q    <= exceeds(end_square_q, radius_square_q, tolerance_q);
            end_inside_q     <= exceeds(radius_square_q, end_square_q, tolerance_q);
        end
    end

    // ------------------------------------------------------------------
    // Run stage
    // ------------------------------------------------------------------
    reg               run_q, cw_q, armed_q, first_octant_q, ve_zero_q;
    reg  [1:0]        quad_q, end_quad_q;
    reg  [W-1:0]      u_q, v_q;
    // the end point in its quadrant's frame (for the look-ahead)
    reg  [W-1:0]      ue_q, ve_q;
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
    // crossing (u' = v or v + 1, v' = 0; ~(2v + 1) = -2v - 2); see README;
    // one adder per register, its operands multiplexed
    // registers whose term is -2u gain 2 on every move that lowers u
    wire [DATA_W-1:0] u_term_add = u_down ? TWO_D : ZERO_D;
    wire [DATA_W-1:0] v_crossed  = ~v_twice_plus1;
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

    // a == b + k (modulo 2^W) without a carry chain: a + ~b == k - 1 (given
    // as c), tested bit by bit: the carry each sum bit needs into it (a ^ ~b
    // ^ c) must be the carry out of the bit below given the carry that one
    // needs, and bit 0 needs none; one LUT per bit (bits i and i - 1 of a
    // and b) and an AND, instead of a register and an adder for b + k
    function equals_plus;
        input [W-1:0] a;
        input [W-1:0] b;
        input [W-1:0] c;
        reg   [W-1:0] b_inverted, needs;
        reg   [W-2:0] gives;                    // the carry out of bits 0 .. W-2
        begin
            b_inverted  = ~b;
            needs       = a ^ b_inverted ^ c;
            gives       = (a[W-2:0] & b_inverted[W-2:0]) | (a[W-2:0] & needs[W-2:0])
                          | (b_inverted[W-2:0] & needs[W-2:0]);
            equals_plus = !needs[0] && (needs[W-1:1] == gives);
        end
    endfunction
    localparam [W-1:0] PLUS1_C  = {W{1'b0}};                    // k = 1: c = 0
    localparam [W-1:0] PLUS2_C  = ONE_W;                        // k = 2: c = 1
    localparam [W-1:0] MINUS2_C = ~TWO_W;                       // k = -2: c = -3

    // look-ahead: the flags for the point after this move, from the flags of
    // this point, the move, and equality tests of this point with constants
    // (they end at the flag registers, not in the enable path)
    wire v_eq_ve_minus2 = equals_plus(v_q, ve_q, MINUS2_C);
    wire v_eq_ue_minus2 = equals_plus(v_q, ue_q, MINUS2_C);
    wire u_eq_ue_plus2  = equals_plus(u_q, ue_q, PLUS2_C);
    wire v_eq_ue_plus1  = equals_plus(v_q, ue_q, PLUS1_C);
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

    // The start point's D1, D2 and the six increments are computed at the
    // load from the pending u and v, each by one carry chain (three of them
    // after a carry-save level with their constant), rather than kept in the
    // pending slot (F = 0 there; ~a = -a - 1 modulo 2^(W+2)):
    //   D1 = v - 2u + 1 = v + ~(2u) + 2       D2 = 2v - u + 1 = {v, 1} + ~u + 1
    //   P3 = 2v - 2u + 5 = 2v + ~(2u) + 6     G3 = 2v - 2u + 2 = 2v + ~(2u) + 3
    //   Q1 = 2 - 2u = ~(2u) + 3               Q2 = 2v + 3
    //   Q4 = -3v = v - 4v = v + ~(4v) + 1     G1 = 1 - 2u = ~(2u) + 2
    function [DATA_W-1:0] add_three;            // a + b + c: carry-save, one chain
        input [DATA_W-1:0] a;
        input [DATA_W-1:0] b;
        input [DATA_W-1:0] c;
        begin
            add_three = (a ^ b ^ c) + (((a & b) | (a & c) | (b & c)) << 1);
        end
    endfunction
    wire [DATA_W-1:0] load_u_twice  = {1'b0, pend_u, 1'b0};
    wire [DATA_W-1:0] load_v        = {2'b00, pend_v};
    wire [DATA_W-1:0] load_v_twice  = {1'b0, pend_v, 1'b0};
    wire [DATA_W-1:0] load_d1       = add_three(load_v, ~load_u_twice, TWO_D);
    wire [DATA_W-1:0] load_d2       = {1'b0, pend_v, 1'b1} - {2'b00, pend_u};
    wire [DATA_W-1:0] load_d_add_a  = add_three(load_v_twice, ~load_u_twice, SIX_D);
    wire [DATA_W-1:0] load_f_add_a  = add_three(load_v_twice, ~load_u_twice, THREE_D);
    wire [DATA_W-1:0] load_d2_add_b = ~load_u_twice + THREE_D;
    wire [DATA_W-1:0] load_d2_add_c = load_v_twice + THREE_D;
    wire [DATA_W-1:0] load_d2_add_b_cross = load_v - {pend_v, 2'b00};
    wire [DATA_W-1:0] load_f_add_b  = ~load_u_twice + TWO_D;

    assign load = hold_q && start_en && !abort_now && !run_q;     // only into an idle stage

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

    always @(posedge clk) begin
        if (load) begin
            cw_q             <= cmd_cw_q;
            quad_q           <= pend_quad_q;
            end_quad_q       <= pend_end_quad_q;
            u_q              <= pend_u;
            v_q              <= pend_v;
            ue_q             <= pend_ue;
            ve_q             <= pend_ve;
            ve_zero_q        <= pend_ve_zero_q;
            first_octant_q   <= pend_first_octant_q;
            armed_q          <= pend_armed_q;
            ve_one_q         <= pend_ve_one_q;
            ue_zero_q        <= pend_ue_zero_q;
            ue_one_q         <= pend_ue_one_q;
            u_one_q          <= pend_u_one_q;
            v_gt_ve_q        <= pend_v_gt_ve_q;
            v_eq_ve_q        <= pend_v_eq_ve_q;
            v_plus1_eq_ve_q  <= pend_v_plus1_eq_ve_q;
            u_lt_ue_q        <= pend_u_lt_ue_q;
            u_eq_ue_q        <= pend_u_eq_ue_q;
            u_eq_ue_plus1_q  <= pend_u_eq_ue_plus1_q;
            v_lt_ue_q        <= pend_v_lt_ue_q;
            v_eq_ue_q        <= pend_v_eq_ue_q;
            v_plus1_eq_ue_q  <= pend_v_plus1_eq_ue_q;
            d1_q             <= load_d1;
            d2_q             <= load_d2;
            d_add_a_q        <= load_d_add_a;
            d2_add_b_q       <= load_d2_add_b;
            d2_add_c_q       <= load_d2_add_c;
            d2_add_b_cross_q <= load_d2_add_b_cross;
            f_add_b_q        <= load_f_add_b;
            f_add_a_q        <= load_f_add_a;
        end else if (advance) begin
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

    // The current point and its F are the outputs x, y, f themselves: a
    // move's edge writes the point it reaches, a load the start point with
    // F = 0, and a reset 0 (run-stage registers otherwise need no reset)
    always @(posedge clk) begin
        if (rst) begin
            point_x_q <= {W{1'b0}};
            point_y_q <= {W{1'b0}};
            f_q       <= {DATA_W{1'b0}};
        end else if (load) begin
            point_x_q <= cmd_xs_q;
            point_y_q <= cmd_ys_q;
            f_q       <= {DATA_W{1'b0}};
        end else if (advance) begin
            point_x_q <= point_x_n;
            point_y_q <= point_y_n;
            f_q       <= f_q + f_add;
        end
    end
    assign x = point_x_q;
    assign y = point_y_q;
    assign f = f_q;

    // ------------------------------------------------------------------
    // Registered outputs
    // ------------------------------------------------------------------
    wire rejecting = (validator_state_q == STATE_DECIDE) && (decide_error != 2'd0) && !abort_now;

    always @(posedge clk) begin
        if (rst) begin
            move     <= 1'b0;
            step_x   <= 1'b0;
            step_y   <= 1'b0;
            dir_x    <= 1'b0;
            dir_y    <= 1'b0;
            done     <= 1'b0;
            reject   <= 1'b0;
            err_code <= 2'd0;
        end else begin
            move   <= advance;
            step_x <= advance && x_steps;
            step_y <= advance && y_steps;
            if (advance && x_steps) dir_x <= x_direction;
            if (advance && y_steps) dir_y <= y_direction;
            done   <= last;
            reject <= rejecting;
            if (rejecting) err_code <= decide_error;
        end
    end

`ifdef FORMAL
    // ========================================================================
    // Formal properties (SymbiYosys: formal/halfpoint_arc.sby, run by
    // python -m halfpoint.flows.formal).  Verilator, Icarus and the cocotb
    // builds do not define FORMAL, so they see the module above unchanged.
    // ========================================================================
    // A monitor follows every command from acceptance to its end: the slot
    // (f_slot_*: the command being validated or pending, with its R^2, |E|^2
    // and the reject code it must get, computed here by multiplication) and
    // the running arc (f_run_*: its R^2 and the moves made), and asserts:
    //   handshake  s_ready only with the validator empty and no abort; the
    //              master holds s_valid and the command until taken (assumed);
    //   no loss    a taken command is validated in W + 5 clocks, then either
    //              rejected and never loaded (F_CODES: with the code of its
    //              check, 1 R = 0, 2 R^2 > (M-1)(M-2), 3 end off the circle),
    //              or loaded into the run stage from the pending slot and run
    //              to its done; only abort_now or rst drops it; busy iff a
    //              command is held anywhere;
    //   increments every increment register equals its formula in u, v, F
    //              (README, "Pipeline"): D1 = F - 2u + v + 1, D2 = F - u + 2v
    //              + 1, P3 = -2u + 2v + 5, Q1 = -2u + 2, Q2 = 2v + 3, Q4 = -3v,
    //              G1 = -2u + 1, G3 = -2u + 2v + 2, in the pending slot or as
    //              the load computes them, and at
    //              every move of the run stage;
    //   circle     (F_RUN_CIRCLE) the bound -(|x| + |y|) <= F < |x| + |y|
    //              (the point within about half a BLU of the circle) for the
    //              run stage and the f output, and the range 1 <= u <= M - 2,
    //              v <= M - 2 (no datapath overflow); without F_RUN_CIRCLE
    //              that range is ASSUMED in the run stage (F_LOAD_CIRCLE
    //              proves it from the circle, below);
    //   bound      (F_RUN_BOUND) the same bound under the assumed range: it
    //              is linear in F, u, v and every move keeps it, so it closes
    //              by k-induction without the circle;
    //   frame      the point (x, y) is (+-u, +-v) or (+-v, +-u) by quadrant and
    //              direction (README, "The algorithm in brief");
    //   steps      a move changes each axis by at most one BLU, step_x/step_y
    //              exactly when it changes, dir_x/dir_y its sign, held between
    //              steps; x, y, f, move, done, reject are the registered views
    //              of the edge before;
    //   ends       (F_RUN_ENDS) termination: every arc stops within 5 * 2^W
    //              moves, under the assumed range (see the block below);
    //              F_ENDS_R: within 5 (2 floor(R) + 2) + 1 moves, from the
    //              circle and the bound;
    //   stop rule  (F_STOP_RULE) the end test is the documented rule, its
    //              look-ahead flags tied to u, v and the end point;
    //   range      (F_LOAD_CIRCLE with F_RUN_CIRCLE) the circle, the bound and
    //              the range proven, the validator's radius checks assumed at
    //              the load (codes, squaring and squares prove them) and the
    //              increments one clock late (see below);
    //   codes      (F_CODES) the reject codes against the squarer's sums as it
    //              ends them (taken in SUM): each check, the code given, and
    //              at the load what range_w8 assumes there (with a_load_ok);
    //   free squares (F_SQUARES_FREE with F_LOAD_CIRCLE, the tasks range_sq_*)
    //              the range's proof with u^2, v^2 and the start's squares as
    //              free values under lemmas true squares obey (next u^2 after
    //              u - 1 is u^2 - 2u + 1, ...): no multiplier, so it closes at
    //              W = 16 too;
    //   squaring   (F_SQUARING, F_SQUARING_K = k) the squaring registers after
    //              k clocks against the shift-and-add partial sums of the
    //              command's magnitudes (linear: no product in the induction),
    //              and the sums taken against those after W clocks;
    //   squarer    (F_SQUARER with F_SQUARER_LINK or F_SQUARER_GHOST) the
    //              same cut at ghost accumulators so that the registers'
    //              part closes at any width (the block below);
    //   squares    (F_SQUARE_LEMMA) the partial sums after W clocks are the
    //              sums of squares: with the two above, the codes hold
    //              against xs^2 + ys^2 and xe^2 + ye^2;
    // Labels: a_* the contract, i_* invariants that tie the validator's
    // registers and the run stage to the monitor so that k-induction closes.
    // The tasks of codes, squaring, F_ENDS_R and the stop rule assert their
    // own labels only; the sby file turns every other assertion into an
    // assumption (Yosys chformal), each proven by a task that does not
    // assume them.
    // rst, en, start_en and abort_now are free (rst high on the first clock).
    // F_PROTOCOL_ONLY leaves out the run stage's invariants (a quick proof).
    // F_INCREMENTS_ASSUMED (the task bound_w8): the run stage's increment
    // invariants, which prove_w8 proves without the bound, are assumed, so
    // that the bound's induction has only the bound to find
    // F_INCREMENTS_PAST (the task range_w8): they are assumed one clock late
    // only (at the clock before), and not checked at the current one (a cover
    // is not checked in prove mode): see the block F_LOAD_CIRCLE
`ifdef F_INCREMENTS_ASSUMED
`define F_INC assume
`elsif F_INCREMENTS_PAST
`define F_INC cover
`else
`define F_INC assert
`endif
    // F's bound on the registered output too, wherever it is asserted
`ifdef F_RUN_CIRCLE
`define F_OUT_BOUND
`endif
`ifdef F_RUN_BOUND
`define F_OUT_BOUND
`endif
    localparam integer F_PW = 2 * W + 4;                    // squares and their sums
    localparam integer F_MW = W + 4;                        // an arc's moves: < 5 * 2^W
    localparam [W-1:0] F_MAG_MAX = {1'b0, {(W-2){1'b1}}, 1'b0};     // M - 2
    localparam [F_PW-1:0] F_R2_MAX = {2'b00, RADIUS_SQUARE_MAX};

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
            f_rule_offer_cw: assume(s_cw == $past(s_cw));
            f_rule_offer_start: assume(s_xs == $past(s_xs) && s_ys == $past(s_ys));
            f_rule_offer_end: assume(s_xe == $past(s_xe) && s_ye == $past(s_ye));
        end

    function [F_PW-1:0] f_wide;                 // zero-extended magnitude
        input [W-1:0] f_a;
        begin
            f_wide = {{(F_PW-W){1'b0}}, (f_a[W-1] ? (~f_a + ONE_W) : f_a)};
        end
    endfunction

    // the slot: the command being validated or pending
    reg           f_slot_valid, f_slot_cw;
    reg  [W-1:0]  f_slot_xs, f_slot_ys, f_slot_xe, f_slot_ye;
    reg  [5:0]    f_slot_age;                   // clocks since taken (saturating)
    wire [F_PW-1:0] f_axs = f_wide(f_slot_xs), f_ays = f_wide(f_slot_ys);
    wire [F_PW-1:0] f_axe = f_wide(f_slot_xe), f_aye = f_wide(f_slot_ye);
    wire [F_PW-1:0] f_slot_tol = (f_axs > f_ays) ? (f_axs << 1) : (f_ays << 1);
    // the shift-and-add partial sum of two squares after k clocks: the sum
    // over i < k of a_i (a << i) + b_i (b << i), that is a (a mod 2^k) +
    // b (b mod 2^k), added in the squarer's order (a's term, then b's, one
    // bit after the other) and without a product, so that the induction
    // stays linear and each clock's step is the squarer's own add; at k = W
    // it is a^2 + b^2 for all a, b < 2^W, which F_SQUARE_LEMMA (the task
    // square_w8) proves
    function [F_PW-1:0] f_squares;
        input [F_PW-1:0] f_a;
        input [F_PW-1:0] f_b;
        input [5:0]      f_k;
        integer          f_i;
        begin
            f_squares = {F_PW{1'b0}};
            for (f_i = 0; f_i < W; f_i = f_i + 1)
                if (f_i < f_k)
                    f_squares = f_squares + (f_a[f_i] ? (f_a << f_i) : {F_PW{1'b0}})
                                          + (f_b[f_i] ? (f_b << f_i) : {F_PW{1'b0}});
        end
    endfunction
    localparam [5:0] F_ALL = W;
    // the squarer's sums R^2, |E|^2 as it ends them (taken in SUM): the codes
    // are proven against these (F_CODES), and these equal the partial sums
    // after W clocks (F_SQUARING, k = W + 1) and so the sums of squares
    // (F_SQUARE_LEMMA); kept apart so that no task has both the checks and
    // the squares to solve (together they had not finished in 10 minutes)
    reg  [SQUARE_W:0] f_sum_r2_q, f_sum_e2_q;
    always @(posedge clk)
        if (validator_state_q == STATE_SUM) begin
            f_sum_r2_q <= radius_square_q;
            f_sum_e2_q <= end_square_q;
        end
    wire f_summed = (validator_state_q >= STATE_CHECK);        // the sums are taken
`ifdef F_CODES
    wire [F_PW-1:0] f_slot_r2 = {3'b000, f_sum_r2_q};
    wire [F_PW-1:0] f_slot_e2 = {3'b000, f_sum_e2_q};
    wire [1:0]      f_slot_err =
        (f_axs == {F_PW{1'b0}} && f_ays == {F_PW{1'b0}}) ? 2'd1    // R = 0: S at the centre
        : (f_slot_r2 > F_R2_MAX) ? 2'd2
        : (f_slot_e2 > f_slot_r2 + f_slot_tol || f_slot_r2 > f_slot_e2 + f_slot_tol) ? 2'd3
        : 2'd0;
`endif

    // the running arc
    reg             f_run_valid, f_run_cw;
    reg  [W-1:0]    f_run_xs, f_run_ys;
    reg             f_run_full;                 // start = end: a full circle
    reg  [F_MW-1:0] f_moves;                    // the moves made since the load
    // the arc of the last move (for the registered outputs), the point before
    reg  [W-1:0]    f_out_xs, f_out_ys, f_px_d, f_py_d;
    reg             f_out_full;

    always @(posedge clk) begin
        f_px_d <= point_x_q;
        f_py_d <= point_y_q;
        if (advance) begin
            f_out_xs   <= f_run_xs;
            f_out_ys   <= f_run_ys;
            f_out_full <= f_run_full;
        end
        if (rst || abort_now) begin
            f_slot_valid <= 1'b0;
            f_run_valid  <= 1'b0;
        end else begin
            if (f_slot_age != 6'h3f) f_slot_age <= f_slot_age + 6'd1;
            if (rejecting || load) f_slot_valid <= 1'b0;
            if (accept) begin
                f_slot_valid <= 1'b1;
                f_slot_cw    <= s_cw;
                f_slot_xs    <= s_xs;
                f_slot_ys    <= s_ys;
                f_slot_xe    <= s_xe;
                f_slot_ye    <= s_ye;
                f_slot_age   <= 6'd0;
            end
            if (advance) f_moves <= f_moves + 1'b1;
            if (last) f_run_valid <= 1'b0;
            if (load) begin
                f_run_valid <= 1'b1;
                f_run_cw    <= f_slot_cw;
                f_run_xs    <= f_slot_xs;
                f_run_ys    <= f_slot_ys;
                f_run_full  <= (f_slot_xs == f_slot_xe) && (f_slot_ys == f_slot_ye);
                f_moves     <= {F_MW{1'b0}};
            end
        end
    end

    // ---- handshake, no loss, validation ----
    // f_afterK: the validator has passed its squaring clock K (count K + 1 on)
    wire f_after0 = (validator_state_q > STATE_SQUARE) || (squaring && square_count_q >= 6'd1);
    wire f_after1 = (validator_state_q > STATE_SQUARE) || (squaring && square_count_q >= 6'd2);
    wire f_after2 = (validator_state_q > STATE_SQUARE) || (squaring && square_count_q >= 6'd3);
    wire f_after3 = (validator_state_q > STATE_SQUARE) || (squaring && square_count_q >= 6'd4);
    wire f_after4 = (validator_state_q > STATE_SQUARE) || (squaring && square_count_q >= 6'd5);
    wire f_after5 = (validator_state_q > STATE_SQUARE) || (squaring && square_count_q >= 6'd6);
    wire f_after6 = (validator_state_q > STATE_SQUARE) || (squaring && square_count_q >= 6'd7);
    always @(*)
        if (f_past_valid && !rst) begin
            a_ready_empty: assert(!s_ready || (!f_slot_valid && !abort_now));
            a_slot_held:   assert(f_slot_valid == (validator_state_q != STATE_IDLE));
            a_run_held:    assert(f_run_valid == run_q);
            a_busy:        assert(busy == (f_slot_valid || f_run_valid));
            i_state:       assert(validator_state_q <= STATE_HOLD);
            i_hold:        assert(hold_q == (validator_state_q == STATE_HOLD));
            if (rejecting) begin
                a_reject_slot: assert(f_slot_valid && !load);
`ifdef F_CODES
                a_reject_code: assert(f_slot_err != 2'd0 && decide_error == f_slot_err);
`endif
            end
            if (load) begin
                a_load_valid: assert(f_slot_valid && validator_state_q == STATE_HOLD);
                // a pending arc enters only an idle run stage (never at the
                // edge of the running arc's last move)
                a_load_idle:  assert(!run_q && !f_run_valid && !last);
`ifdef F_CODES
                a_load_ok: assert(f_slot_err == 2'd0);
                // with a_load_ok (R^2 <= (M-1)(M-2): u^2 + v^2 in range_w8,
                // the same sum as xs^2 + ys^2, i_uv), what range_w8 assumes
                // at the load (f_load_range): u >= 1
                a_load_u: assert(pend_u != {W{1'b0}});
`endif
            end
            // validation: W clocks of squaring, sum, check, decide, init, hold
            if (squaring) begin
                a_square_time: assert(f_slot_age == square_count_q);
                i_square_last: assert(square_count_q <= SQUARE_LAST[5:0]);
            end
            if (validator_state_q == STATE_SUM)
                a_sum_time: assert(f_slot_age == W);
            if (validator_state_q == STATE_CHECK)
                a_check_time: assert(f_slot_age == W + 1);
            if (validator_state_q == STATE_DECIDE)
                a_decide_time: assert(f_slot_age == W + 2);
            if (validator_state_q == STATE_INIT)
                a_init_time: assert(f_slot_age == W + 3);
            if (validator_state_q == STATE_HOLD)
                a_hold_time: assert(f_slot_age >= W + 4);
        end

    // ---- the validator's registers hold the command taken ----
`ifdef F_SQUARING
    // The squaring registers after k clocks of squaring (k = W: in SUM): the
    // multiplicand's bits not yet shifted out, below the partial sums of both
    // squares, (a >> k) + (a (a mod 2^k) + b (b mod 2^k)) 2^(W-k), and the
    // multiplier's bit of count k, bit k of b; k = W + 1: from CHECK on, the
    // sums taken in SUM are the partial sums after W clocks.  One invariant
    // per k, each with shifts by constants; F_SQUARING_K = j asserts the one for
    // k = j and assumes the others (one sby task per k: proven together by
    // induction on the clock, as only the one for the current k is not
    // vacuous; the single task for all k had not finished in 15 minutes).
    wire f_sum_state = (validator_state_q == STATE_SUM);
    genvar f_k;
    generate
        for (f_k = 0; f_k <= W + 1; f_k = f_k + 1) begin : g_f_squaring
            localparam integer F_KS = (f_k > W) ? W : f_k;       // clocks of squaring
            wire [F_PW-1:0] f_r2_part = (f_axs >> F_KS)
                + (f_squares(f_axs, f_ays, F_KS) << (W - F_KS));
            wire [F_PW-1:0] f_e2_part = (f_axe >> F_KS)
                + (f_squares(f_axe, f_aye, F_KS) << (W - F_KS));
            wire f_now = f_past_valid && !rst && f_slot_valid
                         && ((squaring && square_count_q == f_k) || (f_k == W && f_sum_state)
                             || (f_k == W + 1 && f_summed));
            wire f_held = (f_k == W + 1)
                ? ({3'b000, f_sum_r2_q} == f_r2_part && {3'b000, f_sum_e2_q} == f_e2_part)
                : (({3'b000, radius_square_q} == f_r2_part)
                   && ({3'b000, end_square_q} == f_e2_part)
                   && (f_k == W || (multiplier_ys_bit_q == bit_at(abs_ys_q, f_k)
                                    && multiplier_ye_bit_q == bit_at(abs_ye_q, f_k))));
            // (unlabelled: Yosys names a label once per module)
            always @(*)
                if (f_now) begin
                    if (f_k == `F_SQUARING_K)
                        assert(f_held);
                    else
                        assume(f_held);
                end
        end
    endgenerate
`endif
`ifdef F_SQUARER
    // ---- the squarer at any width (F_SQUARER, the tasks squarer_w* and
    // sqghost_w*) ----
    // F_SQUARING's invariants hold the registers against the partial sums
    // themselves, k rows of a multiplier at count k: at W = 10 its
    // induction had not finished in 10 minutes.  Here the proof is cut in two
    // at ghost accumulators, one per register, that add the rows as the
    // squarer does, a_k (a << k) + b_k (b << k) at count k, in the same order:
    // (1, F_SQUARER_LINK) the registers against the ghosts, one invariant per
    // count, no product and no row sum, which closes at W = 32; (2,
    // F_SQUARER_GHOST) each ghost against f_squares(a, b, k), the sum of its
    // first k rows, where the sum for k + 1 is the one for k plus a row; and
    // F_SQUARE_LEMMA: f_squares(a, b, W) = a^2 + b^2.  (2) and the lemma read
    // the ghosts and the count only, no register of the datapath.
    reg  [F_PW-1:0] f_gr2, f_ge2;
    wire [5:0]      f_sk = square_count_q;
    wire [F_PW-1:0] f_row_xs = f_axs[f_sk] ? (f_axs << f_sk) : {F_PW{1'b0}};
    wire [F_PW-1:0] f_row_ys = f_ays[f_sk] ? (f_ays << f_sk) : {F_PW{1'b0}};
    wire [F_PW-1:0] f_row_xe = f_axe[f_sk] ? (f_axe << f_sk) : {F_PW{1'b0}};
    wire [F_PW-1:0] f_row_ye = f_aye[f_sk] ? (f_aye << f_sk) : {F_PW{1'b0}};
    always @(posedge clk)
        if (accept) begin
            f_gr2 <= {F_PW{1'b0}};
            f_ge2 <= {F_PW{1'b0}};
        end else if (squaring) begin
            f_gr2 <= f_gr2 + f_row_xs + f_row_ys;
            f_ge2 <= f_ge2 + f_row_xe + f_row_ye;
        end
    wire f_sq_live = f_past_valid && !rst && f_slot_valid;
`ifdef F_SQUARER_LINK
    // (1) at count k the register is {partial sum, |x| >> k}: the sum's low
    // k bits have entered the register's low half from the top as |x|
    // shifted out of its bottom; the sum is below 2^(W+k+1) (a (a mod 2^k)
    // < 2^W 2^k for each square), so it fits the register's 2W + 1 bits.
    // One invariant per count, with shifts by constants (tried first with a
    // ghost per square, so that the solver had to reassociate the adds: with
    // the count as the shift amount, unfinished at W = 16 after 15 minutes;
    // per count, after 7)
    genvar f_lk;
    generate
        for (f_lk = 0; f_lk < W; f_lk = f_lk + 1) begin : g_f_link
            localparam [F_PW-1:0] F_BOUND = {{(F_PW-1){1'b0}}, 1'b1} << (W + f_lk + 1);
            always @(*)
                if (f_sq_live && squaring && square_count_q == f_lk)
                    assert({3'b000, radius_square_q} == (f_axs >> f_lk) + (f_gr2 << (W - f_lk))
                           && {3'b000, end_square_q} == (f_axe >> f_lk) + (f_ge2 << (W - f_lk))
                           && multiplier_ys_bit_q == bit_at(abs_ys_q, f_lk)
                           && multiplier_ye_bit_q == bit_at(abs_ye_q, f_lk)
                           && f_gr2 < F_BOUND && f_ge2 < F_BOUND);
        end
    endgenerate
    always @(*)
        if (f_sq_live) begin
            if (validator_state_q == STATE_SUM) begin
                sq_sum: assert({3'b000, radius_square_q} == f_gr2
                               && {3'b000, end_square_q} == f_ge2);
            end
            if (f_summed) begin
                sq_taken: assert({3'b000, f_sum_r2_q} == f_gr2 && {3'b000, f_sum_e2_q} == f_ge2);
            end
        end
`endif
`ifdef F_SQUARER_GHOST
    // (2) each ghost is its partial sum: at count k the rows i < k, from SUM
    // on all W rows (the ghosts add nothing after the last squaring clock)
    genvar f_gk;
    generate
        for (f_gk = 0; f_gk <= W; f_gk = f_gk + 1) begin : g_f_ghost
            wire f_at = (f_gk == W) ? (validator_state_q > STATE_SQUARE)
                                    : (squaring && square_count_q == f_gk);
            always @(*)
                if (f_sq_live && f_at)
                    assert(f_gr2 == f_squares(f_axs, f_ays, f_gk)
                           && f_ge2 == f_squares(f_axe, f_aye, f_gk));
        end
    endgenerate
`endif
`endif
    // the start and end frames, as the README defines them
    wire [1:0]   f_start_quad = quadrant_of(f_slot_cw, f_slot_xs, f_slot_ys);
    wire [1:0]   f_end_quad   = quadrant_of(f_slot_cw, f_slot_xe, f_slot_ye);
    wire         f_start_ux   = (f_start_quad[0] == f_slot_cw);
    wire         f_end_ux     = (f_end_quad[0] == f_slot_cw);
    wire [W-1:0] f_pu  = f_start_ux ? magnitude(f_slot_xs) : magnitude(f_slot_ys);
    wire [W-1:0] f_pv  = f_start_ux ? magnitude(f_slot_ys) : magnitude(f_slot_xs);
    wire [W-1:0] f_pue = f_end_ux ? magnitude(f_slot_xe) : magnitude(f_slot_ye);
    wire [W-1:0] f_pve = f_end_ux ? magnitude(f_slot_ye) : magnitude(f_slot_xe);
    wire [DATA_W-1:0] f_pud = {2'b00, f_pu};
    wire [DATA_W-1:0] f_pvd = {2'b00, f_pv};
    always @(*)
        if (f_past_valid && !rst && f_slot_valid) begin
            i_cmd_cw:   assert(cmd_cw_q == f_slot_cw);
            i_cmd_xs:   assert(cmd_xs_q == f_slot_xs && cmd_ys_q == f_slot_ys);
            i_abs_s:    assert(abs_xs_q == magnitude(f_slot_xs)
                               && abs_ys_q == magnitude(f_slot_ys));
            i_abs_e:    assert(abs_xe_q == magnitude(f_slot_xe)
                               && abs_ye_q == magnitude(f_slot_ye));
            // the frames, from the accepting edge
            i_end_quad: assert(pend_end_quad_q == f_end_quad);
            i_quad:     assert(pend_quad_q == f_start_quad);
            i_u_is_x:   assert(start_u_is_x_q == f_start_ux && end_u_is_x_q == f_end_ux);
            i_uv:       assert(pend_u == f_pu && pend_v == f_pv);
            i_uve:      assert(pend_ue == f_pue && pend_ve == f_pve);
`ifdef F_CODES
            // in CHECK the squaring registers still hold the sums of SUM
            if (validator_state_q == STATE_CHECK) begin
                i_r2: assert(radius_square_q == f_sum_r2_q);
                i_e2: assert(end_square_q == f_sum_e2_q);
            end
`endif
            if (f_after6)
                i_tol:   assert({{(F_PW-W-1){1'b0}}, tolerance_q} == f_slot_tol);
            if (f_after0)
                i_zero:  assert(radius_zero_q == (f_slot_xs == {W{1'b0}}
                                                  && f_slot_ys == {W{1'b0}}));
`ifdef F_CODES
            if (validator_state_q >= STATE_DECIDE) begin
                i_too_big: assert(radius_too_big_q == (f_slot_r2 > F_R2_MAX));
                i_off:     assert((end_outside_q || end_inside_q)
                                  == (f_slot_e2 > f_slot_r2 + f_slot_tol
                                      || f_slot_r2 > f_slot_e2 + f_slot_tol));
            end
            if (validator_state_q >= STATE_INIT)
                a_pend_ok: assert(f_slot_err == 2'd0);
`endif
            // the pending slot's increments (F = 0 at the start point)
            if (f_after0) begin
                // computed by the load from the pending u, v
                i_l_d1:  assert(load_d1 == f_pvd - (f_pud << 1) + ONE_D);
                i_l_p3:  assert(load_d_add_a == ((f_pvd - f_pud) << 1) + FIVE_D);
                i_l_g3:  assert(load_f_add_a == ((f_pvd - f_pud) << 1) + TWO_D);
                i_l_q4:  assert(load_d2_add_b_cross == ZERO_D - f_pvd - (f_pvd << 1));
                i_l_d2:  assert(load_d2 == (f_pvd << 1) - f_pud + ONE_D);
                i_l_q1:  assert(load_d2_add_b == TWO_D - (f_pud << 1));
                i_l_q2:  assert(load_d2_add_c == (f_pvd << 1) + THREE_D);
                i_l_g1:  assert(load_f_add_b == ONE_D - (f_pud << 1));
            end
            if (f_after1)
                i_p_u1:  assert(pend_u_one_q == (f_pu == ONE_W));
            // the comparator's difference in the clock after each of its steps
            if (squaring && square_count_q == 6'd2)
                i_c_v_ve:  assert(compare_difference_q == {1'b0, f_pv} - {1'b0, f_pve});
            if (squaring && square_count_q == 6'd3)
                i_c_u_ue:  assert(compare_difference_q == {1'b0, f_pu} - {1'b0, f_pue});
            if (squaring && square_count_q == 6'd4)
                i_c_v_ue:  assert(compare_difference_q == {1'b0, f_pv} - {1'b0, f_pue});
            if (squaring && square_count_q == 6'd5)
                i_c_ve_ue: assert(compare_difference_q == {1'b0, f_pve} - {1'b0, f_pue});
            if (squaring && square_count_q == 6'd6)
                i_c_xs_ys: assert(compare_difference_q == {1'b0, magnitude(f_slot_xs)}
                                                          - {1'b0, magnitude(f_slot_ys)});
        end

    // ---- the run stage: increments, circle, frame ----
    wire [DATA_W-1:0] f_ud = {2'b00, u_q};
    wire [DATA_W-1:0] f_vd = {2'b00, v_q};
    wire [F_PW-1:0]   f_uw = {{(F_PW-W){1'b0}}, u_q};
    wire [F_PW-1:0]   f_vw = {{(F_PW-W){1'b0}}, v_q};
    wire [F_PW-1:0]   f_fw = {{(F_PW-DATA_W){f_q[DATA_W-1]}}, f_q};   // F, sign-extended
    // u^2 and v^2 (W x W -> 2W bits); F_SQUARES_FREE (the tasks range_sq_*):
    // free values constrained by lemmas (see the block F_LOAD_CIRCLE)
`ifdef F_SQUARES_FREE
    (* anyseq *) wire [2*W-1:0] f_u_sq;
    (* anyseq *) wire [2*W-1:0] f_v_sq;
`else
    wire [2*W-1:0]    f_u_sq = u_q * u_q;
    wire [2*W-1:0]    f_v_sq = v_q * v_q;
`endif
    wire [W-1:0]      f_xmag = u_is_x ? u_q : v_q;
    wire [W-1:0]      f_ymag = u_is_x ? v_q : u_q;
    // the run stage's registers hold the arc's point while it runs and in the
    // clock after its last move (the next arc is never loaded at that edge)
    reg f_last_d;
    always @(posedge clk)
        f_last_d <= !rst && last;
    // the increments against their formulas in u, v (modulo 2^(W+2), as the
    // datapath computes them); D1 = F - 2u + v + 1 and D2 = F - u + 2v + 1 in
    // the equivalent form D2 - D1 = u + v, D2 - F = -u + 2v + 1 (the direct
    // form's induction did not finish in 10 minutes, this one does)
    wire f_inc_d1 = (d2_q - d1_q == f_ud + f_vd);
    wire f_inc_d2 = (d2_q - f_q == (f_vd << 1) + ONE_D - f_ud);
    wire f_inc_p3 = (d_add_a_q == ((f_vd - f_ud) << 1) + FIVE_D);
    wire f_inc_q1 = (d2_add_b_q == TWO_D - (f_ud << 1));
    wire f_inc_q2 = (d2_add_c_q == (f_vd << 1) + THREE_D);
    wire f_inc_q4 = (d2_add_b_cross_q == ZERO_D - f_vd - (f_vd << 1));
    wire f_inc_g1 = (f_add_b_q == ONE_D - (f_ud << 1));
    wire f_inc_g3 = (f_add_a_q == ((f_vd - f_ud) << 1) + TWO_D);
    wire f_run_checked = f_past_valid && !rst && (run_q || f_last_d);
`ifndef F_PROTOCOL_ONLY
    always @(*)
        if (f_run_checked) begin
            i_cw:       assert(cw_q == f_run_cw);
            i_u_one:    assert(u_one_q == (u_q == ONE_W));
            // the point in its quadrant's frame
            i_px:       assert(point_x_q == (x_positive ? f_xmag : ~f_xmag + ONE_W));
            i_py:       assert(point_y_q == (y_positive ? f_ymag : ~f_ymag + ONE_W));
            // the increments
            a_d1:       `F_INC(f_inc_d1);
            a_d2:       `F_INC(f_inc_d2);
            a_p3:       `F_INC(f_inc_p3);
            a_q1:       `F_INC(f_inc_q1);
            a_q2:       `F_INC(f_inc_q2);
            a_q4:       `F_INC(f_inc_q4);
            a_g1:       `F_INC(f_inc_g1);
            a_g3:       `F_INC(f_inc_g3);
`ifndef F_RUN_CIRCLE
            // without F_RUN_CIRCLE the range of u and v, which follows from
            // the circle, is assumed (F_RUN_CIRCLE asserts it)
            f_uv_range: assume(u_q != {W{1'b0}} && u_q <= F_MAG_MAX && v_q <= F_MAG_MAX);
`ifdef F_RUN_BOUND
            // F's bound under the assumed range: linear in F, u, v, and kept
            // by every move (the move rule's D1, D2 signs bound F' on both
            // sides), so its induction needs no square
            a_f_low:    assert($signed(f_fw) >= -$signed(f_uw + f_vw));
            a_f_high:   assert($signed(f_fw) < $signed(f_uw + f_vw));
`endif
`else
            // F's bound and the range of u and v
            i_u_pos:    assert(u_q != {W{1'b0}});
            i_u_max:    assert(u_q <= F_MAG_MAX);
            i_v_max:    assert(v_q <= F_MAG_MAX);
`ifdef F_LOAD_CIRCLE
            // F on the circle's terms, R^2 taken as u^2 + v^2 of the load
            i_c_r2:     assert(f_load_r2 <= F_R2_MAX);
            a_c_circle: assert(f_fw == {4'b0000, f_u_sq} + {4'b0000, f_v_sq} - f_load_r2);
`endif
            a_f_low:    assert($signed(f_fw) >= -$signed(f_uw + f_vw));
            a_f_high:   assert($signed(f_fw) < $signed(f_uw + f_vw));
`endif
        end

`endif

`ifdef F_LOAD_CIRCLE
    // ---- the circle from the load (F_LOAD_CIRCLE, the task range_w8) ----
    // R^2 is taken as u^2 + v^2 of the loaded start point (the same sum of
    // squares as xs^2 + ys^2: u, v are |xs|, |ys| in some order), in 2W-bit
    // products, and the validator's range check R^2 <= (M-1)(M-2) and a
    // start off the centre (u >= 1) are ASSUMED at the load (codes_w8 proves
    // them there, a_load_ok and a_load_u, against the squarer's sums, which
    // squaring_k9_w8 and square_w8 prove to be xs^2 + ys^2); from them
    // F = u^2 + v^2 - R^2, the bound and the range 1 <= u <= M - 2,
    // v <= M - 2 are proven together.  With F_SQUARES_FREE (range_sq_*) the
    // squares are free values under lemmas true squares obey (block below).
    reg  [F_PW-1:0] f_load_r2;
`ifdef F_SQUARES_FREE
    (* anyseq *) wire [2*W-1:0] f_pend_u_sq;               // pend_u^2, pend_v^2 (lemmas)
    (* anyseq *) wire [2*W-1:0] f_pend_v_sq;
`else
    wire [2*W-1:0]  f_pend_u_sq = pend_u * pend_u;     // 2W bits (the context's)
    wire [2*W-1:0]  f_pend_v_sq = pend_v * pend_v;
`endif
    wire [F_PW-1:0] f_pend_r2 = {4'b0000, f_pend_u_sq} + {4'b0000, f_pend_v_sq};
    always @(posedge clk)
        if (load) f_load_r2 <= f_pend_r2;
    always @(*)
        if (f_past_valid && !rst && load)
            f_load_range: assume(f_pend_r2 <= F_R2_MAX && pend_u != {W{1'b0}});
`ifdef F_SQUARES_FREE
    // ---- the squares as free values (F_SQUARES_FREE, the tasks range_sq_*) ----
    // With bit-blasted multipliers the solver must find (u - 1)^2 = u^2 - 2u + 1
    // inside them, and the induction did not close above W = 8 (range_w10: 10
    // minutes).  Here u^2, v^2 (f_u_sq, f_v_sq), the squares of their
    // next-state values (f_u_sq_nx, f_v_sq_nx) and of the pending start
    // (f_pend_u_sq, f_pend_v_sq) are free values (anyseq) constrained ONLY by
    // the facts below, each true of the real squares (of W-bit values, exact
    // in 2W bits: x^2 <= (2^W - 1)^2 < 2^2W).  True squares satisfy them all,
    // so the proof covers the real design (an over-approximation: sound).
    (* anyseq *) wire [2*W-1:0] f_u_sq_nx;
    (* anyseq *) wire [2*W-1:0] f_v_sq_nx;
    wire [2*W-1:0] f_u2 = {{W{1'b0}}, u_q};               // u, v at 2W bits
    wire [2*W-1:0] f_v2 = {{W{1'b0}}, v_q};
    wire [2*W-1:0] f_one2 = {{(2*W-1){1'b0}}, 1'b1};
    wire           f_v_top = (v_q == {W{1'b1}});          // v + 1 would wrap
    // (M - 1)(M - 2) + M - 1 = (M - 1)^2 and the bound M - 1, at 2W bits
    localparam [2*W-1:0] F_M1 = {{(W+1){1'b0}}, {(W-1){1'b1}}};            // M - 1
    localparam [2*W-1:0] F_M1_SQ = {2'b00, {(W-2){1'b1}}, {(W-1){1'b0}}, 1'b1};
    // x^2 >= x (x^2 - x = x (x - 1) >= 0 for every integer x); x^2 + 1 >= 2x
    // ((x - 1)^2 >= 0; at 2W + 1 bits, no wrap: so u^2 - 2u + 1 does not wrap
    // either); and for x >= M - 1: x^2 >= (M - 1)^2 (squaring is increasing
    // on x >= 0); 0^2 = 0, 1^2 = 1 (a crossing leaves u = 1)
    function f_sq_facts;
        input [W-1:0]   f_x;
        input [2*W-1:0] f_x_sq;
        begin
            f_sq_facts = (f_x_sq >= {{W{1'b0}}, f_x})
                         && ({1'b0, f_x_sq} + 1'b1 >= {{W{1'b0}}, f_x, 1'b0})
                         && ({{W{1'b0}}, f_x} < F_M1 || f_x_sq >= F_M1_SQ)
                         && (f_x != {W{1'b0}} || f_x_sq == {(2*W){1'b0}})
                         && (f_x != ONE_W || f_x_sq == {{(2*W-1){1'b0}}, 1'b1});
        end
    endfunction
    // Each case below also names the next value it squares (f_u_claim,
    // f_v_claim), and f_claim_u / f_claim_v check those against the registers
    // a clock later (the tasks sqclaims_*, with every other assertion and
    // assumption removed: the claims hold in every state).  So a change of the
    // RTL's u_n, v_n or of the registers' load and advance that the lemmas do
    // not follow fails there, instead of leaving range_sq's proof unsound.
    reg [W-1:0] f_u_claim, f_v_claim;
    always @(*) begin
        f_u_claim = u_q;
        f_v_claim = v_q;
        // the next-state squares, by the register's next value (load first,
        // as in the RTL; u_q, v_q hold without load or advance):
        if (load) begin
            // u' = pend_u, v' = pend_v: their squares (the same values)
            f_u_claim = pend_u;
            f_v_claim = pend_v;
            f_sq_load_u: assume(f_u_sq_nx == f_pend_u_sq);
            f_sq_load_v: assume(f_v_sq_nx == f_pend_v_sq);
        end else if (!advance) begin
            // unchanged registers, unchanged squares
            f_sq_hold_u: assume(f_u_sq_nx == f_u_sq);
            f_sq_hold_v: assume(f_v_sq_nx == f_v_sq);
        end else if (crossing) begin
            // relabelling (u', v') = (v + move_a, 0): u'^2 = v^2 (move B) or
            // (v + 1)^2 = v^2 + 2v + 1 (move A, v + 1 < 2^W: no wrap in u_n);
            // v'^2 = 0^2 = 0
            f_u_claim = v_q + {{(W-1){1'b0}}, move_a};
            f_v_claim = {W{1'b0}};
            if (!move_a)
                f_sq_cross_b: assume(f_u_sq_nx == f_v_sq);
            else if (!f_v_top)
                f_sq_cross_a: assume(f_u_sq_nx == f_v_sq + (f_v2 << 1) + f_one2);
            f_sq_cross_v: assume(f_v_sq_nx == {(2*W){1'b0}});
        end else begin
            // u' = u - 1 (u >= 1: no wrap): (u - 1)^2 = u^2 - 2u + 1; else u' = u
            if (!u_down) begin
                f_sq_u_same: assume(f_u_sq_nx == f_u_sq);
            end else begin
                f_u_claim = u_q - ONE_W;
                if (u_q != {W{1'b0}})
                    f_sq_u_down: assume(f_u_sq_nx == f_u_sq - (f_u2 << 1) + f_one2);
            end
            // v' = v + 1 (v + 1 < 2^W): (v + 1)^2 = v^2 + 2v + 1; else v' = v
            if (!v_up) begin
                f_sq_v_same: assume(f_v_sq_nx == f_v_sq);
            end else begin
                f_v_claim = v_q + ONE_W;
                if (!f_v_top)
                    f_sq_v_up:   assume(f_v_sq_nx == f_v_sq + (f_v2 << 1) + f_one2);
            end
        end
        // monotonicity facts of each square of a register or of the slot
        f_sq_mono_u: assume(f_sq_facts(u_q, f_u_sq));
        f_sq_mono_v: assume(f_sq_facts(v_q, f_v_sq));
        f_sq_mono_pu: assume(f_sq_facts(pend_u, f_pend_u_sq));
        f_sq_mono_pv: assume(f_sq_facts(pend_v, f_pend_v_sq));
    end
    // congruence: the square of a register is the square of its next-state
    // value a clock before (the register is that value)
    always @(posedge clk)
        if (f_past_valid) begin
            f_sq_next_u: assume(f_u_sq == $past(f_u_sq_nx));
            f_sq_next_v: assume(f_v_sq == $past(f_v_sq_nx));
        end
    // the registers are the values the cases claimed a clock before
    reg [W-1:0] f_u_claim_q, f_v_claim_q;
    always @(posedge clk) begin
        f_u_claim_q <= f_u_claim;
        f_v_claim_q <= f_v_claim;
    end
    always @(*)
        if (f_past_valid) begin
            f_claim_u: assert(u_q == f_u_claim_q);
            f_claim_v: assert(v_q == f_v_claim_q);
        end
`endif
`ifdef F_INCREMENTS_PAST
    // The increment invariants are assumed at the clock before only: this task
    // proves "increments up to t - 1 => circle, bound and range up to t", and
    // prove_w8 proves "range up to t => increments up to t" (it assumes the
    // range), so by induction on t both hold on every clock.
    reg f_increments_held;
    always @(posedge clk)
        f_increments_held <= !f_run_checked || (f_inc_d1 && f_inc_d2 && f_inc_p3
                             && f_inc_q1 && f_inc_q2 && f_inc_q4 && f_inc_g1 && f_inc_g3);
    always @(*)
        f_inc_past: assume(f_increments_held);
`endif
`endif

`ifdef F_RUN_ENDS
    // ---- termination (F_RUN_ENDS, the task ends_w8) ----
    // Within a quadrant every move lowers u or raises v (or both), so the
    // moves made since the quadrant was entered (f_quadrant_moves) are at most
    // (u_entry - u) + (v - v_entry). An arc crosses into
    // the next quadrant at most four times before its last move: it is armed
    // from the load (it starts in another quadrant than its end, or before
    // the end in the end's quadrant) or from its first crossing, and an armed
    // arc stops on the move that would leave the end's quadrant. With the
    // range 1 <= u <= M - 2, v <= M - 2 (assumed, as in prove_w8; range_w8
    // proves it), a quadrant takes fewer than 2M = 2^W moves, so an arc fewer
    // than 5 * 2^W (a_ends, on f_moves).
    // With u, v <= R + 1/2 instead (the circle), the same count gives the
    // documented 5 (2 floor(R) + 2) + 1.
    reg  [2:0]      f_crossings;                // quadrant crossings since the load
    reg  [1:0]      f_first_quad;               // the quadrant at the load
    reg             f_load_armed;               // armed at the load
    reg  [W-1:0]    f_u_entry, f_v_entry;       // u, v where this quadrant was entered
    reg  [F_MW-1:0] f_quadrant_moves;
    always @(posedge clk) begin
        if (load) begin
            f_crossings      <= 3'd0;
            f_first_quad     <= pend_quad_q;
            f_load_armed     <= pend_armed_q;
            f_u_entry        <= pend_u;
            f_v_entry        <= pend_v;
            f_quadrant_moves <= {F_MW{1'b0}};
        end else if (advance) begin
            if (crossing) begin
                f_crossings      <= f_crossings + 3'd1;
                f_u_entry        <= u_n;
                f_v_entry        <= {W{1'b0}};
                f_quadrant_moves <= {F_MW{1'b0}};
            end else begin
                f_quadrant_moves <= f_quadrant_moves + 1'b1;
            end
        end
    end
    wire [1:0] f_turned = cw_q ? f_first_quad - f_crossings[1:0]
                               : f_first_quad + f_crossings[1:0];
    // crossings from the first quadrant to the end's, in the direction
    wire [1:0] f_to_end = cw_q ? f_first_quad - end_quad_q : end_quad_q - f_first_quad;
    wire [F_MW-1:0] f_made = ({{(F_MW-W){1'b0}}, f_u_entry} - {{(F_MW-W){1'b0}}, u_q})
                           + ({{(F_MW-W){1'b0}}, v_q} - {{(F_MW-W){1'b0}}, f_v_entry});
    always @(*)
        if (f_past_valid && !rst && f_slot_valid && f_after6)
            // a pending arc not armed starts in its end's quadrant
            i_e_pend:    assert(pend_armed_q || pend_quad_q == pend_end_quad_q);
    always @(*)
        if (f_past_valid && !rst && run_q) begin
            i_e_quad:    assert(quad_q == f_turned);
            i_e_armed:   assert(armed_q == (f_load_armed || f_crossings != 3'd0));
            i_e_first:   assert(f_load_armed || f_first_quad == end_quad_q);
            i_e_cross:   assert(f_load_armed ? (f_crossings <= {1'b0, f_to_end})
                                             : (f_crossings <= 3'd4));
            i_e_entry:   assert(u_q <= f_u_entry && v_q >= f_v_entry);
            i_e_range:   assert(f_u_entry <= F_MAG_MAX);
            i_e_inside:  assert(f_quadrant_moves <= f_made);
            i_e_count:   assert(f_moves <= ({{(F_MW-3){1'b0}}, f_crossings} << W)
                                           + f_quadrant_moves);
            a_ends:      assert(f_moves < ({{(F_MW-3){1'b0}}, 3'd5} << W));
        end
`ifdef F_ENDS_R
    // ---- termination within the documented bound in R (F_ENDS_R) ----
    // With the circle and the bound (range_w8 proves them; assumed here),
    // u^2 - u < R^2 + v - v^2 <= R^2 < (r + 1)^2 for r = floor(R), so u and
    // v stay at most r + 1.  A quadrant left by a crossing (from u = 1) takes
    // at most (u_entry - 1) + (v - v_entry) <= 2r + 1 moves and the crossing
    // one more; so an arc with at most four crossings makes at most
    // 4 (2r + 2) + 2r + 1 moves, within the documented 5 (2 floor(R) + 2) + 1.
    // r is taken at the load as any value with r^2 <= R^2 < (r + 1)^2 (that
    // is floor(R), the only such value).
    (* anyseq *) reg [W-1:0] f_any_root;
    reg  [W-1:0]    f_root;                     // floor(R) of the running arc
    wire [F_PW-1:0] f_any_root_w = {{(F_PW-W){1'b0}}, f_any_root};
    always @(*)
        if (f_past_valid && !rst && load)
            f_root_load: assume(f_any_root_w * f_any_root_w <= f_pend_r2
                                && f_pend_r2 < (f_any_root_w + 1'b1) * (f_any_root_w + 1'b1));
    always @(posedge clk)
        if (load) f_root <= f_any_root;
    wire [F_MW-1:0] f_root_m    = {{(F_MW-W){1'b0}}, f_root};
    wire [F_MW-1:0] f_per_cross = (f_root_m << 1) + 2'd2;                  // 2r + 2
    wire [F_MW-1:0] f_crossed   = f_per_cross * {{(F_MW-3){1'b0}}, f_crossings};
    wire [F_MW-1:0] f_documented = f_per_cross * 3'd5 + 1'b1;             // 5 (2r + 2) + 1
    always @(*)
        if (f_past_valid && !rst && run_q) begin
            i_r_root:    assert(f_load_r2 < (({{(F_PW-W){1'b0}}, f_root} + 1'b1)
                                             * ({{(F_PW-W){1'b0}}, f_root} + 1'b1)));
            i_r_u:       assert(u_q <= f_root + 1'b1 && v_q <= f_root + 1'b1);
            i_r_entry:   assert(f_u_entry <= f_root + 1'b1);
            i_r_count:   assert(f_moves <= f_crossed + f_quadrant_moves);
            a_ends_r:    assert(f_moves < f_documented);
        end
`endif
`endif

`ifdef F_STOP_RULE
    // ---- the end test is the documented rule (F_STOP_RULE, the task stop_w8) ----
    // README, "Termination contract": in E's quadrant E = (ue, ve) is given the
    // order (v, -u) if ve <= ue, else (-u, v); a point is past E when it is in
    // E's quadrant and not before E in that order; an armed arc stops after the
    // first move that reaches a point past E or leaves E's quadrant.  The run
    // stage decides this from look-ahead flags kept one clock ahead; here the
    // flags are tied to u, v and E (i_s_*), and the stop to the rule (a_stop).
    localparam [W:0] F_MAG_HALF = {2'b01, {(W-1){1'b0}}};   // 2^(W-1)
    wire [W:0] f_ue  = {1'b0, ue_q};                      // E in its quadrant's frame
    wire [W:0] f_ve  = {1'b0, ve_q};
    wire [W:0] f_u   = {1'b0, u_q};
    wire [W:0] f_v   = {1'b0, v_q};
    wire [W:0] f_un  = {1'b0, u_n};                        // the point after the move
    wire [W:0] f_vn  = {1'b0, v_n};
    wire       f_first = (f_ve <= f_ue);
    wire       f_past_n = (quad_n == end_quad_q)
        && (f_first ? (f_vn > f_ve || (f_vn == f_ve && f_un <= f_ue))
                    : (f_un < f_ue || (f_un == f_ue && f_vn >= f_ve)));
    wire       f_leaves = (quad_q == end_quad_q) && (quad_n != end_quad_q);
    // the pending slot's flags, against its u, v and E
    wire [W:0] f_pu_w = {1'b0, pend_u}, f_pv_w = {1'b0, pend_v};
    wire [W:0] f_pue_w = {1'b0, pend_ue}, f_pve_w = {1'b0, pend_ve};
    // (each flag from the clock after the comparator's step that sets it)
    always @(*)
        if (f_past_valid && !rst && f_slot_valid) begin
            if (f_after0)
                i_s_p_mag:   assert(f_pue_w <= F_MAG_HALF && f_pve_w <= F_MAG_HALF);
            if (f_after1)
                i_s_p_const: assert(pend_ve_zero_q == (f_pve_w == 0)
                                    && pend_ve_one_q == (f_pve_w == 1)
                                    && pend_ue_zero_q == (f_pue_w == 0)
                                    && pend_ue_one_q == (f_pue_w == 1));
            if (f_after2)
                i_s_p_v_ve:  assert(pend_v_gt_ve_q == (f_pv_w > f_pve_w)
                                    && pend_v_eq_ve_q == (f_pv_w == f_pve_w)
                                    && pend_v_plus1_eq_ve_q == (f_pv_w + 1'b1 == f_pve_w));
            if (f_after3)
                i_s_p_u_ue:  assert(pend_u_lt_ue_q == (f_pu_w < f_pue_w)
                                    && pend_u_eq_ue_q == (f_pu_w == f_pue_w)
                                    && pend_u_eq_ue_plus1_q == (f_pu_w == f_pue_w + 1'b1));
            if (f_after4)
                i_s_p_v_ue:  assert(pend_v_lt_ue_q == (f_pv_w < f_pue_w)
                                    && pend_v_eq_ue_q == (f_pv_w == f_pue_w)
                                    && pend_v_plus1_eq_ue_q == (f_pv_w + 1'b1 == f_pue_w));
            if (f_after5)
                i_s_p_first: assert(pend_first_octant_q == (f_pve_w <= f_pue_w));
        end
    always @(*)
        if (f_past_valid && !rst && run_q) begin
            // E's magnitudes are at most 2^(W-1)
            i_s_e:       assert(f_ue <= F_MAG_HALF && f_ve <= F_MAG_HALF);
            i_s_const:   assert(ve_zero_q == (f_ve == 0) && ve_one_q == (f_ve == 1)
                                && ue_zero_q == (f_ue == 0) && ue_one_q == (f_ue == 1)
                                && first_octant_q == f_first);
            i_s_v:       assert(v_gt_ve_q == (f_v > f_ve) && v_eq_ve_q == (f_v == f_ve)
                                && v_plus1_eq_ve_q == (f_v + 1'b1 == f_ve));
            i_s_u:       assert(u_lt_ue_q == (f_u < f_ue) && u_eq_ue_q == (f_u == f_ue)
                                && u_eq_ue_plus1_q == (f_u == f_ue + 1'b1));
            i_s_vu:      assert(v_lt_ue_q == (f_v < f_ue) && v_eq_ue_q == (f_v == f_ue)
                                && v_plus1_eq_ue_q == (f_v + 1'b1 == f_ue));
            if (advance)
                a_stop:  assert(last == (armed_q && (f_past_n || f_leaves)));
        end
`endif

`ifdef F_SQUARE_LEMMA
    // ---- the squares (F_SQUARE_LEMMA, the task square_w8) ----
    // After W clocks the shift-and-add partial sum of any two W-bit
    // magnitudes is the sum of their squares: the link from the linear sums
    // of F_CODES to R^2 = xs^2 + ys^2, |E|^2 = xe^2 + ye^2 and to range_w8's
    // u^2 + v^2.  A property of free constants, so a bounded check of its
    // first step proves it for every value (the rest of the monitor is idle
    // under rst there).
    (* anyconst *) reg [W-1:0] f_lemma_a, f_lemma_b;
    wire [F_PW-1:0] f_lemma_aw = {{(F_PW-W){1'b0}}, f_lemma_a};
    wire [F_PW-1:0] f_lemma_bw = {{(F_PW-W){1'b0}}, f_lemma_b};
    always @(*)
        a_squares: assert(f_squares(f_lemma_aw, f_lemma_bw, F_ALL)
                          == f_lemma_aw * f_lemma_aw + f_lemma_bw * f_lemma_bw);
`endif

    // ---- registered outputs: one step per axis per move, in its direction ----
    wire [W-1:0]    f_dx = x - f_px_d;
    wire [W-1:0]    f_dy = y - f_py_d;
    wire [F_PW-1:0] f_ax = f_wide(x), f_ay = f_wide(y);
    wire [F_PW-1:0] f_fo = {{(F_PW-DATA_W){f[DATA_W-1]}}, f};
    always @(posedge clk)
        if (f_past_valid && !$past(rst) && !rst) begin
            a_move:   assert(move == $past(advance));
            a_done:   assert(done == $past(last));
            a_reject: assert(reject == $past(rejecting));
`ifdef F_CODES
            if (reject) begin
                a_err_code: assert(err_code == $past(f_slot_err));
            end
`endif
            if (!move) begin
                a_no_step: assert(!step_x && !step_y);
            end
            if (move && !$past(load)) begin
                a_out_point: assert(x == point_x_q && y == point_y_q && f == f_q);
            end
            if (move) begin
                // each axis: +1 in dir, -1 against it, or still (no step)
                a_step_x: assert(step_x ? (f_dx == (dir_x ? ONE_W : {W{1'b1}}))
                                        : (f_dx == {W{1'b0}}));
                a_step_y: assert(step_y ? (f_dy == (dir_y ? ONE_W : {W{1'b1}}))
                                        : (f_dy == {W{1'b0}}));
                a_step_any: assert(step_x || step_y);
`ifdef F_OUT_BOUND
                a_out_low:    assert($signed(f_fo) >= -$signed(f_ax + f_ay));
                a_out_high:   assert($signed(f_fo) < $signed(f_ax + f_ay));
`endif
            end
            if (!step_x) begin
                a_dir_x_held: assert(dir_x == $past(dir_x));
            end
            if (!step_y) begin
                a_dir_y_held: assert(dir_y == $past(dir_y));
            end
        end

    // ---- reachability (sby task cover) ----
    always @(posedge clk)
        if (f_past_valid && !rst) begin
            c_done:         cover(done);
            c_reject_1:     cover(reject && err_code == 2'd1);
            c_reject_2:     cover(reject && err_code == 2'd2);
            c_reject_3:     cover(reject && err_code == 2'd3);
            c_quadrant:     cover(advance && crossing);
            // a full circle (start = end) ends back on its start
            c_full_circle:  cover(done && f_out_full && x == f_out_xs && y == f_out_ys);
        end
`endif

endmodule

`default_nettype wire
