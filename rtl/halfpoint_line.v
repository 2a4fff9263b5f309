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
// Parameters:
//   NA  number of axes, 1..6
//   W   delta width in bits, 8..32 (signed deltas); the datapath is W+2 bits
//
// abort_now: at the next edge no move is made and the running, pending and
// validating segments are dropped (no reject for them); s_ready is low while
// abort_now is high.
//
// Reset: synchronous, active high, clears control state and outputs.
// ============================================================================
module halfpoint_line #(
    parameter integer NA = 3,
    parameter integer W  = 32
) (
    input  wire               clk,
    input  wire               rst,
    input  wire               en,
    input  wire               s_valid,
    output wire               s_ready,
    input  wire [NA*W-1:0]    s_delta,
    output wire               busy,
    output reg                move,
    output reg  [NA-1:0]      step,
    output reg  [NA-1:0]      dir,
    output reg                done,
    output reg                reject,
    output reg  [1:0]         err_code,
    // sequencing (for the motion core; tie start_en high when used alone)
    input  wire               abort_now,  // drop the running, pending and validated segments
    input  wire               start_en,   // the pending segment may enter the run stage
    output wire               running,    // a segment is in the run stage
    output wire               loading,    // the pending segment enters the run stage at this edge
    output wire               ending,     // the running segment makes its last move at this edge
    output wire [NA-1:0]      nx_step,    // next move (if en): axes that step
    output wire [NA-1:0]      nx_dir      //   and their directions, 1 = positive
);

    generate
        if (NA < 1 || NA > 6) begin : g_bad_na
            halfpoint_line_illegal_parameter_NA_must_be_1_to_6 u_bad ();
        end
        if (W < 8 || W > 32) begin : g_bad_w
            halfpoint_line_illegal_parameter_W_must_be_8_to_32 u_bad ();
        end
    endgenerate

    localparam integer DW = W + 2;
    localparam [1:0] L_IDLE = 2'd0, L_MAX = 2'd1, L_INIT = 2'd2, L_HOLD = 2'd3;
    localparam integer NLAST = NA - 1;
    localparam [W-1:0] ONE_W = {{(W-1){1'b0}}, 1'b1};
    localparam [DW-1:0] ONE_D = {{(DW-1){1'b0}}, 1'b1};

    reg  [1:0]      vstate_q;
    reg  [2:0]      vcnt_q;
    reg  [NA*W-1:0] c_mag_q;          // |d_i|
    reg  [NA-1:0]   c_neg_q;          // d_i < 0
    reg  [W-1:0]    max_q;            // running maximum of |d_i|
    reg  [NA*DW-1:0] p_e_q, p_ks_q, p_kn_q;
    reg  [W-1:0]    p_cnt_q;

    assign s_ready = (vstate_q == L_IDLE) && !abort_now;
    wire   accept  = s_valid && s_ready;
    wire   empty   = (max_q == {W{1'b0}});
    wire   load;

    wire [W-1:0] mag_sel = c_mag_q[vcnt_q*W +: W];

    always @(posedge clk) begin
        if (rst || abort_now) begin
            vstate_q <= L_IDLE;
        end else begin
            case (vstate_q)
                L_IDLE: if (accept) vstate_q <= L_MAX;
                L_MAX:  if (vcnt_q == NLAST[2:0]) vstate_q <= L_INIT;
                L_INIT: vstate_q <= empty ? L_IDLE : L_HOLD;
                L_HOLD: if (load) vstate_q <= L_IDLE;
                default: vstate_q <= L_IDLE;
            endcase
        end
    end

    always @(posedge clk) begin
        if (accept) begin
            vcnt_q <= 3'd0;
            max_q  <= {W{1'b0}};
        end
        if (vstate_q == L_MAX) begin
            vcnt_q <= vcnt_q + 3'd1;
            if (mag_sel > max_q) max_q <= mag_sel;
        end
        if (vstate_q == L_INIT) p_cnt_q <= max_q;
    end

    genvar i;
    generate
        for (i = 0; i < NA; i = i + 1) begin : g_in
            wire [W-1:0]  d_in = s_delta[i*W +: W];
            wire [DW-1:0] m2   = {1'b0, c_mag_q[i*W +: W], 1'b0};     // 2|d_i|
            wire [DW-1:0] mx   = {2'b00, max_q};
            always @(posedge clk) begin
                if (accept) begin
                    c_neg_q[i] <= d_in[W-1];
                    c_mag_q[i*W +: W] <= d_in[W-1] ? (~d_in + ONE_W) : d_in;
                end
                if (vstate_q == L_INIT) begin
                    p_e_q[i*DW +: DW]  <= m2 - mx - ONE_D;     // E_0 (F = 0)
                    p_ks_q[i*DW +: DW] <= m2 - (mx << 1);       // after a step
                    p_kn_q[i*DW +: DW] <= m2;                   // no step
                end
            end
        end
    endgenerate

    // ------------------------------------------------------------------
    // Run stage
    // ------------------------------------------------------------------
    reg              run_q;
    reg  [W-1:0]     cnt_q;           // moves left
    reg  [NA-1:0]    neg_q;
    reg  [NA*DW-1:0] e_q, ks_q, kn_q;
    wire [NA-1:0]    stp;

    wire ce   = run_q && en && !abort_now;
    wire last = ce && (cnt_q == ONE_W);
    assign load = (vstate_q == L_HOLD) && start_en && !abort_now && (!run_q || last);

    assign running = run_q;
    assign loading = load;
    assign ending  = last;
    assign nx_step = stp;
    assign nx_dir  = ~neg_q;
    assign busy = run_q || (vstate_q != L_IDLE);

    generate
        for (i = 0; i < NA; i = i + 1) begin : g_axis
            wire [DW-1:0] e = e_q[i*DW +: DW];
            assign stp[i] = !e[DW-1];
            always @(posedge clk) begin
                if (load) begin
                    e_q[i*DW +: DW]  <= p_e_q[i*DW +: DW];
                    ks_q[i*DW +: DW] <= p_ks_q[i*DW +: DW];
                    kn_q[i*DW +: DW] <= p_kn_q[i*DW +: DW];
                end else if (ce) begin
                    e_q[i*DW +: DW] <= e + (stp[i] ? ks_q[i*DW +: DW] : kn_q[i*DW +: DW]);
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
            cnt_q <= p_cnt_q;
            neg_q <= c_neg_q;
        end else if (ce) begin
            cnt_q <= cnt_q - ONE_W;
        end
    end

    always @(posedge clk) begin
        if (rst) begin
            move <= 1'b0; step <= {NA{1'b0}}; dir <= {NA{1'b0}};
            done <= 1'b0; reject <= 1'b0; err_code <= 2'd0;
        end else begin
            move <= ce;
            step <= ce ? stp : {NA{1'b0}};
            if (ce) dir <= (dir & ~stp) | (~neg_q & stp);
            done <= last;
            reject <= (vstate_q == L_INIT) && empty && !abort_now;
            if ((vstate_q == L_INIT) && empty && !abort_now) err_code <= 2'd1;
        end
    end

endmodule

`default_nettype wire
