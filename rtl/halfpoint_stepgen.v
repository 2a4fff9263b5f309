// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// ============================================================================
// halfpoint_stepgen: one axis's STEP/DIR output with programmable timing
// ============================================================================
// Turns step requests into STEP/DIR pin activity that never violates the
// programmed timing (clock ticks, LinuxCNC / Mesa hostmot2 meanings):
//   steplen    STEP active for exactly max(steplen, 1) clocks per step
//   stepspace  STEP inactive for at least max(stepspace, 1) clocks between steps
//   dirsetup   DIR changes at least dirsetup clocks before STEP goes active
//   dirhold    DIR changes at least dirhold clocks after STEP went inactive
// and step_inv / dir_inv invert the pins (active-low drivers).
//
// Handshake: ready_pos / ready_neg say whether a request in that direction
// is taken at this clock edge (they depend only on registers: the
// comparisons of the inactive time with stepspace and dirhold are registered,
// made at each edge with that clock's settings).  The requester asserts req
// (with req_dir, 1 = positive) only when the matching ready is high and holds
// its interpolator back otherwise, so no step is dropped or merged.  A
// request in the same direction makes STEP active from the next clock; one in
// the other direction changes DIR at the next clock and makes STEP active
// dirsetup clocks later.
//
// Both pins are registers.  Settings may change at any time; they act from
// the next decision on (on readiness, one clock later).
//
// Parameters: see the comment above each (an illegal value stops
// elaboration).
//
// Reset: synchronous, active high: STEP inactive, DIR = negative (0), ready.
// ============================================================================
module halfpoint_stepgen #(
    // width of the timing settings in bits, 2..16
    parameter integer TW = 16
) (
    input  wire          clk,
    input  wire          rst,

    /*
     * Configuration: timing in clocks, pin polarity
     */
    input  wire [TW-1:0] cfg_steplen,
    input  wire [TW-1:0] cfg_stepspace,
    input  wire [TW-1:0] cfg_dirsetup,
    input  wire [TW-1:0] cfg_dirhold,
    input  wire          cfg_step_inv,
    input  wire          cfg_dir_inv,

    /*
     * Step requests (req_dir: 1 = positive) and readiness per direction
     */
    input  wire          req,
    input  wire          req_dir,
    output wire          ready_pos,
    output wire          ready_neg,

    /*
     * Status
     */
    // a step (or a direction change before it) is in progress
    output wire          busy,

    /*
     * STEP/DIR pins (registered)
     */
    output reg           step_pin,
    output reg           dir_pin
);

    generate
        if (TW < 2 || TW > 16) begin : g_bad_tw
            halfpoint_stepgen_illegal_parameter_TW_must_be_2_to_16 u_bad ();
        end
    endgenerate

    // states
    localparam [1:0] STATE_LOW   = 2'd0;    // STEP inactive; takes requests
    localparam [1:0] STATE_SETUP = 2'd1;    // DIR changed, waiting dirsetup clocks
    localparam [1:0] STATE_HIGH  = 2'd2;    // STEP active
    localparam [TW-1:0] ONE_T = {{(TW-1){1'b0}}, 1'b1};
    localparam [TW-1:0] MAX_T = {TW{1'b1}};

    reg  [1:0]    state_q;
    reg  [TW-1:0] count_q;        // clocks left in SETUP / HIGH
    reg  [TW-1:0] low_time_q;     // clocks STEP has been inactive (saturating)
    reg           dir_q;      // logical direction, 1 = positive

    wire [TW-1:0] step_length = (cfg_steplen == {TW{1'b0}}) ? ONE_T : cfg_steplen;
    wire          in_low      = (state_q == STATE_LOW);
    // low_time >= stepspace and low_time >= dirhold, registered: computed at each
    // edge for the new low_time, so no comparator sits in the ready path
    reg           space_ok_q, hold_ok_q;
    wire          ready_same = in_low && space_ok_q;
    wire          ready_flip = in_low && space_ok_q && hold_ok_q;
    assign ready_pos = dir_q  ? ready_same : ready_flip;
    assign ready_neg = !dir_q ? ready_same : ready_flip;
    assign busy      = !in_low;

    wire take = req && in_low && (req_dir ? ready_pos : ready_neg);
    wire flip = take && (req_dir != dir_q);

    // next state
    reg  [1:0]    state_n;
    reg  [TW-1:0] count_n, low_time_n;
    always @(*) begin
        state_n = state_q;
        count_n    = count_q;
        low_time_n = low_time_q;
        case (state_q)
            STATE_LOW: begin
                if (take) begin
                    if (flip && cfg_dirsetup != {TW{1'b0}}) begin
                        state_n = STATE_SETUP;
                        count_n = cfg_dirsetup;
                    end else begin
                        state_n = STATE_HIGH;
                        count_n = step_length;
                    end
                end else if (low_time_q != MAX_T) begin
                    low_time_n = low_time_q + ONE_T;
                end
            end
            STATE_SETUP: begin
                if (count_q <= ONE_T) begin
                    state_n = STATE_HIGH;
                    count_n = step_length;
                end else begin
                    count_n = count_q - ONE_T;
                end
            end
            default: begin   // STATE_HIGH
                if (count_q <= ONE_T) begin
                    state_n = STATE_LOW;
                    low_time_n = ONE_T;
                end else begin
                    count_n = count_q - ONE_T;
                end
            end
        endcase
    end
    wire dir_n = take ? req_dir : dir_q;

    always @(posedge clk) begin
        if (rst) begin
            state_q    <= STATE_LOW;
            count_q    <= {TW{1'b0}};
            low_time_q <= MAX_T;
            dir_q      <= 1'b0;
            space_ok_q <= 1'b1;       // low_time = max
            hold_ok_q  <= 1'b1;
            step_pin   <= cfg_step_inv;
            dir_pin    <= cfg_dir_inv;
        end else begin
            state_q    <= state_n;
            count_q    <= count_n;
            low_time_q <= low_time_n;
            dir_q      <= dir_n;
            space_ok_q <= (low_time_n >= cfg_stepspace);
            hold_ok_q  <= (low_time_n >= cfg_dirhold);
            // pins are registered copies of the next state, with polarity
            step_pin <= (state_n == STATE_HIGH) ^ cfg_step_inv;
            dir_pin  <= dir_n ^ cfg_dir_inv;
        end
    end

endmodule

`default_nettype wire
