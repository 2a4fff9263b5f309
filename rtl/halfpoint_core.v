// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// ============================================================================
// halfpoint_core: the motion core -- command stream, queue, sequencing of
// arcs and lines, feed rate, STEP/DIR outputs and absolute positions
// ============================================================================
// Commands arrive as single 256-bit beats on an AXI4-Stream slave (the
// encoding is defined in model/halfpoint/encoding.py and tabled in the
// README).  They wait in a queue of DEPTH entries; a dispatcher hands them in
// program order to the arc unit (XY plane, axes 0 and 1) or the line unit
// (all NA axes), with at most one command in flight (handed over, not yet
// started), so that a unit's pending segment starts at the edge of the
// previous segment's last move: no idle clock at a boundary when the next
// segment has been validated in time.
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
// Parameters:
//   NA     number of axes, 2..6 (arcs move axes 0 and 1)
//   W      coordinate and position width, 8..32
//   DEPTH  command queue depth, a power of two, 2..256
//   TW     width of the STEP/DIR timing settings, 2..16
//
// Reset: synchronous, active high.
// ============================================================================
module halfpoint_core #(
    parameter integer NA    = 3,
    parameter integer W     = 32,
    parameter integer DEPTH = 16,
    parameter integer TW    = 16
) (
    input  wire               clk,
    input  wire               rst,
    // command stream (AXI4-Stream slave, one command per beat)
    input  wire               s_axis_tvalid,
    output wire               s_axis_tready,
    input  wire [255:0]       s_axis_tdata,
    // STEP/DIR timing per axis (axis k in bits k*TW +: TW) and polarity
    input  wire [NA*TW-1:0]   cfg_steplen,
    input  wire [NA*TW-1:0]   cfg_stepspace,
    input  wire [NA*TW-1:0]   cfg_dirsetup,
    input  wire [NA*TW-1:0]   cfg_dirhold,
    input  wire [NA-1:0]      cfg_step_inv,
    input  wire [NA-1:0]      cfg_dir_inv,
    input  wire [7:0]         feed_override,   // percent, values above 200 act as 200
    input  wire               abort_now,           // stop now: no move, queue and pending segments dropped
    // outputs
    output wire [NA-1:0]      step_pin,
    output wire [NA-1:0]      dir_pin,
    output reg  [NA*W-1:0]    pos,             // absolute position per axis
    output reg                move,            // a move was made at the last edge
    output wire               busy,
    output wire [$clog2(DEPTH):0] queue_level,
    output reg                err,             // a command was rejected at the last edge
    output reg  [3:0]         err_code,        // code of the last rejected command
    output reg                underrun
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
    endgenerate

    localparam integer AW = $clog2(DEPTH);
    localparam [3:0] OP_LINE = 4'd1, OP_ARC_CW = 4'd2, OP_ARC_CCW = 4'd3;
    localparam [3:0] E_OPCODE = 4'd1, E_FIELD = 4'd2;
    localparam [34:0] COST_AXIS = 35'd16777216;     // 2^24
    localparam [34:0] COST_DIAG = 35'd23726566;     // round(sqrt(2) * 2^24)
    localparam [34:0] CREDIT_CAP = 35'd67108864;    // 2^26

    // ------------------------------------------------------------------
    // Decode at the queue's input
    // ------------------------------------------------------------------
    // Each command is checked and put in run form as it is pushed, so that
    // the queue head feeds the dispatcher and the units with no arithmetic
    // in between.  The checks are the same and their results are acted on
    // when the command reaches the head, exactly as if it were decoded there.
    wire [255:0] in_w = s_axis_tdata;
    wire [31:0]  iw0 = in_w[31:0];
    wire [3:0]   op = iw0[3:0];
    wire         in_cont = iw0[8];
    wire [31:0]  in_rate = in_w[63:32];
    wire         resv0 = (iw0[7:4] != 4'd0) || (iw0[31:9] != 23'd0);

    // does a 33-bit signed value fit W bits?
    function fits;
        input [32:0] v;
        reg   [32:0] top;
        begin
            top  = v >> (W - 1);
            fits = (top == 33'd0) || (top == ({33{1'b1}} >> (W - 1)));
        end
    endfunction
    function [32:0] sx33;
        input [31:0] v;
        begin
            sx33 = {v[31], v};
        end
    endfunction

    // line fields
    reg          l_fit, l_resv, l_zero;
    reg [NA*W-1:0] l_delta;
    integer k;
    always @(*) begin
        l_fit = 1'b1; l_resv = 1'b0; l_zero = 1'b1;
        l_delta = {NA*W{1'b0}};
        for (k = 0; k < 6; k = k + 1) begin
            if (k < NA) begin
                if (!fits(sx33(in_w[64+32*k +: 32]))) l_fit = 1'b0;
                if (in_w[64+32*k +: 32] != 32'd0) l_zero = 1'b0;
                l_delta[k*W +: W] = in_w[64+32*k +: W];
            end else if (in_w[64+32*k +: 32] != 32'd0) begin
                l_resv = 1'b1;
            end
        end
    end

    // arc fields: start and end relative to the centre
    wire [32:0] a_i  = sx33(in_w[95:64]);
    wire [32:0] a_j  = sx33(in_w[127:96]);
    wire [32:0] a_x  = sx33(in_w[159:128]);
    wire [32:0] a_y  = sx33(in_w[191:160]);
    wire [32:0] a_xs = 33'd0 - a_i;
    wire [32:0] a_ys = 33'd0 - a_j;
    wire [32:0] a_xe = a_x - a_i;
    wire [32:0] a_ye = a_y - a_j;
    wire        a_fit = fits(a_i) && fits(a_j) && fits(a_x) && fits(a_y) &&
                        fits(a_xs) && fits(a_ys) && fits(a_xe) && fits(a_ye);
    wire        a_resv = (in_w[255:192] != 64'd0);

    wire is_line = (op == OP_LINE);
    wire is_arc  = (op == OP_ARC_CW) || (op == OP_ARC_CCW);
    wire bad_op  = !(is_line || is_arc) || resv0 || (is_line && l_resv) || (is_arc && a_resv);
    wire bad_fit = !bad_op && ((is_line && !l_fit) || (is_arc && !a_fit));
    wire is_nop  = !bad_op && !bad_fit && is_line && l_zero;

    // queue entry: {payload, rate, flags}; payload = line deltas, or the arc's
    // start and end relative to the centre {ye, xe, ys, xs}
    localparam integer PLW = (NA * W > 4 * W) ? NA * W : 4 * W;
    localparam integer QW  = PLW + 40;
    wire [PLW-1:0] in_pl = is_arc ? {{(PLW-4*W){1'b0}}, a_ye[W-1:0], a_xe[W-1:0], a_ys[W-1:0], a_xs[W-1:0]}
                                  : {{(PLW-NA*W){1'b0}}, l_delta};
    wire [7:0]     in_fl = {1'b0, is_nop, bad_fit, bad_op, in_cont, is_line, op == OP_ARC_CW, is_arc};
    wire [QW-1:0]  in_entry = {in_pl, in_rate, in_fl};

    // ------------------------------------------------------------------
    // Queue
    // ------------------------------------------------------------------
    reg  [QW-1:0] mem [0:DEPTH-1];
    reg  [AW-1:0] wr_q, rd_q;
    reg  [AW:0]   count_q;
    wire          pop;
    wire          push = s_axis_tvalid && s_axis_tready;
    localparam [AW:0] FULL = {1'b1, {AW{1'b0}}};     // DEPTH
    localparam [AW-1:0] P1 = {{(AW-1){1'b0}}, 1'b1};
    localparam [AW:0] C1 = {{AW{1'b0}}, 1'b1};

    assign s_axis_tready = (count_q != FULL) && !abort_now;
    assign queue_level   = count_q;

    always @(posedge clk) begin
        if (push) mem[wr_q] <= in_entry;
    end
    always @(posedge clk) begin
        if (rst || abort_now) begin
            wr_q <= {AW{1'b0}}; rd_q <= {AW{1'b0}}; count_q <= {(AW+1){1'b0}};
        end else begin
            if (push) wr_q <= wr_q + P1;
            if (pop)  rd_q <= rd_q + P1;
            if (push && !pop) count_q <= count_q + C1;
            else if (pop && !push) count_q <= count_q - C1;
        end
    end

    // the queue head, decoded
    wire [QW-1:0]  head = mem[rd_q];
    wire           h_arc    = head[0];
    wire           h_cw     = head[1];
    wire           h_line   = head[2];
    wire           h_cont   = head[3];
    wire           h_bad_op = head[4];
    wire           h_bad_fit = head[5];
    wire           h_nop    = head[6];
    wire [31:0]    h_rate   = head[39:8];
    wire [PLW-1:0] h_pl     = head[QW-1:40];
    wire           unused_head = head[7];

    // ------------------------------------------------------------------
    // Dispatcher
    // ------------------------------------------------------------------
    reg         inflight_q;
    wire        head_ok = (count_q != {(AW+1){1'b0}}) && !inflight_q && !abort_now;
    wire        arc_s_valid  = head_ok && h_arc && !h_bad_op && !h_bad_fit;
    wire        line_s_valid = head_ok && h_line && !h_bad_op && !h_bad_fit && !h_nop;
    wire        arc_s_ready, line_s_ready;
    wire        arc_take  = arc_s_valid && arc_s_ready;
    wire        line_take = line_s_valid && line_s_ready;
    wire        disp_err  = head_ok && (h_bad_op || h_bad_fit);
    assign pop = disp_err || (head_ok && h_nop) || arc_take || line_take;

    // ------------------------------------------------------------------
    // Units
    // ------------------------------------------------------------------
    wire       arc_run, arc_loading, arc_ending, arc_nx_diag, arc_busy, arc_reject;
    wire [1:0] arc_nx_step, arc_nx_dir, arc_err;
    wire       line_run, line_loading, line_ending, line_busy, line_reject;
    wire [NA-1:0] line_nx_step, line_nx_dir;
    wire [1:0] line_err;
    wire       go;

    wire       unused_arc_move, unused_arc_sx, unused_arc_sy, unused_arc_dx, unused_arc_dy;
    wire       unused_arc_done, unused_line_move, unused_line_done;
    wire [W-1:0] unused_arc_x, unused_arc_y;
    wire [W+1:0] unused_arc_f;
    wire [NA-1:0] unused_line_step, unused_line_dir;

    halfpoint_arc #(.W(W)) u_arc (
        .clk(clk), .rst(rst), .en(go && arc_run),
        .s_valid(arc_s_valid), .s_ready(arc_s_ready), .s_cw(h_cw),
        .s_xs(h_pl[W-1:0]), .s_ys(h_pl[2*W-1:W]), .s_xe(h_pl[3*W-1:2*W]), .s_ye(h_pl[4*W-1:3*W]),
        .busy(arc_busy), .move(unused_arc_move), .step_x(unused_arc_sx), .step_y(unused_arc_sy),
        .dir_x(unused_arc_dx), .dir_y(unused_arc_dy), .x(unused_arc_x), .y(unused_arc_y),
        .f(unused_arc_f), .done(unused_arc_done), .reject(arc_reject), .err_code(arc_err),
        .abort_now(abort_now), .start_en(!line_run || line_ending), .running(arc_run), .loading(arc_loading),
        .ending(arc_ending), .nx_step(arc_nx_step), .nx_dir(arc_nx_dir), .nx_diag(arc_nx_diag)
    );

    halfpoint_line #(.NA(NA), .W(W)) u_line (
        .clk(clk), .rst(rst), .en(go && line_run),
        .s_valid(line_s_valid), .s_ready(line_s_ready), .s_delta(h_pl[NA*W-1:0]),
        .busy(line_busy), .move(unused_line_move), .step(unused_line_step), .dir(unused_line_dir),
        .done(unused_line_done), .reject(line_reject), .err_code(line_err),
        .abort_now(abort_now), .start_en(!arc_run || arc_ending), .running(line_run), .loading(line_loading),
        .ending(line_ending), .nx_step(line_nx_step), .nx_dir(line_nx_dir)
    );

    wire unused_ok = &{1'b0, unused_arc_move, unused_arc_sx, unused_arc_sy, unused_arc_dx,
                       unused_arc_dy, unused_arc_done, unused_line_move, unused_line_done,
                       unused_arc_x, unused_arc_y, unused_arc_f, unused_line_step,
                       unused_line_dir, line_err};

    // rate and CONT flag handed over with a command, and of the running segment
    reg [31:0] arc_rate_p, line_rate_p, arc_rate_a, line_rate_a;
    reg        arc_cont_p, line_cont_p, arc_cont_a, line_cont_a;

    always @(posedge clk) begin
        if (rst || abort_now) begin
            inflight_q <= 1'b0;
            arc_rate_a <= 32'd0; line_rate_a <= 32'd0;
            arc_cont_a <= 1'b0;  line_cont_a <= 1'b0;
        end else begin
            if (arc_take || line_take) inflight_q <= 1'b1;
            else if (arc_loading || line_loading || arc_reject || line_reject) inflight_q <= 1'b0;
            if (arc_loading)  begin arc_rate_a  <= arc_rate_p;  arc_cont_a  <= arc_cont_p;  end
            if (line_loading) begin line_rate_a <= line_rate_p; line_cont_a <= line_cont_p; end
        end
        if (arc_take)  begin arc_rate_p  <= h_rate; arc_cont_p  <= h_cont; end
        if (line_take) begin line_rate_p <= h_rate; line_cont_p <= h_cont; end
    end

    // ------------------------------------------------------------------
    // go: step/dir readiness and feed credit
    // ------------------------------------------------------------------
    wire [NA-1:0] nx_step = arc_run ? {{(NA-2){1'b0}}, arc_nx_step} : line_run ? line_nx_step : {NA{1'b0}};
    wire [NA-1:0] nx_dir  = arc_run ? {{(NA-2){1'b0}}, arc_nx_dir}  : line_nx_dir;
    wire [NA-1:0] rdy_pos, rdy_neg, sg_busy;
    wire          steps_ready = &(~nx_step | (nx_dir & rdy_pos) | (~nx_dir & rdy_neg));

    reg  [34:0]   credit_q;
    // override accumulator a (0..99, the model's ov_acc) kept as the two
    // thresholds 100 - a and 200 - a, so that k needs compares, not an add;
    // the override input is registered (ovr_q, clamped to 200) and k for the
    // next clock is computed a clock ahead (k_q = k(th, ovr_q)), so that the
    // credit adder starts from a register
    reg  [8:0]    th1_q, th2_q;
    reg  [7:0]    ovr_q;
    reg  [1:0]    k_q;
    wire          diag     = arc_run && arc_nx_diag;
    wire          ok_axis  = (credit_q >= COST_AXIS);
    wire          ok_diag  = (credit_q >= COST_DIAG);
    assign go = (arc_run || line_run) && steps_ready && (diag ? ok_diag : ok_axis) && !abort_now;

    wire [7:0]  ovr_n   = (feed_override > 8'd200) ? 8'd200 : feed_override;
    wire [8:0]  ov_back = (k_q == 2'd2) ? 9'd200 : (k_q == 2'd1) ? 9'd100 : 9'd0;
    wire [8:0]  th1_n   = th1_q - {1'b0, ovr_q} + ov_back;
    wire [8:0]  th2_n   = th2_q - {1'b0, ovr_q} + ov_back;
    // thresholds of the next clock: unchanged across an abort edge
    wire [8:0]  th1_x   = abort_now ? th1_q : th1_n;
    wire [8:0]  th2_x   = abort_now ? th2_q : th2_n;
    wire [1:0]  k_n     = ({1'b0, ovr_n} >= th2_x) ? 2'd2 : ({1'b0, ovr_n} >= th1_x) ? 2'd1 : 2'd0;
    wire [31:0] rate   = arc_run ? arc_rate_a : line_run ? line_rate_a : 32'd0;
    wire [34:0] inc    = (k_q == 2'd2) ? {2'b00, rate, 1'b0} : (k_q == 2'd1) ? {3'b000, rate} : 35'd0;
    // credit + inc - (go ? cost : 0), as two sums in parallel so that the
    // late `go` only selects: the cost is taken off the credit while the
    // override settles inc
    wire [34:0] credit_m = credit_q - (diag ? COST_DIAG : COST_AXIS);
    wire [34:0] sum_go   = credit_m + inc;
    wire [34:0] sum_hold = credit_q + inc;
    // x > CREDIT_CAP (= 2^26) for a non-negative x, as a LUT tree
    function over_cap;
        input [34:0] x;
        begin
            over_cap = (|x[34:27]) || (x[26] && (|x[25:0]));
        end
    endfunction
    wire [34:0] credit_n = go ? (over_cap(sum_go) ? CREDIT_CAP : sum_go)
                              : (over_cap(sum_hold) ? CREDIT_CAP : sum_hold);

    always @(posedge clk) begin
        if (rst) begin
            credit_q <= 35'd0;
            th1_q    <= 9'd100;
            th2_q    <= 9'd200;
            ovr_q    <= 8'd0;
            k_q      <= 2'd0;
        end else begin
            ovr_q <= ovr_n;
            k_q   <= k_n;
            if (abort_now) begin
                credit_q <= 35'd0;
            end else begin
                credit_q <= credit_n;
                th1_q    <= th1_n;
                th2_q    <= th2_n;
            end
        end
    end

    // ------------------------------------------------------------------
    // STEP/DIR generators and positions
    // ------------------------------------------------------------------
    genvar a;
    generate
        for (a = 0; a < NA; a = a + 1) begin : g_axis
            halfpoint_stepgen #(.TW(TW)) u_sg (
                .clk(clk), .rst(rst),
                .cfg_steplen(cfg_steplen[a*TW +: TW]), .cfg_stepspace(cfg_stepspace[a*TW +: TW]),
                .cfg_dirsetup(cfg_dirsetup[a*TW +: TW]), .cfg_dirhold(cfg_dirhold[a*TW +: TW]),
                .cfg_step_inv(cfg_step_inv[a]), .cfg_dir_inv(cfg_dir_inv[a]),
                .req(go && nx_step[a]), .req_dir(nx_dir[a]),
                .ready_pos(rdy_pos[a]), .ready_neg(rdy_neg[a]), .busy(sg_busy[a]),
                .step_pin(step_pin[a]), .dir_pin(dir_pin[a])
            );
            always @(posedge clk) begin
                if (rst) begin
                    pos[a*W +: W] <= {W{1'b0}};
                end else if (go && nx_step[a]) begin
                    pos[a*W +: W] <= nx_dir[a] ? pos[a*W +: W] + {{(W-1){1'b0}}, 1'b1}
                                               : pos[a*W +: W] - {{(W-1){1'b0}}, 1'b1};
                end
            end
        end
    endgenerate

    // ------------------------------------------------------------------
    // Status
    // ------------------------------------------------------------------
    assign busy = (count_q != {(AW+1){1'b0}}) || inflight_q || arc_busy || line_busy || (|sg_busy);

    wire       ending  = arc_ending || line_ending;
    wire       cont    = arc_run ? arc_cont_a : line_cont_a;
    wire [3:0] arc_code = {2'b00, arc_err} + 4'd2;     // 1, 2, 3 -> 3, 4, 5

    always @(posedge clk) begin
        if (rst) begin
            move <= 1'b0; err <= 1'b0; err_code <= 4'd0; underrun <= 1'b0;
        end else begin
            move <= go;
            err  <= !abort_now && (disp_err || arc_reject || line_reject);
            if (!abort_now) begin
                if (disp_err)         err_code <= h_bad_op ? E_OPCODE : E_FIELD;
                else if (arc_reject)  err_code <= arc_code;
                else if (line_reject) err_code <= E_OPCODE;
            end
            if (ending && cont && !arc_loading && !line_loading) underrun <= 1'b1;
        end
    end

endmodule

`default_nettype wire
