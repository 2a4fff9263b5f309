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
// Lookahead: direction, next_ready_same and next_ready_reverse give the
// readiness of the next clock for the present direction and for a reversal,
// if no request is taken at this edge (after a take neither is ready), so
// that a requester can register its decision a clock ahead.
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
    // readiness a clock ahead: ready_pos / ready_neg at the next clock are
    // (direction ? next_ready_same : next_ready_reverse) and the other one,
    // if no request is taken at this edge (after a take both are low)
    output wire          direction,
    output wire          next_ready_same,
    output wire          next_ready_reverse,

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
    localparam [TW:0]   TWO_P = {{(TW-1){1'b0}}, 2'd2};   // at the width of low_time_plus_q

    reg  [1:0]    state_q;
    reg  [TW-1:0] count_q;        // clocks left in SETUP / HIGH
    // the clocks STEP has been inactive (low_time, saturating at 2^TW - 1) plus 1, one bit
    // wider: 1 .. 2^TW, its top bit set exactly when low_time is saturated; the
    // compares read it as it is, and low_time itself is not kept
    reg  [TW:0]   low_time_plus_q;
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

    // Whether a request is taken, and the state after it, come from registers and
    // settings alone; the request (which the core's pop decides late in the
    // clock) meets them only in the last select of each next value
    wire take_ok = in_low && (req_dir ? ready_pos : ready_neg);
    wire take = req && take_ok;
    // a take that reverses DIR with a setup time waits in SETUP first
    wire          take_setup = (req_dir != dir_q) && (cfg_dirsetup != {TW{1'b0}});
    wire [1:0]    state_take = take_setup ? STATE_SETUP : STATE_HIGH;
    wire [TW-1:0] count_take = take_setup ? cfg_dirsetup : step_length;

    // next state without a take
    reg  [1:0]    state_idle;
    reg  [TW-1:0] count_idle;
    reg  [TW:0]   low_time_plus_n;
    always @(*) begin
        state_idle = state_q;
        count_idle = count_q;
        low_time_plus_n = low_time_plus_q;
        case (state_q)
            STATE_LOW: begin
                // low_time counts on a take too (it is not read until the
                // HIGH state's end sets it to 1), so that the readiness
                // compares do not wait for the take
                if (!low_time_plus_q[TW]) begin
                    low_time_plus_n = low_time_plus_q + {{TW{1'b0}}, 1'b1};
                end
            end
            STATE_SETUP: begin
                if (count_q <= ONE_T) begin
                    state_idle = STATE_HIGH;
                    count_idle = step_length;
                end else begin
                    count_idle = count_q - ONE_T;
                end
            end
            default: begin   // STATE_HIGH
                if (count_q <= ONE_T) begin
                    state_idle = STATE_LOW;
                    low_time_plus_n = TWO_P;            // low_time = 1
                end else begin
                    count_idle = count_q - ONE_T;
                end
            end
        endcase
    end
    wire [1:0]    state_n = take ? state_take : state_idle;
    wire [TW-1:0] count_n = take ? count_take : count_idle;
    wire          dir_n = take ? req_dir : dir_q;
    wire          step_n = take ? !take_setup : (state_idle == STATE_HIGH);

    // the next low_time >= stepspace and >= dirhold (registered below), each
    // compare from registers and settings, with the state selecting last: in
    // LOW the next low_time is low_time + 1 (saturating), so it reaches a
    // setting iff low_time + 1 does (low_time_plus_q, a register: the settings
    // meet one carry chain, no arithmetic of their own in front of it); at the
    // HIGH state's end it is 1.  space_ok_q and hold_ok_q are read only in LOW
    // (readiness is in_low and them), and LOW is entered only from the HIGH
    // state's end, which writes them, so in SETUP and in HIGH before its end
    // they take the LOW compares too, unread
    wire          space_counting = (low_time_plus_q >= {1'b0, cfg_stepspace});
    wire          hold_counting  = (low_time_plus_q >= {1'b0, cfg_dirhold});
    wire          space_at_one   = (cfg_stepspace[TW-1:1] == {(TW-1){1'b0}});
    wire          hold_at_one    = (cfg_dirhold[TW-1:1] == {(TW-1){1'b0}});
    wire          high_ends = !in_low && state_q != STATE_SETUP && count_q <= ONE_T;
    wire          space_ok_n = high_ends ? space_at_one : space_counting;
    wire          hold_ok_n  = high_ends ? hold_at_one : hold_counting;

    // readiness at the next clock without a take at this edge: LOW stays LOW,
    // HIGH ends on its last clock (low_time does not depend on the take)
    wire next_same = in_low ? space_counting : (high_ends && space_at_one);
    assign direction          = dir_q;
    assign next_ready_same    = next_same;
    assign next_ready_reverse = next_same && (in_low ? hold_counting : hold_at_one);

    always @(posedge clk) begin
        if (rst) begin
            state_q    <= STATE_LOW;
            count_q    <= {TW{1'b0}};
            low_time_plus_q <= {1'b1, {TW{1'b0}}};   // low_time = 2^TW - 1
            dir_q      <= 1'b0;
            space_ok_q <= 1'b1;       // low_time = max
            hold_ok_q  <= 1'b1;
            step_pin   <= cfg_step_inv;
            dir_pin    <= cfg_dir_inv;
        end else begin
            state_q    <= state_n;
            count_q    <= count_n;
            low_time_plus_q <= low_time_plus_n;
            dir_q      <= dir_n;
            space_ok_q <= space_ok_n;
            hold_ok_q  <= hold_ok_n;
            // pins are registered copies of the next state, with polarity
            step_pin <= step_n ^ cfg_step_inv;
            dir_pin  <= dir_n ^ cfg_dir_inv;
        end
    end

`ifdef FORMAL
    // ========================================================================
    // Formal properties (SymbiYosys: formal/halfpoint_stepgen.sby, run by
    // python -m halfpoint.flows.formal).  Verilator and the cocotb builds do
    // not define FORMAL, so they see the module above unchanged.
    // ========================================================================
    // A pin-level monitor in the manner of halfpoint.sim.timing watches the
    // STEP/DIR levels (pin XOR the inversion of the clock before, when the pin
    // was registered) and the handshake, and asserts:
    //   steplen    every STEP pulse lasts exactly max(steplen, 1) clocks;
    //   stepspace  STEP rises only after >= max(stepspace, 1) inactive clocks;
    //   dirsetup   STEP rises >= dirsetup clocks after the latest DIR change;
    //   dirhold    DIR changes >= dirhold clocks after STEP fell, never while
    //              STEP stays active;
    //   polarity   STEP pin at step_inv while idle, DIR pin = last taken
    //              direction XOR dir_inv;
    //   handshake  take = req && the ready of req_dir.  A take happens only
    //              while idle (nothing merged); each gives exactly one STEP
    //              rise, in its direction: on the edge after the take, or for
    //              a reversal at most dirsetup clocks after the DIR change
    //              the take makes on that edge (nothing dropped or late);
    //              a request while not ready is not taken: no rise, no DIR
    //              change (every rise and DIR change belongs to a take);
    //   readiness  exact: ready for the same direction iff idle and the
    //              inactive time reaches stepspace, for a reversal iff also
    //              dirhold (settings of the clock before): no needless wait;
    //   lookahead  ready_pos / ready_neg are what next_ready_same /
    //              next_ready_reverse announced the clock before (low after
    //              a take).
    // Labels: a_* the contract above, p_* its plain form, i_* invariants.
    // Settings are free inputs.  With F_STABLE_CFG (sby task "stable") they are
    // any constant values, and the four rules are asserted in the plain form
    // of halfpoint.sim.timing.  Without it (task "live") they change at will
    // on any clock, and each rule is asserted against the value the RTL
    // promises to use: steplen at the edge STEP went active; stepspace and
    // dirhold as of the clock before the take (registered readiness);
    // dirsetup at the take.  rst is free after the first clock (assumed
    // high there); a reset restarts the monitor, as a new checker would.
    // The internal invariants at the end tie the RTL state to the monitor so
    // that k-induction closes; F_CONTRACT_ONLY leaves them out (sby task
    // "contract", a bounded check of the contract alone).
    localparam [TW-1:0] MAX_T = {TW{1'b1}};   // the inactive time's saturation
    localparam [TW-1:0] F_ZERO = {TW{1'b0}};

    reg f_past_valid;
    initial f_past_valid = 1'b0;
    always @(posedge clk)
        f_past_valid <= 1'b1;
    always @(*)
        if (!f_past_valid)
            assume(rst);

    // the settings as of the previous clock
    reg [TW-1:0] f_steplen_q, f_stepspace_q, f_dirsetup_q, f_dirhold_q;
    reg          f_step_inv_q, f_dir_inv_q;
    always @(posedge clk) begin
        f_steplen_q   <= cfg_steplen;
        f_stepspace_q <= cfg_stepspace;
        f_dirsetup_q  <= cfg_dirsetup;
        f_dirhold_q   <= cfg_dirhold;
        f_step_inv_q  <= cfg_step_inv;
        f_dir_inv_q   <= cfg_dir_inv;
    end

`ifdef F_STABLE_CFG
    always @(posedge clk)
        if (f_past_valid) begin
            assume(cfg_steplen   == $past(cfg_steplen));
            assume(cfg_stepspace == $past(cfg_stepspace));
            assume(cfg_dirsetup  == $past(cfg_dirsetup));
            assume(cfg_dirhold   == $past(cfg_dirhold));
            assume(cfg_step_inv  == $past(cfg_step_inv));
            assume(cfg_dir_inv   == $past(cfg_dir_inv));
        end
`endif

    // ---- pin-level monitor -------------------------------------------------
    wire          f_step = step_pin ^ f_step_inv_q;     // STEP active
    wire          f_dir  = dir_pin ^ f_dir_inv_q;       // DIR, 1 = positive
    reg           f_step_d, f_dir_d;                    // the previous sample
    reg  [TW-1:0] f_hi;       // clocks STEP was active before this one (this pulse)
    reg  [TW-1:0] f_lo;       // clocks STEP was inactive before this one (sat.)
    reg  [TW-1:0] f_sd;       // clocks since the DIR change before this one (sat.)
    wire          f_rise = f_step && !f_step_d;
    wire          f_fall = !f_step && f_step_d;
    wire          f_dchg = (f_dir != f_dir_d);
    wire [TW-1:0] f_since_dir = f_dchg ? F_ZERO : f_sd;  // clocks since DIR changed
    wire [TW-1:0] f_lo_inc = (f_lo == MAX_T) ? MAX_T : f_lo + ONE_T;  // incl. this one

    // handshake
    wire          f_ready = req_dir ? ready_pos : ready_neg;
    wire          f_take  = req && f_ready;
    reg           f_owed;     // a taken request whose STEP has not risen yet
    reg           f_owed_dir;
    reg  [TW-1:0] f_wait;     // clocks since the edge that took it
    reg  [TW-1:0] f_owed_max; // clocks it may wait: dirsetup for a reversal, else 0
    reg           f_last_dir; // direction of the last taken request

    // the settings each rule is measured against (where the RTL samples them)
    reg  [TW-1:0] f_len_r, f_space_r, f_hold_r, f_setup_r;
    wire [TW-1:0] f_steplen_1 = (f_steplen_q == F_ZERO) ? ONE_T : f_steplen_q;
    wire [TW-1:0] f_len   = f_rise ? f_steplen_1 : f_len_r;     // this pulse
    wire [TW-1:0] f_setup = f_dchg ? f_dirsetup_q : f_setup_r;  // the latest reversal

    always @(posedge clk)
        if (rst) begin
            f_step_d   <= 1'b0;
            f_dir_d    <= 1'b0;
            f_hi       <= F_ZERO;
            f_lo       <= MAX_T;
            f_sd       <= MAX_T;
            f_owed     <= 1'b0;
            f_owed_dir <= 1'b0;
            f_wait     <= F_ZERO;
            f_owed_max <= F_ZERO;
            f_last_dir <= 1'b0;
            f_len_r    <= ONE_T;
            f_space_r  <= F_ZERO;
            f_hold_r   <= F_ZERO;
            f_setup_r  <= F_ZERO;
        end else begin
            f_step_d  <= f_step;
            f_dir_d   <= f_dir;
            f_hi      <= f_step ? f_hi + ONE_T : F_ZERO;
            f_lo      <= f_step ? F_ZERO : f_lo_inc;
            f_sd      <= f_dchg ? ONE_T : ((f_sd == MAX_T) ? MAX_T : f_sd + ONE_T);
            f_len_r   <= f_len;
            f_setup_r <= f_setup;
            if (f_take) begin
                f_owed     <= 1'b1;
                f_owed_dir <= req_dir;
                f_wait     <= F_ZERO;
                f_owed_max <= (req_dir != f_dir) ? cfg_dirsetup : F_ZERO;
                f_last_dir <= req_dir;
                f_space_r  <= f_stepspace_q;
                f_hold_r   <= f_dirhold_q;
            end else if (f_rise) begin
                f_owed     <= 1'b0;
            end else if (f_owed) begin
                f_wait     <= f_wait + ONE_T;
            end
        end

    // the lookahead: ready_pos / ready_neg as the clock before announced them
    // (none after a take; no promise across a reset)
    reg f_next_valid, f_next_pos, f_next_neg;
    always @(posedge clk) begin
        f_next_valid <= !rst;
        f_next_pos <= !f_take && (direction ? next_ready_same : next_ready_reverse);
        f_next_neg <= !f_take && (direction ? next_ready_reverse : next_ready_same);
    end

    // ---- the contract: pin rules and handshake ----------------------------
    always @(*)
        if (f_past_valid) begin
            // steplen: exactly max(steplen, 1) clocks (steplen at the rising edge)
            if (f_step)
                a_steplen_max: assert(f_hi < f_len);
            if (f_fall)
                a_steplen: assert(f_hi == f_len_r);
            // stepspace: inactive >= max(stepspace, 1) (stepspace before the take)
            if (f_rise)
                a_stepspace: assert(f_lo >= f_space_r && f_lo != F_ZERO);
            // dirsetup (dirsetup at the take that reversed DIR)
            if (f_rise)
                a_dirsetup: assert(f_since_dir >= f_setup);
            // dirhold (dirhold before the take), and never while STEP stays active
            if (f_dchg)
                a_dirhold: assert(f_lo >= f_hold_r);
            if (f_dchg)
                a_dir_stable: assert(!(f_step && f_step_d));
            // polarity
            if (!busy && !f_owed)
                a_step_polarity: assert(step_pin == f_step_inv_q);
            a_dir_polarity: assert(dir_pin == (f_last_dir ^ f_dir_inv_q));
            // handshake: a take only when idle (nothing merged), one STEP rise per
            // take in its direction (nothing spurious) within the wait it is
            // allowed (nothing dropped); DIR moves only for a take
            if (f_take)
                a_take_idle: assert(!busy && !f_owed && !f_step);
            if (f_rise)
                a_rise_taken: assert(f_owed && f_dir == f_owed_dir);
            if (f_owed)
                a_taken_rises: assert(f_wait <= f_owed_max);
            if (f_dchg)
                a_dir_taken: assert(f_owed && f_wait == F_ZERO && f_dir == f_owed_dir);
            a_busy_def: assert(busy == (f_owed || f_step));
            // readiness: exact, from the settings of the clock before
            a_ready_same: assert((f_last_dir ? ready_pos : ready_neg)
                               == (!busy && f_lo_inc >= f_stepspace_q));
            a_ready_rev: assert((f_last_dir ? ready_neg : ready_pos)
                              == (!busy && f_lo_inc >= f_stepspace_q
                                  && f_lo_inc >= f_dirhold_q));
            // lookahead: what the clock before announced
            if (f_next_valid)
                a_next_ready: assert(ready_pos == f_next_pos && ready_neg == f_next_neg);
        end

`ifdef F_STABLE_CFG
    // constant settings: the rules in the plain form of halfpoint.sim.timing
    wire [TW-1:0] f_cfg_len = (cfg_steplen != F_ZERO) ? cfg_steplen : ONE_T;
    always @(*)
        if (f_past_valid) begin
            if (f_fall)
                p_steplen: assert(f_hi == f_cfg_len);
            if (f_step)
                p_steplen_max: assert(f_hi < f_cfg_len);
            if (f_rise)
                p_stepspace: assert(f_lo >= cfg_stepspace && f_lo != F_ZERO);
            if (f_rise)
                p_dirsetup: assert(f_since_dir >= cfg_dirsetup);
            if (f_dchg)
                p_dirhold: assert(f_lo >= cfg_dirhold);
            if (!busy && !f_owed)
                p_step_polarity: assert(step_pin == cfg_step_inv);
            p_dir_polarity: assert(dir_pin == (f_last_dir ^ cfg_dir_inv));
        end
`endif

`ifndef F_CONTRACT_ONLY
    // ---- induction invariants: RTL state against the monitor ----------------
    // (left out by F_CONTRACT_ONLY, the bounded check of the contract alone;
    // sums one bit wider, so that no wrapped value satisfies them)
    wire [TW:0] f_hi_cnt    = {1'b0, f_hi} + {1'b0, count_q};
    wire [TW:0] f_wait_cnt  = {1'b0, f_wait} + {1'b0, count_q};
    wire [TW:0] f_since_cnt = {1'b0, f_since_dir} + {1'b0, count_q};
    // the inactive time the RTL keeps as low_time_plus_q (1 .. 2^TW, i_low_time_plus)
    wire [TW:0]   f_low_time_wide = low_time_plus_q - {{TW{1'b0}}, 1'b1};
    wire [TW-1:0] f_low_time = f_low_time_wide[TW-1:0];
    always @(*)
        if (f_past_valid) begin
            i_state: assert(state_q != 2'd3);
            i_step: assert(f_step == (state_q == STATE_HIGH));
            i_dir: assert(f_dir == dir_q);
            i_last_dir: assert(f_last_dir == dir_q);
            i_hi: assert(f_step_d == (f_hi != F_ZERO));
            i_lo: assert(f_step_d == (f_lo == F_ZERO));
            i_sd: assert(f_sd != F_ZERO);
            // space_ok_q and hold_ok_q are meaningful (and read) in LOW only
            if (state_q == STATE_LOW) begin
                i_space: assert(space_ok_q == (f_low_time >= f_stepspace_q));
                i_hold: assert(hold_ok_q == (f_low_time >= f_dirhold_q));
            end
            i_low_time_plus: assert(low_time_plus_q != {(TW+1){1'b0}}
                                    && (!low_time_plus_q[TW]
                                        || low_time_plus_q[TW-1:0] == {TW{1'b0}}));
            i_owed: assert(f_owed == (state_q == STATE_SETUP || f_rise));
            if (f_owed)
                i_owed_dir: assert(f_owed_dir == dir_q);
            if (state_q == STATE_LOW)
                i_low_time: assert(f_low_time == f_lo_inc);
            if (state_q == STATE_HIGH) begin
                i_high_count: assert(count_q != F_ZERO);
                i_high_len: assert(f_hi_cnt == {1'b0, f_len});
            end
            if (state_q == STATE_SETUP) begin
                i_setup_count: assert(count_q != F_ZERO);
                i_setup_wait: assert(f_wait_cnt == {1'b0, f_owed_max});
                i_setup_dir: assert(f_since_cnt == {1'b0, f_setup});
                i_setup_space: assert(f_lo >= f_space_r);
                i_setup_low: assert(!f_step_d);
            end else begin
                i_since_dir: assert(f_since_dir >= f_setup);
            end
            if (f_rise)
                i_rise_wait: assert(f_wait == f_owed_max);
`ifdef F_STABLE_CFG
            // the settings captured by the monitor are the constant settings
            if (f_step)
                i_len_cfg: assert(f_len == f_cfg_len);
            if (f_owed)
                i_space_cfg: assert(f_space_r == cfg_stepspace);
            if (f_owed)
                i_hold_cfg: assert(f_hold_r == cfg_dirhold);
            i_setup_cfg: assert(f_setup == cfg_dirsetup || f_since_dir == MAX_T);
`endif
        end
`endif

    // ---- cover: the interesting sequences are reachable -----------------------
    always @(*)
        if (f_past_valid && !rst) begin
            cover(f_fall && f_hi == 3);                 // a 3-clock pulse
            cover(f_rise && f_dchg);                    // reversal, dirsetup 0
            cover(f_rise && f_since_dir == 2 && f_lo == 3);   // reversal after setup
            cover(f_rise && f_lo == 1);                 // fastest rate
        end
`endif

endmodule

`default_nettype wire
