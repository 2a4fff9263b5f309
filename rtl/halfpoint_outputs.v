// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// ============================================================================
// halfpoint_outputs: spindle / laser / coolant output stage (issue 14 item 3)
// ============================================================================
// The pins of M3 / M4 / M5 (spindle enable and direction, a PWM output whose
// duty follows S) and M7 / M8 / M9 (coolant mist and flood), loaded in program
// order by the core, and the laser mode (grbl's $32): under M4 the duty follows
// the profile stage's path speed over the segment's cruise speed, so the power
// per length stays constant through accelerations and corners; at rest the
// laser is off.  The model halfpoint.spec.outputs.OutputStage is the
// specification (register names there without the _q); it documents the
// arithmetic and the schedule in full.
//
// load (pulse): the settings registers take load_* (a power above 65536 is
// taken as 65536).  off (level): every setting, the duty, pwm and the pending
// result are cleared at the edge; off wins over load.  take (pulse): the
// cruise register takes take_v_cruise and, with take_set_power, the power
// register take_power (a segment's PROFILE carrying it: laser power that
// changes with the motion, not at rest); a load at the same edge wins.
//
// PWM: a PWM_BITS-bit counter runs freely (period 2^PWM_BITS clocks).  The duty
// register (0..2^PWM_BITS) takes the unit's result at the wrap, so each period
// has one duty.  pwm is a register: during the clock with counter k + 1 it is
// spindle_enable && k < duty, high for exactly duty clocks per period.
//
// The unit (one 33-bit adder / subtractor, shifts, no multiplier), by the
// counter's value during the clock, P = PWM_BITS:
//   0         sample: speed, cruise and the settings; remainder = speed >> 6
//   1..P      non-restoring division: one bit of speed * 2^P / (cruise << 6)
//   P+1       clear the accumulator, addend = the power register (the base)
//   P+2..2P+1 shift-and-add: base * quotient, one quotient bit a clock
//   2^P-1     the duty register takes the effective duty (at the wrap)
// So the duty lags the speed and the settings by one to two PWM periods.
// The schedule's flags are decoded from the counter a clock early (registers).
// The adder's operands are one LUT level from registers and its sum goes
// straight into registers (the quotient's bits are taken from the sign a clock
// later; the sign is kept twice, halving its fanout), so its loop is the
// reference loop's: a sign-selected add / subtract, here 33 bits.
//
// Parameters: see the comment above each (an illegal value stops
// elaboration).
//
// Reset: synchronous, active high: every register cleared (the outputs low).
// ============================================================================
module halfpoint_outputs #(
    // PWM counter width in bits, 4..16: period 2^PWM_BITS clocks, duty 0..2^PWM_BITS
    parameter integer PWM_BITS = 10
) (
    input  wire                clk,
    input  wire                rst,

    /*
     * Settings, in program order (an OUTPUT command)
     */
    input  wire                load,
    // 0..65536 = 0..100 % (above 65536 acts as 65536)
    input  wire [16:0]         load_power,
    input  wire                load_enable,
    input  wire                load_reverse,
    input  wire                load_laser,
    input  wire                load_dynamic,
    input  wire                load_mist,
    input  wire                load_flood,
    // level: clear the settings and the duty (abort, stop at rest)
    input  wire                off,

    /*
     * From the profile stage
     */
    // path speed, BLU per clock x 2^38
    input  wire [37:0]         speed,
    // a new segment: its cruise speed, BLU per clock x 2^32
    input  wire                take,
    input  wire [31:0]         take_v_cruise,
    // with take: the power register takes take_power (as load_power; a load at
    // the same edge wins), the power the segment's PROFILE carries
    input  wire                take_set_power,
    input  wire [16:0]         take_power,

    /*
     * Pins (registered)
     */
    output wire                spindle_enable,
    output wire                spindle_reverse,
    output wire                coolant_mist,
    output wire                coolant_flood,
    output wire                pwm,

    /*
     * Status: this period's duty, 0..2^PWM_BITS clocks
     */
    output wire [PWM_BITS:0]   duty
);

    generate
        if (PWM_BITS < 4 || PWM_BITS > 16) begin : g_bad_pwm_bits
            halfpoint_outputs_illegal_parameter_PWM_BITS_must_be_4_to_16 u_bad ();
        end
    endgenerate

    localparam integer P = PWM_BITS;
    // the accumulator: remainder in [-cruise, cruise), then a product < 2^(2P+1) <= 2^33
    localparam integer ACCUMULATOR_BITS = 33;
    localparam [P-1:0] COUNTER_LAST = {P{1'b1}};
    localparam [P-1:0] COUNTER_ONE = {{(P-1){1'b0}}, 1'b1};
    // the operand's low bits take the sign from accumulator_q, the others from its copy
    localparam integer SIGN_SPLIT = ACCUMULATOR_BITS / 2;

    // ---- settings -------------------------------------------------------------
    reg          enable_q, reverse_q, laser_q, dynamic_q, mist_q, flood_q;
    // the power in 1/2^P of full: load_power >> (16 - P), 0..2^P
    reg  [P:0]   power_q;
    reg  [31:0]  cruise_q;

    // the power loaded at this edge: an OUTPUT's, else the taken segment's
    wire         take_power_now = take && take_set_power;
    wire [16:0]  new_power = load ? load_power : take_power;
    // a power of 65536 or more is full power; the bits below 2^(16-P) are dropped
    wire [P:0]   new_power_top = new_power[16] ? {1'b1, {P{1'b0}}}
                                               : {1'b0, new_power[15:16-P]};
    generate
        if (P < 16) begin : g_power_unused
            wire unused_power_low = ^new_power[15-P:0];
        end
    endgenerate
    // the enable setting after this edge (the pwm register's gate)
    wire         enable_next = off ? 1'b0 : (load ? load_enable : enable_q);

    always @(posedge clk) begin
        if (rst || off) begin
            enable_q  <= 1'b0;
            reverse_q <= 1'b0;
            laser_q   <= 1'b0;
            dynamic_q <= 1'b0;
            mist_q    <= 1'b0;
            flood_q   <= 1'b0;
            power_q   <= {(P+1){1'b0}};
        end else if (load) begin
            enable_q  <= load_enable;
            reverse_q <= load_reverse;
            laser_q   <= load_laser;
            dynamic_q <= load_dynamic;
            mist_q    <= load_mist;
            flood_q   <= load_flood;
            power_q   <= new_power_top;
        end else if (take_power_now) begin
            power_q   <= new_power_top;
        end
    end

    always @(posedge clk) begin
        if (rst) begin
            cruise_q <= 32'd0;
        end else if (take) begin
            cruise_q <= take_v_cruise;
        end
    end

    // ---- counter and the schedule ---------------------------------------------
    reg  [P-1:0] counter_q;
    reg          at_start_q, dividing_q, clearing_q, multiplying_q, at_end_q;
    // signs shifts: counter 2..2P (a clock after each division step, then the product's)
    reg          shifting_q;

    // the flags of the next clock, from this clock's counter (next = counter + 1)
    wire [31:0]  counter_wide = {{(32-P){1'b0}}, counter_q};
    wire         multiplying_next = (counter_wide >= P + 1) && (counter_wide <= 2 * P);

    always @(posedge clk) begin
        if (rst) begin
            counter_q     <= {P{1'b0}};
            at_start_q    <= 1'b1;
            dividing_q    <= 1'b0;
            clearing_q    <= 1'b0;
            multiplying_q <= 1'b0;
            shifting_q    <= 1'b0;
            at_end_q      <= 1'b0;
        end else begin
            counter_q     <= counter_q + COUNTER_ONE;
            at_start_q    <= (counter_q == COUNTER_LAST);
            dividing_q    <= (counter_wide < P);
            clearing_q    <= (counter_wide == P);
            multiplying_q <= multiplying_next;
            shifting_q    <= (counter_wide >= 1) && (counter_wide <= 2 * P - 1);
            at_end_q      <= (counter_q == COUNTER_LAST - COUNTER_ONE);
        end
    end

    // ---- the unit -------------------------------------------------------------
    reg                         sample_enable_q, sample_laser_q, sample_dynamic_q;
    reg                         sample_moving_q, sample_full_q;
    reg  [P:0]                  sample_power_q;
    reg  [ACCUMULATOR_BITS-1:0] accumulator_q;
    reg  [P-1:0]                dividend_q;
    reg  [P-1:0]                signs_q;
    reg  [31:0]                 addend_q;
    reg                         multiply_add_q;

    // the sample: the dividend floor(speed * 2^P / 2^6) split into its high part
    // (speed >> 6, the first remainder) and its low P bits (fed in bit by bit)
    wire [P-1:0]  dividend_low;
    generate
        if (P >= 6) begin : g_low_wide
            assign dividend_low = {speed[5:0], {(P-6){1'b0}}};
        end else begin : g_low_narrow
            assign dividend_low = speed[5:6-P];
        end
    endgenerate
    wire          speed_full = (speed[37:6] >= cruise_q);

    // the one adder / subtractor, its operands one level of logic from registers
    // and its sum straight into registers.  Sample: speed >> 6 plus 0.  Dividing:
    // the shifted remainder with the next dividend bit, minus the divisor when the
    // remainder is not negative, plus it when negative.  Multiplying: twice the
    // product plus the addend when multiply_add (the quotient's bit) is set.
    wire          remainder_negative = accumulator_q[ACCUMULATOR_BITS-1];
    // a copy of the sign (always equal to it) for the operand's high bits: it halves
    // the sign's fanout, the loop's longest wire (keep: not merged with the original)
    (* keep *) reg sign_copy_q;
    wire          subtract = dividing_q && !remainder_negative;
    wire          subtract_high = dividing_q && !sign_copy_q;
    wire [ACCUMULATOR_BITS-1:0] shifted = at_start_q
        ? {1'b0, speed[37:6]}
        : {accumulator_q[ACCUMULATOR_BITS-2:0], dividend_q[P-1]};
    wire [ACCUMULATOR_BITS-1:0] addend_wide = {1'b0, addend_q};
    wire [ACCUMULATOR_BITS-1:0] operand_select =
        {{(ACCUMULATOR_BITS-SIGN_SPLIT){subtract_high}}, {SIGN_SPLIT{subtract}}};
    wire [ACCUMULATOR_BITS-1:0] operand =
        dividing_q ? (addend_wide ^ operand_select)
                   : (addend_wide & {ACCUMULATOR_BITS{multiply_add_q}});
    wire [ACCUMULATOR_BITS-1:0] total =
        shifted + operand + {{(ACCUMULATOR_BITS-1){1'b0}}, subtract};
    wire          accumulate = at_start_q || dividing_q || multiplying_q;
    // multiply_add of the next clock: a multiplication step follows and the
    // quotient's next bit (the inverted sign then on top of signs) is 1
    wire          sign_next = shifting_q ? signs_q[P-2] : signs_q[P-1];

    // the accumulator: the sum, or cleared (a synchronous reset) before the product
    always @(posedge clk) begin
        if (rst || clearing_q) begin
            accumulator_q <= {ACCUMULATOR_BITS{1'b0}};
            sign_copy_q   <= 1'b0;
        end else if (accumulate) begin
            accumulator_q <= total;
            sign_copy_q   <= total[ACCUMULATOR_BITS-1];
        end
    end

    always @(posedge clk) begin
        if (rst) begin
            signs_q <= {P{1'b0}};
        end else if (shifting_q) begin
            signs_q <= {signs_q[P-2:0], remainder_negative};
        end
    end

    always @(posedge clk) begin
        if (rst) begin
            dividend_q     <= {P{1'b0}};
            addend_q       <= 32'd0;
            multiply_add_q <= 1'b0;
        end else begin
            if (at_start_q) begin
                dividend_q <= dividend_low;
                addend_q   <= cruise_q;
            end else if (dividing_q) begin
                dividend_q <= {dividend_q[P-2:0], 1'b0};
            end else if (clearing_q) begin
                addend_q   <= {{(31-P){1'b0}}, sample_power_q};
            end
            multiply_add_q <= multiplying_next && !sign_next;
        end
    end

    always @(posedge clk) begin
        if (rst) begin
            sample_laser_q   <= 1'b0;
            sample_dynamic_q <= 1'b0;
            sample_moving_q  <= 1'b0;
            sample_full_q    <= 1'b0;
            sample_power_q   <= {(P+1){1'b0}};
        end else if (at_start_q) begin
            sample_laser_q   <= laser_q;
            sample_dynamic_q <= dynamic_q;
            sample_moving_q  <= (speed != 38'd0);
            sample_full_q    <= speed_full;
            sample_power_q   <= power_q;
        end
    end

    // off also cancels the result under way
    always @(posedge clk) begin
        if (rst || off) begin
            sample_enable_q <= 1'b0;
        end else if (at_start_q) begin
            sample_enable_q <= enable_q;
        end
    end

    // the effective duty (valid from counter 2P + 2 on)
    reg  [P:0] result;
    always @(*) begin
        if (!sample_enable_q) begin
            result = {(P+1){1'b0}};
        end else if (!sample_laser_q) begin
            result = sample_power_q;
        end else if (!sample_moving_q) begin
            result = {(P+1){1'b0}};
        end else if (!sample_dynamic_q || sample_full_q) begin
            result = sample_power_q;
        end else begin
            result = accumulator_q[2*P:P];
        end
    end

    // ---- duty and pins --------------------------------------------------------
    reg  [P:0] duty_q;
    reg        pwm_q;

    always @(posedge clk) begin
        if (rst || off) begin
            duty_q <= {(P+1){1'b0}};
        end else if (at_end_q) begin
            duty_q <= result;
        end
    end

    always @(posedge clk) begin
        if (rst) begin
            pwm_q <= 1'b0;
        end else begin
            pwm_q <= enable_next && ({1'b0, counter_q} < duty_q);
        end
    end

    assign spindle_enable  = enable_q;
    assign spindle_reverse = reverse_q;
    assign coolant_mist    = mist_q;
    assign coolant_flood   = flood_q;
    assign pwm             = pwm_q;
    assign duty            = duty_q;

endmodule

`default_nettype wire
