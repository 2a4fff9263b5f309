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
// Outputs are registered.  In the clock after a move edge: move=1, step_x/y
// and dir_x/y (1 = positive) for that move, x/y/f = the point reached and its
// deviation F = x^2+y^2-R^2, done=1 if it was the arc's last move.  x/y/f
// also show the start point (F=0) when an arc is loaded into an idle run
// stage.  busy = an arc is running, pending or being validated.
//
// Parameters:
//   W   coordinate width in bits, 8..32 (signed coordinates).  The datapath
//       (D1, D2, F, increments) is W+2 bits wide.
//
// abort_now: at the next edge no move is made and the running, pending and
// validating arcs are dropped (no reject is reported for them); outputs x, y,
// f keep the last point; s_ready is low while abort_now is high.
//
// Reset: synchronous, active high, clears control state and outputs.
// ============================================================================
module halfpoint_arc #(
    parameter integer W = 32
) (
    input  wire                clk,
    input  wire                rst,
    input  wire                en,
    // command stream
    input  wire                s_valid,
    output wire                s_ready,
    input  wire                s_cw,
    input  wire [W-1:0]        s_xs,
    input  wire [W-1:0]        s_ys,
    input  wire [W-1:0]        s_xe,
    input  wire [W-1:0]        s_ye,
    // status and per-clock outputs
    output wire                busy,
    output reg                 move,
    output reg                 step_x,
    output reg                 step_y,
    output reg                 dir_x,
    output reg                 dir_y,
    output reg  [W-1:0]        x,
    output reg  [W-1:0]        y,
    output reg  [W+1:0]        f,
    output reg                 done,
    output reg                 reject,
    output reg  [1:0]          err_code,
    // sequencing (for the motion core; tie start_en high when used alone)
    input  wire                abort_now,      // drop the running, pending and validated arcs now
    input  wire                start_en,   // the pending arc may enter the run stage
    output wire                running,    // an arc is in the run stage
    output wire                loading,    // the pending arc enters the run stage at this edge
    output wire                ending,     // the running arc makes its last move at this edge
    output wire [1:0]          nx_step,    // next move (if en): steps X (bit 0) and Y (bit 1)
    output wire [1:0]          nx_dir,     //   and their directions, 1 = positive
    output wire                nx_diag     //   it is a diagonal move (A)
);

    // ------------------------------------------------------------------
    // Parameter check: an illegal width stops elaboration.
    // ------------------------------------------------------------------
    generate
        if (W < 8 || W > 32) begin : g_bad_width
            halfpoint_arc_illegal_parameter_W_must_be_8_to_32 u_bad ();
        end
    endgenerate

    localparam integer DW = W + 2;           // datapath width
    localparam integer PW = 2 * W;           // square width
    // small signed constants at datapath width
    localparam [DW-1:0] C0  = {DW{1'b0}};
    localparam [DW-1:0] K1  = {{(DW-4){1'b0}}, 4'd1};
    localparam [DW-1:0] K2  = {{(DW-4){1'b0}}, 4'd2};
    localparam [DW-1:0] K3  = {{(DW-4){1'b0}}, 4'd3};
    localparam [DW-1:0] K4  = {{(DW-4){1'b0}}, 4'd4};
    localparam [DW-1:0] K5  = {{(DW-4){1'b0}}, 4'd5};
    localparam [DW-1:0] K6  = {{(DW-4){1'b0}}, 4'd6};
    localparam [DW-1:0] K8  = {{(DW-4){1'b0}}, 4'd8};
    localparam [DW-1:0] KM1 = {DW{1'b1}};
    localparam [DW-1:0] KM3 = ~K2;
    localparam [W-1:0] ONE_W = {{(W-1){1'b0}}, 1'b1};
    localparam integer VLAST = W - 1;
    localparam [2:0] V_IDLE = 3'd0, V_SQ = 3'd1, V_SUM = 3'd2, V_CHK = 3'd3,
                     V_DEC = 3'd4, V_INIT = 3'd5, V_HOLD = 3'd6;
    // Largest accepted R^2: (M-1)(M-2) = M^2 - 3M + 2, M = 2^(W-1).
    localparam [PW+1:0] ONE = {{(PW+1){1'b0}}, 1'b1};
    localparam [PW+1:0] THREE = {{(PW){1'b0}}, 2'b11};
    localparam [PW+1:0] R2_MAX = (ONE << (2*W-2)) - (THREE << (W-1)) + (ONE << 1);

    // Quadrant (0..3 = I..IV) of a non-origin point for a direction; a point
    // on an axis belongs to the quadrant the motion enters.
    function [1:0] quad;
        input          cw;
        input [W-1:0]  px;
        input [W-1:0]  py;
        reg xn, yn, xz, yz;
        begin
            xn = px[W-1]; yn = py[W-1];
            xz = (px == {W{1'b0}}); yz = (py == {W{1'b0}});
            if (!cw) begin
                if (!xn && !xz && !yn)       quad = 2'd0;  // x>0, y>=0
                else if ((xn || xz) && !yn && !yz) quad = 2'd1;  // x<=0, y>0
                else if (xn && (yn || yz))   quad = 2'd2;  // x<0, y<=0
                else                         quad = 2'd3;  // x>=0, y<0
            end else begin
                if (!xn && !yn && !yz)       quad = 2'd0;  // x>=0, y>0
                else if (xn && !yn)          quad = 2'd1;  // x<0, y>=0
                else if ((xn || xz) && yn)   quad = 2'd2;  // x<=0, y<0
                else                         quad = 2'd3;  // x>0, y<=0
            end
        end
    endfunction

    // ------------------------------------------------------------------
    // Validator: capture, square by shift-and-add, check, prepare.
    // ------------------------------------------------------------------
    reg  [2:0]    vstate_q;
    reg  [5:0]    vcnt_q;
    reg           c_cw_q;
    reg  [W-1:0]  c_xs_q, c_ys_q, c_xe_q, c_ye_q;   // raw coordinates
    reg  [W-1:0]  a_xs_q, a_ys_q, a_xe_q, a_ye_q;   // magnitudes
    reg  [PW-1:0] sq_xs_q, sq_ys_q, sq_xe_q, sq_ye_q;
    reg  [PW:0]   s2_q, e2_q;                        // R^2 and |E|^2
    reg  signed [PW+1:0] fe_q, nfe_q;                // |E|^2 - R^2 and R^2 - |E|^2
    reg  [W:0]    tol_q;                             // 2 max(|xs|, |ys|)
    reg           zero_q, range_q;

    // pending command, in run-stage form
    reg  [1:0]    p_q_q, p_qe_q;
    reg  [W-1:0]  p_u_q, p_v_q, p_ue_q, p_ve_q;
    reg  [DW-1:0] p_d1_q, p_d2_q, p_p1_q, p_p2_q, p_p3_q, p_p4_q, p_p5_q;
    reg  [DW-1:0] p_q1_q, p_q2_q, p_q4_q, p_g1_q, p_g2_q, p_g3_q;
    reg  [W-1:0]  p_ue1_q, p_uem1_q, p_vem1_q;
    reg           p_armed_q, p_oct1_q, p_ve0_q;

    assign s_ready = (vstate_q == V_IDLE) && !abort_now;
    wire   accept  = s_valid && s_ready;

    function [W-1:0] mag;
        input [W-1:0] a;
        begin
            mag = a[W-1] ? (~a + {{(W-1){1'b0}}, 1'b1}) : a;
        end
    endfunction

    // one shift-and-add squaring step: P = {hi, lo}; hi += lo[0] ? a : 0
    function [PW-1:0] sq_step;
        input [PW-1:0] p;
        input [W-1:0]  a;
        reg   [W:0]    s;
        begin
            s = {1'b0, p[PW-1:W]} + (p[0] ? {1'b0, a} : {(W+1){1'b0}});
            sq_step = {s, p[W-1:1]};
        end
    endfunction

    // DEC-stage combinational checks and frames
    wire signed [PW+1:0] tol = $signed({{(PW-W+1){1'b0}}, tol_q});
    wire           end_off = (fe_q > tol) || (nfe_q > tol);
    wire [1:0]     dec_err = zero_q ? 2'd1 : range_q ? 2'd2 : end_off ? 2'd3 : 2'd0;
    wire [1:0]     dec_qs    = quad(c_cw_q, c_xs_q, c_ys_q);
    wire [1:0]     dec_qe    = quad(c_cw_q, c_xe_q, c_ye_q);
    wire           dec_uxs   = (dec_qs[0] == c_cw_q);
    wire           dec_uxe   = (dec_qe[0] == c_cw_q);

    // INIT-stage: armed flag from the progress order
    wire           init_oct1  = (p_ve_q <= p_ue_q);
    wire           init_before = init_oct1
                                     ? ((p_v_q < p_ve_q) || (p_v_q == p_ve_q && p_u_q > p_ue_q))
                                     : ((p_u_q > p_ue_q) || (p_u_q == p_ue_q && p_v_q < p_ve_q));
    wire [DW-1:0]  iu = {2'b00, p_u_q};
    wire [DW-1:0]  iv = {2'b00, p_v_q};

    // run-stage handshake with the pending slot (defined below)
    wire           load;

    always @(posedge clk) begin
        if (rst || abort_now) begin
            vstate_q <= V_IDLE;
            vcnt_q   <= 6'd0;
        end else begin
            case (vstate_q)
                V_IDLE: if (accept) begin
                    vstate_q <= V_SQ;
                    vcnt_q   <= 6'd0;
                end
                V_SQ: begin
                    vcnt_q <= vcnt_q + 6'd1;
                    if (vcnt_q == VLAST[5:0]) vstate_q <= V_SUM;
                end
                V_SUM:  vstate_q <= V_CHK;
                V_CHK:  vstate_q <= V_DEC;
                V_DEC:  vstate_q <= (dec_err != 2'd0) ? V_IDLE : V_INIT;
                V_INIT: vstate_q <= V_HOLD;
                V_HOLD: if (load) vstate_q <= V_IDLE;
                default: vstate_q <= V_IDLE;
            endcase
        end
    end

    // validator datapath (no reset needed: qualified by vstate_q)
    always @(posedge clk) begin
        if (accept) begin
            c_cw_q <= s_cw;
            c_xs_q <= s_xs; c_ys_q <= s_ys; c_xe_q <= s_xe; c_ye_q <= s_ye;
            a_xs_q <= mag(s_xs); a_ys_q <= mag(s_ys);
            a_xe_q <= mag(s_xe); a_ye_q <= mag(s_ye);
            sq_xs_q <= {{W{1'b0}}, mag(s_xs)};
            sq_ys_q <= {{W{1'b0}}, mag(s_ys)};
            sq_xe_q <= {{W{1'b0}}, mag(s_xe)};
            sq_ye_q <= {{W{1'b0}}, mag(s_ye)};
        end
        if (vstate_q == V_SQ) begin
            sq_xs_q <= sq_step(sq_xs_q, a_xs_q);
            sq_ys_q <= sq_step(sq_ys_q, a_ys_q);
            sq_xe_q <= sq_step(sq_xe_q, a_xe_q);
            sq_ye_q <= sq_step(sq_ye_q, a_ye_q);
        end
        if (vstate_q == V_SUM) begin
            s2_q <= {1'b0, sq_xs_q} + {1'b0, sq_ys_q};
            e2_q <= {1'b0, sq_xe_q} + {1'b0, sq_ye_q};
            tol_q <= {((a_xs_q > a_ys_q) ? a_xs_q : a_ys_q), 1'b0};
        end
        if (vstate_q == V_CHK) begin
            fe_q    <= $signed({1'b0, e2_q}) - $signed({1'b0, s2_q});
            nfe_q   <= $signed({1'b0, s2_q}) - $signed({1'b0, e2_q});
            zero_q  <= (s2_q == {(PW+1){1'b0}});
            range_q <= ({1'b0, s2_q} > R2_MAX);
        end
        if (vstate_q == V_DEC) begin
            p_q_q  <= dec_qs;
            p_qe_q <= dec_qe;
            p_u_q  <= dec_uxs ? a_xs_q : a_ys_q;
            p_v_q  <= dec_uxs ? a_ys_q : a_xs_q;
            p_ue_q <= dec_uxe ? a_xe_q : a_ye_q;
            p_ve_q <= dec_uxe ? a_ye_q : a_xe_q;
        end
        if (vstate_q == V_INIT) begin
            // F = 0 at the start point
            p_d1_q <= (iv - (iu << 1)) + K1;         // F - 2u + v + 1
            p_d2_q <= ((iv << 1) - iu) + K1;         // F - u + 2v + 1
            p_p1_q <= K3 - (iu << 1);                // dD1 after B
            p_p2_q <= (iv << 1) + K2;                // dD1 after C
            p_p3_q <= ((iv - iu) << 1) + K5;         // dD1, dD2 after A
            p_p4_q <= K1 - (iv + (iv << 1));         // dD1 after B crossing
            p_p5_q <= C0 - iv;                       // dD1 after A crossing
            p_q1_q <= K2 - (iu << 1);                // dD2 after B
            p_q2_q <= (iv << 1) + K3;                // dD2 after C
            p_q4_q <= C0 - (iv + (iv << 1));         // dD2 after B crossing
            p_g1_q <= K1 - (iu << 1);                // dF after B
            p_g2_q <= (iv << 1) + K1;                // dF after C
            p_g3_q <= ((iv - iu) << 1) + K2;         // dF after A
            p_oct1_q  <= init_oct1;
            p_armed_q <= !((p_q_q == p_qe_q) && !init_before);
            p_ue1_q   <= p_ue_q + ONE_W;
            p_uem1_q  <= p_ue_q - ONE_W;
            p_vem1_q  <= p_ve_q - ONE_W;
            p_ve0_q   <= (p_ve_q == {W{1'b0}});
        end
    end

    // ------------------------------------------------------------------
    // Run stage
    // ------------------------------------------------------------------
    reg           run_q, cw_q, armed_q, oct1_q, ve0_q;
    reg  [1:0]    q_q, qe_q;
    reg  [W-1:0]  u_q, v_q, ue1_q;
    reg  [W-1:0]  px_q, py_q;                        // current point
    reg  [DW-1:0] d1_q, d2_q, f_q;
    reg  [DW-1:0] p1_q, p2_q, p3_q, p4_q, p5_q, q1_q, q2_q, q4_q, g1_q, g2_q, g3_q;
    // end-point constants beyond ue + 1, ue - 1, ve - 1 (for the look-ahead)
    reg  [W-1:0]  ue2_q, uem2_q, vem2_q;
    reg           ve1_q, ue0_q, ueone_q;
    // comparison flags of the current (u, v) with the end point, kept one
    // clock ahead (look-ahead): each register equals the comparison its name
    // states for the current u_q, v_q, so that no comparator sits between
    // the decision and the end detection (see "end detection" below)
    reg           u_one_q;                           // u == 1
    reg           f_v_gt_ve, f_v_eq_ve, f_v1_eq_ve;  // v > ve, v == ve, !ve0 && v + 1 == ve
    reg           f_u_lt_ue, f_u_eq_ue, f_u_eq_ue1;  // u < ue, u == ue, u == ue + 1
    reg           f_v_lt_ue, f_v_eq_ue, f_v1_eq_ue;  // v < ue, v == ue, v + 1 == ue

    // decision: sign bits -> move
    wire mv_b  = !d1_q[DW-1];
    wire mv_a  = d1_q[DW-1] && !d2_q[DW-1];
    wire mv_c  = d1_q[DW-1] && d2_q[DW-1];
    wire dec_u = mv_b || mv_a;                       // u shrinks
    wire inc_v = mv_a || mv_c;                       // v grows
    wire xing = u_one_q && dec_u;                   // u reaches 0: next quadrant

    wire ce    = run_q && en && !abort_now;

    // increments of the crossing cases, from -(2v+2) = ~P2 + 1
    wire [DW-1:0] np2 = ~p2_q;

    // the loop: select one prepared increment, one add per register
    wire [DW-1:0] d1_inc = xing ? (mv_b ? p4_q : p5_q)
                                 : (mv_b ? p1_q : mv_a ? p3_q : p2_q);
    wire [DW-1:0] d2_inc = xing ? (mv_b ? q4_q : p5_q)
                                 : (mv_b ? q1_q : mv_a ? p3_q : q2_q);
    wire [DW-1:0] f_inc  = mv_b ? g1_q : mv_a ? g3_q : g2_q;

    // next increments: register + constant, or ~P2 + constant on a crossing
    // (u' = v or v + 1, v' = 0); see README for the derivation
    // registers whose term is -2u gain 2 on every move that lowers u
    wire [DW-1:0] du2 = dec_u ? K2 : C0;

    wire [DW-1:0] p1_n = xing ? (np2 + (mv_b ? K6 : K4)) : (p1_q + du2);
    wire [DW-1:0] p2_n = xing ? K2 : (p2_q + (inc_v ? K2 : C0));
    wire [DW-1:0] p3_n = xing ? (np2 + (mv_b ? K8 : K6))
                               : (p3_q + (mv_a ? K4 : K2));
    wire [DW-1:0] p4_n = xing ? K1 : (p4_q + (inc_v ? KM3 : C0));
    wire [DW-1:0] p5_n = xing ? C0    : (p5_q + (inc_v ? KM1 : C0));
    wire [DW-1:0] q1_n = xing ? (np2 + (mv_b ? K5 : K3)) : (q1_q + du2);
    wire [DW-1:0] q2_n = xing ? K3 : (q2_q + (inc_v ? K2 : C0));
    wire [DW-1:0] q4_n = xing ? C0    : (q4_q + (inc_v ? KM3 : C0));
    wire [DW-1:0] g1_n = xing ? (np2 + (mv_b ? K4 : K2)) : (g1_q + du2);
    wire [DW-1:0] g2_n = xing ? K1 : (g2_q + (inc_v ? K2 : C0));
    wire [DW-1:0] g3_n = xing ? (np2 + (mv_b ? K5 : K3))
                               : (g3_q + (mv_a ? K4 : K2));

    wire [W-1:0]  u_n  = xing ? (mv_a ? v_q + ONE_W : v_q) : (dec_u ? u_q - ONE_W : u_q);
    wire [W-1:0]  v_n  = xing ? {W{1'b0}} : (inc_v ? v_q + ONE_W : v_q);
    wire [1:0]    q_n  = xing ? (cw_q ? q_q - 2'd1 : q_q + 2'd1) : q_q;

    // physical steps: u steps toward the axis, v away from it
    wire ux    = (q_q[0] == cw_q);
    wire xpos  = (q_q == 2'd0) || (q_q == 2'd3);     // x >= 0 in this quadrant
    wire ypos  = !q_q[1];                            // y >= 0 in this quadrant
    wire stx   = ux ? dec_u : inc_v;
    wire sty   = ux ? inc_v : dec_u;
    wire dirx  = ux ? !xpos : xpos;                  // 1 = positive
    wire diry  = ux ? ypos : !ypos;
    wire [W-1:0] px_n = stx ? (dirx ? px_q + ONE_W : px_q - ONE_W) : px_q;
    wire [W-1:0] py_n = sty ? (diry ? py_q + ONE_W : py_q - ONE_W) : py_q;

    // end detection for the point after this move (progress order of E),
    // from the registered comparison flags
    wire v_gt_ve  = f_v_gt_ve;
    wire v_eq_ve  = f_v_eq_ve;
    wire v1_eq_ve = f_v1_eq_ve;
    wire v_ge_ve  = v_gt_ve || v_eq_ve;
    wire v1_ge_ve = v_ge_ve || v1_eq_ve;             // v + 1 >= ve
    wire u_lt_ue  = f_u_lt_ue;
    wire u_eq_ue  = f_u_eq_ue;
    wire u_eq_ue1 = f_u_eq_ue1;
    wire u_le_ue  = u_lt_ue || u_eq_ue;
    wire u_le_ue1 = u_le_ue || u_eq_ue1;
    wire v_lt_ue  = f_v_lt_ue;
    wire v_eq_ue  = f_v_eq_ue;
    wire v1_eq_ue = f_v1_eq_ue;                      // v + 1 == ue

    // look-ahead: the flags for the point after this move, from the flags of
    // this point, the move, and equality tests of this point with constants
    // (they end at the flag registers, not in the enable path)
    wire c_v_eq_vem2 = (v_q == vem2_q);              // v + 2 == ve
    wire c_v_eq_uem2 = (v_q == uem2_q);              // v + 2 == ue
    wire c_u_eq_ue2  = (u_q == ue2_q);               // u == ue + 2
    wire c_v_eq_ue1  = (v_q == ue1_q);               // v == ue + 1
    wire c_u_eq_2    = (u_q == {{(W-2){1'b0}}, 2'd2});
    wire c_v_eq_1    = (v_q == ONE_W);
    wire c_v_eq_0    = (v_q == {W{1'b0}});
    // on a crossing u' = v + (A ? 1 : 0) and v' = 0
    wire n_v_gt_ve  = xing ? 1'b0    : inc_v ? (v_gt_ve || v_eq_ve) : v_gt_ve;
    wire n_v_eq_ve  = xing ? ve0_q   : inc_v ? v1_eq_ve : v_eq_ve;
    wire n_v1_eq_ve = xing ? ve1_q   : inc_v ? (!ve0_q && c_v_eq_vem2) : v1_eq_ve;
    wire n_u_lt_ue  = xing ? (mv_a ? (v_lt_ue && !v1_eq_ue) : v_lt_ue)
                           : dec_u ? (u_lt_ue || u_eq_ue) : u_lt_ue;
    wire n_u_eq_ue  = xing ? (mv_a ? v1_eq_ue : v_eq_ue)
                           : dec_u ? u_eq_ue1 : u_eq_ue;
    wire n_u_eq_ue1 = xing ? (mv_a ? v_eq_ue : c_v_eq_ue1)
                           : dec_u ? c_u_eq_ue2 : u_eq_ue1;
    wire n_v_lt_ue  = xing ? !ue0_q  : inc_v ? (v_lt_ue && !v1_eq_ue) : v_lt_ue;
    wire n_v_eq_ue  = xing ? ue0_q   : inc_v ? v1_eq_ue : v_eq_ue;
    wire n_v1_eq_ue = xing ? ueone_q : inc_v ? c_v_eq_uem2 : v1_eq_ue;
    wire n_u_one    = xing ? (mv_a ? c_v_eq_0 : c_v_eq_1)
                           : dec_u ? c_u_eq_2 : u_one_q;

    reg  past_same;   // next point (same quadrant) is at or past E
    always @(*) begin
        if (oct1_q) begin   // order (v, -u)
            if (mv_b)      past_same = v_gt_ve || (v_eq_ve && u_le_ue1);
            else if (mv_c) past_same = v_ge_ve || (v1_eq_ve && u_le_ue);
            else           past_same = v_ge_ve || (v1_eq_ve && u_le_ue1);
        end else begin      // order (-u, v)
            if (mv_b)      past_same = u_le_ue || (u_eq_ue1 && v_ge_ve);
            else if (mv_c) past_same = u_lt_ue || (u_eq_ue && v1_ge_ve);
            else           past_same = u_le_ue || (u_eq_ue1 && v1_ge_ve);
        end
    end
    // entering E's quadrant at (u', 0) with u' = v (B) or v + 1 (A)
    wire past_entry = oct1_q ? (ve0_q && (mv_b ? (v_lt_ue || v_eq_ue) : v_lt_ue))
                             : (mv_b ? v_lt_ue : (v_lt_ue && !v1_eq_ue));
    wire stop = armed_q && (((q_q == qe_q) && (xing || past_same)) ||
                            (xing && (q_n == qe_q) && past_entry));
    wire last = ce && stop;

    assign load = (vstate_q == V_HOLD) && start_en && !abort_now && (!run_q || last);

    assign running = run_q;
    assign loading = load;
    assign ending  = last;
    assign nx_step = {sty, stx};
    assign nx_dir  = {diry, dirx};
    assign nx_diag = mv_a;
    assign busy = run_q || (vstate_q != V_IDLE);

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
            cw_q <= c_cw_q;  q_q <= p_q_q;  qe_q <= p_qe_q;
            u_q  <= p_u_q;   v_q <= p_v_q;
            ue1_q <= p_ue1_q; ve0_q <= p_ve0_q;
            oct1_q <= p_oct1_q; armed_q <= p_armed_q;
            ue2_q  <= p_ue1_q + ONE_W;  uem2_q <= p_uem1_q - ONE_W;  vem2_q <= p_vem1_q - ONE_W;
            ve1_q  <= (p_ve_q == ONE_W);  ue0_q <= (p_ue_q == {W{1'b0}});
            ueone_q <= (p_ue_q == ONE_W);
            u_one_q    <= (p_u_q == ONE_W);
            f_v_gt_ve  <= (p_v_q > p_ve_q);
            f_v_eq_ve  <= (p_v_q == p_ve_q);
            f_v1_eq_ve <= !p_ve0_q && (p_v_q == p_vem1_q);
            f_u_lt_ue  <= (p_u_q < p_ue_q);
            f_u_eq_ue  <= (p_u_q == p_ue_q);
            f_u_eq_ue1 <= (p_u_q == p_ue1_q);
            f_v_lt_ue  <= (p_v_q < p_ue_q);
            f_v_eq_ue  <= (p_v_q == p_ue_q);
            f_v1_eq_ue <= (p_v_q == p_uem1_q);
            px_q <= c_xs_q;  py_q <= c_ys_q;
            d1_q <= p_d1_q;  d2_q <= p_d2_q; f_q <= {DW{1'b0}};
            p1_q <= p_p1_q;  p2_q <= p_p2_q; p3_q <= p_p3_q;
            p4_q <= p_p4_q;  p5_q <= p_p5_q;
            q1_q <= p_q1_q;  q2_q <= p_q2_q; q4_q <= p_q4_q;
            g1_q <= p_g1_q;  g2_q <= p_g2_q; g3_q <= p_g3_q;
        end else if (ce) begin
            q_q <= q_n;  u_q <= u_n;  v_q <= v_n;
            armed_q <= armed_q || xing;
            u_one_q    <= n_u_one;
            f_v_gt_ve  <= n_v_gt_ve;  f_v_eq_ve <= n_v_eq_ve;  f_v1_eq_ve <= n_v1_eq_ve;
            f_u_lt_ue  <= n_u_lt_ue;  f_u_eq_ue <= n_u_eq_ue;  f_u_eq_ue1 <= n_u_eq_ue1;
            f_v_lt_ue  <= n_v_lt_ue;  f_v_eq_ue <= n_v_eq_ue;  f_v1_eq_ue <= n_v1_eq_ue;
            px_q <= px_n; py_q <= py_n;
            d1_q <= d1_q + d1_inc;
            d2_q <= d2_q + d2_inc;
            f_q  <= f_q + f_inc;
            p1_q <= p1_n; p2_q <= p2_n; p3_q <= p3_n; p4_q <= p4_n; p5_q <= p5_n;
            q1_q <= q1_n; q2_q <= q2_n; q4_q <= q4_n;
            g1_q <= g1_n; g2_q <= g2_n; g3_q <= g3_n;
        end
    end

    // ------------------------------------------------------------------
    // Registered outputs
    // ------------------------------------------------------------------
    always @(posedge clk) begin
        if (rst) begin
            move <= 1'b0; step_x <= 1'b0; step_y <= 1'b0;
            dir_x <= 1'b0; dir_y <= 1'b0;
            x <= {W{1'b0}}; y <= {W{1'b0}}; f <= {DW{1'b0}};
            done <= 1'b0; reject <= 1'b0; err_code <= 2'd0;
        end else begin
            move   <= ce;
            step_x <= ce && stx;
            step_y <= ce && sty;
            if (ce && stx) dir_x <= dirx;
            if (ce && sty) dir_y <= diry;
            if (ce) begin
                x <= px_n; y <= py_n; f <= f_q + f_inc;
            end else if (load) begin
                x <= c_xs_q; y <= c_ys_q; f <= {DW{1'b0}};
            end
            done   <= last;
            reject <= (vstate_q == V_DEC) && (dec_err != 2'd0) && !abort_now;
            if ((vstate_q == V_DEC) && (dec_err != 2'd0) && !abort_now) err_code <= dec_err;
        end
    end

endmodule

`default_nettype wire
