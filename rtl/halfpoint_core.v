// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// ============================================================================
// halfpoint_core: the motion core -- command stream, queue, sequencing of
// arcs and lines, feed rate, STEP/DIR outputs and absolute positions
// ============================================================================
// Commands arrive as single 256-bit beats on an AXI4-Stream slave; their
// layout, opcodes and the error codes come from halfpoint_cmd.vh, generated
// from the one definition in model/halfpoint/spec/encoding.py (tabled in the
// README), so no field position is written here.  They wait in a queue of
// DEPTH entries; a dispatcher hands them in program order to the arc unit (in
// the plane of the two axes the command names; halfpoint_helix maps its moves
// onto them and steps the helix axes against the arc's move count) or the line
// unit (all NA axes), with at most one command in flight (handed over, not yet
// started).  A PROFILE command sets the
// velocity profile in force for the motion commands that follow it.
//
// The interpolators are decoupled from the pacing (issue 13): the running unit
// makes one move per clock into a move queue of MOVE_DEPTH entries whenever it
// has room (its count before the edge: no path from the pacing back to the
// interpolators), each entry the axes stepped, their directions, the move's
// cost class (axis move, diagonal arc move, line iteration) and whether it is
// its segment's last.  A unit's pending segment starts when the other is not running
// (no end test in front of a load: an arc-line boundary costs a clock the move queue hides).
// A motion command is handed to its unit only while the profile queue
// (PROFILE_DEPTH entries) has room; its profile and CONT flag enter that queue
// once the unit has validated it, long before its first move, so that the
// profile stage knows the next segment is coming.  The motion-profile stage
// (halfpoint_profile; model/halfpoint/spec/profile.py) pops the head move at
// the planned path speed, when every axis the move steps has its STEP/DIR
// generator ready for its direction; it takes the next profile at the edge of
// the current segment's last move.
//
// An OUTPUT command (spindle, laser and coolant settings) waits at the queue
// head until everything before it has moved (nothing in flight, both units
// idle, the move and profile queues empty, the profile stage idle), then loads
// halfpoint_outputs at that edge; abort and a stop at rest switch the outputs
// off.  A PROFILE may carry a power (set_power): the output stage takes it at
// the edge the profile stage takes that segment, with no stop (laser power
// changing with the motion, as grbl's laser mode does with S words).
//
// hold (level) decelerates along the path to rest and waits; releasing it
// accelerates back to the plan.  stop (level) decelerates to rest; an edge at
// rest with stop high sets the flush register (the profile stage drops its
// segment, nothing pops; an OUTPUT does not load while stop is high), and the
// next edge drops the queue, the command in flight, both units' segments, the
// move and profile queues and the profile in force (a controlled stop; tready
// is low meanwhile).  The flush is a register, so that no path runs from the
// profile stage's speed register through the dispatcher to the queue.
// feed_override (1/128, above 128 acts as 128) scales the cruise speed, its
// changes ramping at the segment's acceleration.  abort_now (level): at each
// edge while it is high no move is made and everything not yet moved is
// dropped at once; tready is low.  A STEP pulse already started completes
// with its full timing; positions keep every step made.  abort_now and stop
// pass through a register first: each acts from the edge after the one that
// saw it high (one clock of latency).
//
// Rejected commands (bad opcode or reserved bits, field out of range, no
// profile or a bad one, arc validator rejects) make no motion, set err_code
// and pulse err; the rest of the program runs.  A line whose deltas are all
// zero is a no-op.  underrun is set (sticky until reset) when a segment
// flagged CONT made its last move and no next profile was taken at that edge;
// dry (sticky) when the profile stage had to decelerate for a dry queue.
//
// Parameters: see the comment above each (an illegal value stops
// elaboration).
//
// Reset: synchronous, active high.
// ============================================================================
`include "halfpoint_cmd.vh"

module halfpoint_core #(
    // number of axes, 2..6 (arcs in any plane of two axes, helices on up to two more)
    parameter integer NA    = 3,
    // coordinate and position width in bits, 8..32 (signed coordinates)
    parameter integer W     = 32,
    // command queue depth in commands, a power of two, 2..256
    parameter integer DEPTH = 16,
    // width of the STEP/DIR timing settings in bits, 2..16
    parameter integer TW    = 16,
    // speed-step tick of the profile stage: 2^DIV clocks, 1..24 (the host's
    // profile.choose_div of the clock frequency: 12 at 50 MHz)
    parameter integer DIV   = 12,
    // move queue depth in moves, 2..16
    parameter integer MOVE_DEPTH    = 4,
    // profile queue depth in segments, 1..8
    parameter integer PROFILE_DEPTH = 2,
    // spindle/laser PWM period of 2^PWM_BITS clocks, 4..16 (10: 48.8 kHz at 50 MHz)
    parameter integer PWM_BITS      = 10
) (
    input  wire                           clk,
    input  wire                           rst,

    /*
     * Command stream (AXI4-Stream slave, one command per beat)
     */
    input  wire                           s_axis_tvalid,
    output wire                           s_axis_tready,
    input  wire [`HALFPOINT_CMD_BITS-1:0] s_axis_tdata,

    /*
     * STEP/DIR configuration: timing per axis (axis k in bits k*TW +: TW), polarity
     */
    input  wire [NA*TW-1:0]               cfg_steplen,
    input  wire [NA*TW-1:0]               cfg_stepspace,
    input  wire [NA*TW-1:0]               cfg_dirsetup,
    input  wire [NA*TW-1:0]               cfg_dirhold,
    input  wire [NA-1:0]                  cfg_step_inv,
    input  wire [NA-1:0]                  cfg_dir_inv,

    /*
     * Motion control
     */
    // feed override in 1/128 (128 = 100 %); values above 128 act as 128
    input  wire [7:0]                     feed_override,
    // feed hold: decelerate to rest and wait (level)
    input  wire                           hold,
    // controlled stop: decelerate to rest, then drop everything not yet moved (level)
    input  wire                           stop,
    // stop now: no move, queue and pending segments dropped (level)
    input  wire                           abort_now,

    /*
     * STEP/DIR outputs
     */
    output wire [NA-1:0]                  step_pin,
    output wire [NA-1:0]                  dir_pin,

    /*
     * Spindle, laser and coolant outputs (OUTPUT commands; halfpoint_outputs)
     */
    output wire                           spindle_enable,
    // counter-clockwise (M4 outside laser mode)
    output wire                           spindle_reverse,
    // duty = the OUTPUT's power (laser M4: times speed / cruise speed)
    output wire                           spindle_pwm,
    output wire                           coolant_mist,
    output wire                           coolant_flood,

    /*
     * Status
     */
    // absolute position per axis (axis k in bits k*W +: W)
    output reg  [NA*W-1:0]                pos,
    // a move was made at the last edge
    output reg                            move,
    output wire                           busy,
    output wire [$clog2(DEPTH):0]         queue_level,
    // a command was rejected at the last edge
    output reg                            err,
    // code of the last rejected command (HALFPOINT_E_* of halfpoint_cmd.vh)
    output reg  [`HALFPOINT_ERR_CODE_BITS-1:0] err_code,
    // a CONT segment ended and no segment was taken at that edge (sticky)
    output reg                            underrun,
    // the profile stage decelerated for a dry queue (sticky)
    output wire                           dry,
    // path speed, BLU per clock x 2^38 (the profile stage's speed register)
    output wire [37:0]                    speed
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
        if (TW < 2 || TW > 16) begin : g_bad_tw
            halfpoint_core_illegal_parameter_TW_must_be_2_to_16 u_bad ();
        end
        if (DIV < 1 || DIV > 24) begin : g_bad_div
            halfpoint_core_illegal_parameter_DIV_must_be_1_to_24 u_bad ();
        end
        if (MOVE_DEPTH < 2 || MOVE_DEPTH > 16) begin : g_bad_move_depth
            halfpoint_core_illegal_parameter_MOVE_DEPTH_must_be_2_to_16 u_bad ();
        end
        if (PROFILE_DEPTH < 1 || PROFILE_DEPTH > 8) begin : g_bad_profile_depth
            halfpoint_core_illegal_parameter_PROFILE_DEPTH_must_be_1_to_8 u_bad ();
        end
        if (PWM_BITS < 4 || PWM_BITS > 16) begin : g_bad_pwm_bits
            halfpoint_core_illegal_parameter_PWM_BITS_must_be_4_to_16 u_bad ();
        end
    endgenerate

    localparam integer INDEX_W = $clog2(DEPTH);         // queue index width
    localparam integer CODE_W = `HALFPOINT_ERR_CODE_BITS;
    // profile fields: distances are DW bits; a profile is PROFILE_W bits,
    // {power, set_power, d_stop, d_exit, line_cost[17:0], accel[33:0], v_exit[31:0],
    // v_cruise[31:0]}, the power's two fields from POWER_AT on
    localparam integer DW = W + `HALFPOINT_PROFILE_DISTANCE_EXTRA;
    localparam integer POWER_W = `HALFPOINT_CMD_PROFILE_POWER_WIDTH;
    localparam integer POWER_AT = 116 + 2 * DW;
    localparam integer PROFILE_W = POWER_AT + 1 + POWER_W;

    // ------------------------------------------------------------------
    // Decode at the queue's input
    // ------------------------------------------------------------------
    // Each command is checked and put in run form as it is pushed, so that
    // the queue head feeds the dispatcher and the units with no arithmetic
    // in between.  The checks are the same and their results are acted on
    // when the command reaches the head, exactly as if it were decoded there.
    wire [`HALFPOINT_CMD_BITS-1:0] cmd = s_axis_tdata;
    wire [`HALFPOINT_CMD_OPCODE_WIDTH-1:0] opcode =
        cmd[`HALFPOINT_CMD_OPCODE_LSB +: `HALFPOINT_CMD_OPCODE_WIDTH];
    wire        cmd_cont = cmd[`HALFPOINT_FLAG_CONT_BIT];

    // does a 33-bit signed value fit W bits?
    function fits;
        input [32:0] value;
        reg   [32:0] top;
        begin
            top  = value >> (W - 1);
            fits = (top == 33'd0) || (top == ({33{1'b1}} >> (W - 1)));
        end
    endfunction
    function [32:0] sign_extend;
        input [31:0] value;
        begin
            sign_extend = {value[31], value};
        end
    endfunction

    // line fields: the deltas of the core's NA axes (queued in place, read at
    // the head as head_delta); those of the others must be zero (they are
    // reserved bits of this core)
    reg             line_fits, line_reserved_set, line_zero;
    reg  [31:0]     delta;
    integer k;
    always @(*) begin
        line_fits = 1'b1;
        line_reserved_set = 1'b0;
        line_zero = 1'b1;
        for (k = 0; k < `HALFPOINT_MAX_AXES; k = k + 1) begin
            delta = cmd[`HALFPOINT_CMD_DELTA_LSB + `HALFPOINT_CMD_DELTA_STRIDE * k
                        +: `HALFPOINT_CMD_DELTA_WIDTH];
            if (k < NA) begin
                if (!fits(sign_extend(delta))) line_fits = 1'b0;
                if (delta != 32'd0) line_zero = 1'b0;
            end else if (delta != 32'd0) begin
                line_reserved_set = 1'b1;
            end
        end
    end

    // arc fields: start and end relative to the centre
    wire [32:0] arc_i  = sign_extend(cmd[`HALFPOINT_CMD_ARC_I_LSB +: `HALFPOINT_CMD_ARC_I_WIDTH]);
    wire [32:0] arc_j  = sign_extend(cmd[`HALFPOINT_CMD_ARC_J_LSB +: `HALFPOINT_CMD_ARC_J_WIDTH]);
    wire [32:0] arc_x  = sign_extend(cmd[`HALFPOINT_CMD_ARC_X_LSB +: `HALFPOINT_CMD_ARC_X_WIDTH]);
    wire [32:0] arc_y  = sign_extend(cmd[`HALFPOINT_CMD_ARC_Y_LSB +: `HALFPOINT_CMD_ARC_Y_WIDTH]);
    wire [32:0] arc_xs = 33'd0 - arc_i;
    wire [32:0] arc_ys = 33'd0 - arc_j;
    wire [32:0] arc_xe = arc_x - arc_i;
    wire [32:0] arc_ye = arc_y - arc_j;
    wire        arc_fits = fits(arc_i) && fits(arc_j) && fits(arc_x) && fits(arc_y) &&
                           fits(arc_xs) && fits(arc_ys) && fits(arc_xe) && fits(arc_ye);

    // arc plane and helix (halfpoint_helix): the plane's axes (u, v), the move
    // count N, the helix slots' deltas; a delta in a slot this core does not have
    // (min(2, NA - 2) slots) is a reserved bit set (E_OPCODE), the axis pair out of
    // range or a delta beyond W is E_FIELD, |delta| > N is E_HELIX
    localparam integer SLOTS = (NA - 2 < `HALFPOINT_HELIX_SLOTS) ? NA - 2
                                                                 : `HALFPOINT_HELIX_SLOTS;
    wire [2:0]  arc_u = cmd[`HALFPOINT_CMD_ARC_U_AXIS_LSB +: `HALFPOINT_CMD_ARC_U_AXIS_WIDTH];
    wire [2:0]  arc_v = cmd[`HALFPOINT_CMD_ARC_V_AXIS_LSB +: `HALFPOINT_CMD_ARC_V_AXIS_WIDTH];
    wire [31:0] arc_count = cmd[`HALFPOINT_CMD_ARC_COUNT_LSB +: `HALFPOINT_CMD_ARC_COUNT_WIDTH];
    wire        arc_plane_ok = ({29'd0, arc_u} < NA) && ({29'd0, arc_v} < NA) &&
                               (arc_u != arc_v);
    reg         helix_fits, helix_reserved_set, helix_over;
    reg  [1:0]  helix_negative;
    reg  [2*W-1:0] helix_magnitude;
    reg  [32:0] helix_delta, helix_abs;
    integer h;
    always @(*) begin
        helix_fits = 1'b1;
        helix_reserved_set = 1'b0;
        helix_over = 1'b0;
        helix_negative = 2'b00;
        helix_magnitude = {2*W{1'b0}};
        for (h = 0; h < `HALFPOINT_HELIX_SLOTS; h = h + 1) begin
            helix_delta = sign_extend(cmd[`HALFPOINT_CMD_ARC_HELIX0_LSB +
                                          `HALFPOINT_CMD_ARC_HELIX_STRIDE * h
                                          +: `HALFPOINT_CMD_ARC_HELIX0_WIDTH]);
            helix_abs = helix_delta[32] ? 33'd0 - helix_delta : helix_delta;
            if (h < SLOTS) begin
                if (!fits(helix_delta)) helix_fits = 1'b0;
                if (helix_abs > {1'b0, arc_count}) helix_over = 1'b1;
                helix_negative[h] = helix_delta[32];
                helix_magnitude[h*W +: W] = helix_abs[W-1:0];
            end else if (helix_delta != 33'd0) begin
                helix_reserved_set = 1'b1;
            end
        end
    end

    // output fields: power at most 100 % (else E_FIELD)
    wire [`HALFPOINT_CMD_OUTPUT_POWER_WIDTH-1:0] output_power =
        cmd[`HALFPOINT_CMD_OUTPUT_POWER_LSB +: `HALFPOINT_CMD_OUTPUT_POWER_WIDTH];
    wire output_fits = (output_power <= `HALFPOINT_OUTPUT_POWER_FULL);

    // profile fields and their rules (else E_PROFILE_FIELD)
    wire [31:0] profile_v_cruise = cmd[`HALFPOINT_CMD_PROFILE_V_CRUISE_LSB +:
                                       `HALFPOINT_CMD_PROFILE_V_CRUISE_WIDTH];
    wire [31:0] profile_v_exit = cmd[`HALFPOINT_CMD_PROFILE_V_EXIT_LSB +:
                                     `HALFPOINT_CMD_PROFILE_V_EXIT_WIDTH];
    wire [33:0] profile_accel = cmd[`HALFPOINT_CMD_PROFILE_ACCEL_LSB +:
                                    `HALFPOINT_CMD_PROFILE_ACCEL_WIDTH];
    wire [`HALFPOINT_CMD_PROFILE_D_EXIT_WIDTH-1:0] profile_d_exit_field =
        cmd[`HALFPOINT_CMD_PROFILE_D_EXIT_LSB +: `HALFPOINT_CMD_PROFILE_D_EXIT_WIDTH];
    wire [`HALFPOINT_CMD_PROFILE_D_STOP_WIDTH-1:0] profile_d_stop_field =
        cmd[`HALFPOINT_CMD_PROFILE_D_STOP_LSB +: `HALFPOINT_CMD_PROFILE_D_STOP_WIDTH];
    // d_exit < 2^DW; then d_stop <= d_exit < 2^DW follows from the compare of
    // the whole fields
    wire          profile_d_exit_fits = (profile_d_exit_field >> DW) == 0;
    // the power the segment's outputs take with it (laser mode): at most 100 %,
    // and 0 unless set_power
    wire          profile_set_power = cmd[`HALFPOINT_CMD_PROFILE_SET_POWER_LSB];
    wire [POWER_W-1:0] profile_power = cmd[`HALFPOINT_CMD_PROFILE_POWER_LSB +: POWER_W];
    wire          profile_power_ok = (profile_power <= `HALFPOINT_OUTPUT_POWER_FULL) &&
                                     (profile_set_power || (profile_power == {POWER_W{1'b0}}));
    wire          profile_rules_ok = (profile_accel != 34'd0) &&
                                     (profile_v_exit <= profile_v_cruise) &&
                                     (profile_d_stop_field <= profile_d_exit_field) &&
                                     profile_d_exit_fits && profile_power_ok;

    wire is_line    = (opcode == `HALFPOINT_OP_LINE);
    wire is_arc_cw  = (opcode == `HALFPOINT_OP_ARC_CW);
    wire is_arc     = is_arc_cw || (opcode == `HALFPOINT_OP_ARC_CCW);
    wire is_profile = (opcode == `HALFPOINT_OP_PROFILE);
    wire is_output  = (opcode == `HALFPOINT_OP_OUTPUT);
    wire line_reserved = ((cmd & `HALFPOINT_CMD_RESERVED_LINE) != {`HALFPOINT_CMD_BITS{1'b0}}) ||
                         line_reserved_set;
    wire arc_reserved  = ((cmd & `HALFPOINT_CMD_RESERVED_ARC) != {`HALFPOINT_CMD_BITS{1'b0}}) ||
                         helix_reserved_set;
    wire profile_reserved =
        ((cmd & `HALFPOINT_CMD_RESERVED_PROFILE) != {`HALFPOINT_CMD_BITS{1'b0}});
    wire output_reserved =
        ((cmd & `HALFPOINT_CMD_RESERVED_OUTPUT) != {`HALFPOINT_CMD_BITS{1'b0}});
    wire bad_opcode = !(is_line || is_arc || is_profile || is_output) ||
                      (is_line && line_reserved) || (is_arc && arc_reserved) ||
                      (is_profile && profile_reserved) || (is_output && output_reserved);
    wire bad_fit = !bad_opcode && ((is_line && !line_fits) ||
                                   (is_arc && !(arc_fits && arc_plane_ok && helix_fits)) ||
                                   (is_output && !output_fits));
    wire bad_helix = !bad_opcode && !bad_fit && is_arc && helix_over;
    wire bad_profile = !bad_opcode && is_profile && !profile_rules_ok;
    wire is_nop  = !bad_opcode && !bad_fit && is_line && line_zero;

    // queue entry: {payload, flags}.  The payload is the command itself from
    // bit PAYLOAD_LSB (the lowest field above the flags) up, with the
    // profile's set_power bit below it as payload bit 0, so that command bit c
    // >= PAYLOAD_LSB is payload bit c - PAYLOAD_LSB + 1.  An arc's computed
    // fields are written over the raw ones they come from (no other opcode's
    // field is moved): xs, ys, xe, ye over the low W bits of i, j, x, y, each
    // helix slot's magnitude over the low W bits of its delta, the slots'
    // signs over two bits that are reserved in an arc command (ARC_NEGATIVE*).
    localparam integer PAYLOAD_LSB = `HALFPOINT_CMD_PROFILE_POWER_LSB;
    localparam integer PAYLOAD_W   = `HALFPOINT_CMD_BITS - PAYLOAD_LSB + 1;
    localparam integer ARC_NEGATIVE0_BIT = 19;
    localparam integer ARC_NEGATIVE1_BIT = 23;
    localparam integer FLAGS_W   = 11;
    localparam integer ENTRY_W   = PAYLOAD_W + FLAGS_W;
    localparam [`HALFPOINT_CMD_BITS-1:0] RESERVED_ARC = `HALFPOINT_CMD_RESERVED_ARC;
    generate
        if (!RESERVED_ARC[ARC_NEGATIVE0_BIT] || !RESERVED_ARC[ARC_NEGATIVE1_BIT] ||
            `HALFPOINT_CMD_PROFILE_SET_POWER_LSB >= PAYLOAD_LSB) begin : g_bad_layout
            halfpoint_core_payload_layout_does_not_match_the_encoding u_bad ();
        end
    endgenerate
    // the payload bit of command bit c (c >= PAYLOAD_LSB)
    function integer payload_bit;
        input integer c;
        begin
            payload_bit = c - PAYLOAD_LSB + 1;
        end
    endfunction
    reg [`HALFPOINT_CMD_BITS-1:0] in_command;
    integer slot;
    always @(*) begin
        in_command = cmd;
        if (is_arc) begin
            in_command[`HALFPOINT_CMD_ARC_I_LSB +: W] = arc_xs[W-1:0];
            in_command[`HALFPOINT_CMD_ARC_J_LSB +: W] = arc_ys[W-1:0];
            in_command[`HALFPOINT_CMD_ARC_X_LSB +: W] = arc_xe[W-1:0];
            in_command[`HALFPOINT_CMD_ARC_Y_LSB +: W] = arc_ye[W-1:0];
            in_command[ARC_NEGATIVE0_BIT] = helix_negative[0];
            in_command[ARC_NEGATIVE1_BIT] = helix_negative[1];
        end
        for (slot = 0; slot < SLOTS; slot = slot + 1)
            if (is_arc)
                in_command[`HALFPOINT_CMD_ARC_HELIX0_LSB + `HALFPOINT_CMD_ARC_HELIX_STRIDE * slot
                           +: W] = helix_magnitude[slot*W +: W];
    end
    wire [PAYLOAD_W-1:0] in_payload = {in_command[`HALFPOINT_CMD_BITS-1:PAYLOAD_LSB],
                                       cmd[`HALFPOINT_CMD_PROFILE_SET_POWER_LSB]};
    // below PAYLOAD_LSB: the opcode and the flags (decoded into in_flags)
    wire [PAYLOAD_LSB-1:0] unused_command_low = in_command[PAYLOAD_LSB-1:0];
    wire [FLAGS_W-1:0] in_flags = {bad_helix, is_output, bad_profile, is_profile, is_nop,
                                   bad_fit,
                                   bad_opcode,
                                   cmd_cont, is_line, is_arc_cw, is_arc};
    wire [ENTRY_W-1:0] in_entry = {in_payload, in_flags};

    // ------------------------------------------------------------------
    // Queue
    // ------------------------------------------------------------------
    reg  [ENTRY_W-1:0] queue_mem [0:DEPTH-1];
    reg  [INDEX_W-1:0] write_index_q, read_index_q;
    reg  [INDEX_W:0]   count_q;
    wire               pop;
    wire               push = s_axis_tvalid && s_axis_tready;
    wire               flush;      // abort, or the stop flush register
    localparam [INDEX_W:0]   QUEUE_FULL = {1'b1, {INDEX_W{1'b0}}};     // DEPTH
    localparam [INDEX_W-1:0] INDEX_ONE = {{(INDEX_W-1){1'b0}}, 1'b1};
    localparam [INDEX_W:0]   COUNT_ONE = {{INDEX_W{1'b0}}, 1'b1};
    wire               stage_stopped;  // stop (or the flush) at rest (the profile stage)

    // abort_now and stop are registered before they act: the core acts on them from
    // the edge after they rise (they reach the reset of every stage, and a
    // path from an input to it would set the core's clock).  flush_q: an edge
    // at rest with stop high sets it, and the next edge is the flush (the
    // stage's stop is held high at it, so it takes nothing from the queues
    // being dropped; it is at rest with no segment since the edge before)
    reg                abort_q, stop_q, flush_q;
    always @(posedge clk) begin
        if (rst) begin
            abort_q <= 1'b0;
            stop_q <= 1'b0;
            flush_q <= 1'b0;
        end else begin
            abort_q <= abort_now;
            stop_q <= stop;
            flush_q <= stage_stopped && stop_q;
        end
    end

    assign s_axis_tready = (count_q != QUEUE_FULL) && !abort_q && !stage_stopped;
    assign queue_level   = count_q;

    always @(posedge clk) begin
        if (push) queue_mem[write_index_q] <= in_entry;
    end

    // The head's flags, which every dispatch decision reads, come from a
    // register that always equals the flags of queue_mem[read_index_q] while
    // the queue is not empty: on a pop it takes the next entry's flags (a
    // second, flags-only copy of the queue read at read_index_q + 1, or the
    // beat pushed at the same edge when it becomes the head), so no memory
    // read lies between read_index_q and the decisions.  The payload is data
    // only and is still read from the memory.
    reg  [FLAGS_W-1:0] flags_mem [0:DEPTH-1];
    reg  [FLAGS_W-1:0] head_flags_q;
    wire [INDEX_W-1:0] read_index_next = read_index_q + INDEX_ONE;
    always @(posedge clk) begin
        if (push) flags_mem[write_index_q] <= in_flags;
    end
    always @(posedge clk) begin
        if (pop) begin
            // count_q >= 2: the next entry is in the memory; count_q == 1:
            // the queue empties unless a beat is pushed at this edge
            head_flags_q <= (count_q != COUNT_ONE) ? flags_mem[read_index_next] : in_flags;
        end else if (count_q == {(INDEX_W+1){1'b0}}) begin
            head_flags_q <= in_flags;
        end
    end
    always @(posedge clk) begin
        if (rst || flush) begin
            write_index_q <= {INDEX_W{1'b0}};
            read_index_q <= {INDEX_W{1'b0}};
            count_q <= {(INDEX_W+1){1'b0}};
        end else begin
            if (push) write_index_q <= write_index_q + INDEX_ONE;
            if (pop)  read_index_q <= read_index_q + INDEX_ONE;
            if (push && !pop) count_q <= count_q + COUNT_ONE;
            else if (pop && !push) count_q <= count_q - COUNT_ONE;
        end
    end

    // the queue head, decoded
    wire [ENTRY_W-1:0]   head = queue_mem[read_index_q];
    wire                 head_arc     = head_flags_q[0];
    wire                 head_cw      = head_flags_q[1];
    wire                 head_line    = head_flags_q[2];
    wire                 head_cont    = head_flags_q[3];
    wire                 head_bad_opcode = head_flags_q[4];
    wire                 head_bad_fit = head_flags_q[5];
    wire                 head_nop     = head_flags_q[6];
    wire                 head_profile = head_flags_q[7];
    wire                 head_bad_profile = head_flags_q[8];
    wire                 head_output  = head_flags_q[9];
    wire                 head_bad_helix = head_flags_q[10];
    wire [PAYLOAD_W-1:0] head_payload = head[ENTRY_W-1:FLAGS_W];
    // the profile of a PROFILE entry's payload, in the profile queue's layout
    function [PROFILE_W-1:0] profile_of;
        input [PAYLOAD_W-1:0] p;
        begin
            // set_power is payload bit 0
            profile_of = {p[payload_bit(`HALFPOINT_CMD_PROFILE_POWER_LSB) +: POWER_W], p[0],
                          p[payload_bit(`HALFPOINT_CMD_PROFILE_D_STOP_LSB) +: DW],
                          p[payload_bit(`HALFPOINT_CMD_PROFILE_D_EXIT_LSB) +: DW],
                          p[payload_bit(`HALFPOINT_CMD_PROFILE_LINE_COST_LSB) +: 18],
                          p[payload_bit(`HALFPOINT_CMD_PROFILE_ACCEL_LSB) +: 34],
                          p[payload_bit(`HALFPOINT_CMD_PROFILE_V_EXIT_LSB) +: 32],
                          p[payload_bit(`HALFPOINT_CMD_PROFILE_V_CRUISE_LSB) +: 32]};
        end
    endfunction
    wire [PROFILE_W-1:0] head_profile_fields = profile_of(head_payload);
    wire [NA*W-1:0]      head_delta;
    genvar head_axis;
    generate
        for (head_axis = 0; head_axis < NA; head_axis = head_axis + 1) begin : g_head_delta
            assign head_delta[head_axis*W +: W] = head_payload[
                payload_bit(`HALFPOINT_CMD_DELTA_LSB + `HALFPOINT_CMD_DELTA_STRIDE * head_axis)
                +: W];
        end
    endgenerate
    wire [FLAGS_W-1:0]   unused_head_flags = head[FLAGS_W-1:0];

    // ------------------------------------------------------------------
    // Dispatcher
    // ------------------------------------------------------------------
    // profile_q: the profile in force (profile_valid_q), profile_arc_q = its
    // line cost is 0 (an arc's profile)
    reg                  in_flight_q;
    reg  [PROFILE_W-1:0] profile_q;
    reg                  profile_valid_q, profile_arc_q;
    wire        head_ok = (count_q != {(INDEX_W+1){1'b0}}) && !in_flight_q && !flush;
    wire        head_bad = head_bad_opcode || head_bad_fit || head_bad_profile ||
                           head_bad_helix;
    wire        head_motion = (head_arc || (head_line && !head_nop)) && !head_bad;
    wire        profile_mismatch = !profile_valid_q || (head_arc != profile_arc_q);
    wire        profile_load = head_ok && head_profile && !head_bad;
    wire        no_profile = head_ok && head_motion && profile_mismatch;
    wire        profile_room;    // the profile queue has room (count before the edge)
    // a motion command is handed over only while the profile queue has room
    wire        arc_s_valid  = head_ok && head_motion && head_arc && !profile_mismatch &&
                               profile_room;
    wire        line_s_valid = head_ok && head_motion && head_line && !profile_mismatch &&
                               profile_room;
    wire        arc_s_ready, line_s_ready;
    wire        arc_take  = arc_s_valid && arc_s_ready;
    wire        line_take = line_s_valid && line_s_ready;
    wire        dispatch_error = head_ok && (head_bad || no_profile);
    // an OUTPUT runs once everything before it has moved, not while stop is
    // high (an idle machine is at rest: that edge is a stop at rest, and the
    // next one drops the OUTPUT)
    wire        downstream_idle;
    wire        output_load = head_ok && head_output && !head_bad && downstream_idle &&
                              !stop_q;
    assign pop = dispatch_error || (head_ok && (head_nop || profile_load)) || arc_take ||
                 line_take || output_load;

    // ------------------------------------------------------------------
    // Units
    // ------------------------------------------------------------------
    wire          arc_run, arc_loading, arc_ending, arc_next_diagonal, arc_busy, arc_reject;
    wire [1:0]    arc_next_step, arc_next_dir, arc_error;
    wire          line_run, line_loading, line_ending, line_busy, line_reject;
    wire [NA-1:0] line_next_step, line_next_dir;
    wire [1:0]    line_error;
    wire          move_room;       // the move queue has room (count before the edge)
    wire          arc_pending, line_pending;

    wire          unused_arc_move, unused_arc_step_x, unused_arc_step_y;
    wire          unused_arc_dir_x, unused_arc_dir_y;
    wire          unused_arc_done, unused_line_move, unused_line_done;
    wire [W-1:0]  unused_arc_x, unused_arc_y;
    wire [W+1:0]  unused_arc_f;
    wire [NA-1:0] unused_line_step, unused_line_dir;

    halfpoint_arc #(
        .W (W)
    ) u_arc (
        .clk       (clk),
        .rst       (rst),
        .en        (move_room && arc_run),
        .s_valid   (arc_s_valid),
        .s_ready   (arc_s_ready),
        .s_cw      (head_cw),
        .s_xs      (head_payload[payload_bit(`HALFPOINT_CMD_ARC_I_LSB) +: W]),
        .s_ys      (head_payload[payload_bit(`HALFPOINT_CMD_ARC_J_LSB) +: W]),
        .s_xe      (head_payload[payload_bit(`HALFPOINT_CMD_ARC_X_LSB) +: W]),
        .s_ye      (head_payload[payload_bit(`HALFPOINT_CMD_ARC_Y_LSB) +: W]),
        .busy      (arc_busy),
        .move      (unused_arc_move),
        .step_x    (unused_arc_step_x),
        .step_y    (unused_arc_step_y),
        .dir_x     (unused_arc_dir_x),
        .dir_y     (unused_arc_dir_y),
        .x         (unused_arc_x),
        .y         (unused_arc_y),
        .f         (unused_arc_f),
        .done      (unused_arc_done),
        .reject    (arc_reject),
        .err_code  (arc_error),
        .abort_now (flush),
        .start_en  (!line_run),
        .running   (arc_run),
        .pending   (arc_pending),
        .loading   (arc_loading),
        .ending    (arc_ending),
        .nx_step   (arc_next_step),
        .nx_dir    (arc_next_dir),
        .nx_diag   (arc_next_diagonal)
    );

    halfpoint_line #(
        .NA (NA),
        .W  (W)
    ) u_line (
        .clk       (clk),
        .rst       (rst),
        .en        (move_room && line_run),
        .s_valid   (line_s_valid),
        .s_ready   (line_s_ready),
        .s_delta   (head_delta),
        .busy      (line_busy),
        .move      (unused_line_move),
        .step      (unused_line_step),
        .dir       (unused_line_dir),
        .done      (unused_line_done),
        .reject    (line_reject),
        .err_code  (line_error),
        .abort_now (flush),
        .start_en  (!arc_run),
        .running   (line_run),
        .pending   (line_pending),
        .loading   (line_loading),
        .ending    (line_ending),
        .nx_step   (line_next_step),
        .nx_dir    (line_next_dir)
    );

    // the arc's moves on the core's axes (plane and helix)
    wire [NA-1:0] helix_step, helix_dir;
    wire          helix_count_error;
    halfpoint_helix #(
        .NA (NA),
        .W  (W)
    ) u_helix (
        .clk             (clk),
        .rst             (rst),
        .flush           (flush),
        .take            (arc_take),
        .take_u          (head_payload[payload_bit(`HALFPOINT_CMD_ARC_U_AXIS_LSB) +: 3]),
        .take_v          (head_payload[payload_bit(`HALFPOINT_CMD_ARC_V_AXIS_LSB) +: 3]),
        .take_count      (head_payload[payload_bit(`HALFPOINT_CMD_ARC_COUNT_LSB) +: 32]),
        .take_magnitude0 (head_payload[payload_bit(`HALFPOINT_CMD_ARC_HELIX0_LSB) +: W]),
        .take_magnitude1 (head_payload[payload_bit(`HALFPOINT_CMD_ARC_HELIX0_LSB
                                          + `HALFPOINT_CMD_ARC_HELIX_STRIDE) +: W]),
        .take_negative   ({head_payload[payload_bit(ARC_NEGATIVE1_BIT)],
                           head_payload[payload_bit(ARC_NEGATIVE0_BIT)]}),
        .load            (arc_loading),
        .move            (move_room && arc_run),
        .last            (arc_ending),
        .arc_step        (arc_next_step),
        .arc_dir         (arc_next_dir),
        .step            (helix_step),
        .dir             (helix_dir),
        .count_error     (helix_count_error)
    );

    wire [PWM_BITS:0] unused_duty;
    wire unused_ok = &{1'b0, unused_head_flags, unused_duty, unused_arc_move,
                       unused_arc_step_x,
                       unused_arc_step_y,
                       unused_arc_dir_x, unused_arc_dir_y, unused_arc_done, unused_line_move,
                       unused_line_done, unused_arc_x, unused_arc_y, unused_arc_f,
                       unused_line_step, unused_line_dir, line_error};

    // CONT of the command in flight; accepted_q: its profile entered the
    // profile queue, which it does on the first clock the unit holds it
    // validated in its pending slot (only the command in flight can be there)
    reg  pend_cont_q;
    reg  accepted_q;
    wire accept = (arc_pending || line_pending) && !accepted_q;

    always @(posedge clk) begin
        if (rst || flush) begin
            in_flight_q <= 1'b0;
            profile_valid_q <= 1'b0;
            accepted_q <= 1'b0;
        end else begin
            if (arc_loading || line_loading) begin
                accepted_q <= 1'b0;
            end else if (accept) begin
                accepted_q <= 1'b1;
            end
            if (arc_take || line_take) begin
                in_flight_q <= 1'b1;
            end else if (arc_loading || line_loading || arc_reject || line_reject) begin
                in_flight_q <= 1'b0;
            end
            if (profile_load) begin
                profile_valid_q <= 1'b1;
            end else if (head_ok && head_bad_profile) begin
                profile_valid_q <= 1'b0;
            end
        end
        if (profile_load) begin
            profile_q <= head_profile_fields;
            profile_arc_q <= (head_profile_fields[115:98] == 18'd0);
        end
        if (arc_take || line_take) begin
            pend_cont_q <= head_cont;
        end
    end

    // ------------------------------------------------------------------
    // Move queue: {last, class[1:0], dir[NA-1:0], step[NA-1:0]}
    // ------------------------------------------------------------------
    localparam integer MOVE_W = 2 * NA + 3;
    localparam integer MOVE_INDEX_W = (MOVE_DEPTH > 1) ? $clog2(MOVE_DEPTH) : 1;
    localparam [MOVE_INDEX_W:0] MOVE_FULL = MOVE_DEPTH[MOVE_INDEX_W:0];
    localparam [MOVE_INDEX_W:0] MOVE_COUNT_ONE = {{MOVE_INDEX_W{1'b0}}, 1'b1};
    localparam [MOVE_INDEX_W-1:0] MOVE_LAST_INDEX = MOVE_DEPTH[MOVE_INDEX_W-1:0] - 1'b1;

    reg  [MOVE_W-1:0]       move_mem [0:MOVE_DEPTH-1];
    reg  [MOVE_INDEX_W-1:0] move_write_q, move_read_q;
    reg  [MOVE_INDEX_W:0]   move_count_q;
    wire                    stage_pop;
    assign move_room = (move_count_q != MOVE_FULL);

    wire          produce = move_room && (arc_run || line_run);
    wire [NA-1:0] produce_step = arc_run ? helix_step : line_next_step;
    wire [NA-1:0] produce_dir  = arc_run ? helix_dir : line_next_dir;
    // cost class: 0 axis move, 1 diagonal arc move, 2 line iteration
    wire [1:0]    produce_class = arc_run ? {1'b0, arc_next_diagonal} : 2'd2;
    wire          produce_last = arc_run ? arc_ending : line_ending;
    wire [MOVE_W-1:0] produce_entry = {produce_last, produce_class, produce_dir, produce_step};

    function [MOVE_INDEX_W-1:0] move_next;
        input [MOVE_INDEX_W-1:0] index;
        begin
            move_next = (index == MOVE_LAST_INDEX) ? {MOVE_INDEX_W{1'b0}}
                                                   : index + {{(MOVE_INDEX_W-1){1'b0}}, 1'b1};
        end
    endfunction

    always @(posedge clk) begin
        if (produce && !flush) move_mem[move_write_q] <= produce_entry;
    end

    // The head move, which the profile stage's pop decision reads, comes from
    // a register equal to move_mem[move_read_q] while the queue is not empty:
    // on a pop it takes the next entry (or the move produced at that edge
    // when it becomes the head), so no memory read lies in front of the pop.
    reg [MOVE_W-1:0] move_head_q;
    // the head after this edge, with and without a pop
    wire [MOVE_W-1:0] head_after_pop = (move_count_q != MOVE_COUNT_ONE)
                                       ? move_mem[move_next(move_read_q)] : produce_entry;
    wire [MOVE_W-1:0] head_after_wait = (move_count_q == {(MOVE_INDEX_W+1){1'b0}})
                                        ? produce_entry : move_head_q;
    always @(posedge clk) begin
        move_head_q <= stage_pop ? head_after_pop : head_after_wait;
    end
    always @(posedge clk) begin
        if (rst || flush) begin
            move_write_q <= {MOVE_INDEX_W{1'b0}};
            move_read_q <= {MOVE_INDEX_W{1'b0}};
            move_count_q <= {(MOVE_INDEX_W+1){1'b0}};
        end else begin
            if (produce) move_write_q <= move_next(move_write_q);
            if (stage_pop) move_read_q <= move_next(move_read_q);
            if (produce && !stage_pop) move_count_q <= move_count_q + MOVE_COUNT_ONE;
            else if (stage_pop && !produce) move_count_q <= move_count_q - MOVE_COUNT_ONE;
        end
    end
    // move_count_q != 0 as a register beside the count, for the pop
    reg move_valid_q;
    always @(posedge clk) begin
        if (rst || flush) begin
            move_valid_q <= 1'b0;
        end else begin
            move_valid_q <= produce || (move_count_q > MOVE_COUNT_ONE)
                            || (move_valid_q && !stage_pop);
        end
    end

    wire [MOVE_W-1:0] move_head = move_head_q;
    wire              move_valid = move_valid_q;
    wire [NA-1:0]     head_step = move_head[NA-1:0];
    wire [NA-1:0]     head_dir  = move_head[2*NA-1:NA];
    wire [1:0]        head_class = move_head[2*NA+1:2*NA];
    wire              head_last = move_head[2*NA+2];

    // ------------------------------------------------------------------
    // Profile queue: {cont, profile}
    // ------------------------------------------------------------------
    localparam integer PQ_W = PROFILE_W + 1;
    localparam integer PQ_INDEX_W = (PROFILE_DEPTH > 1) ? $clog2(PROFILE_DEPTH) : 1;
    localparam [PQ_INDEX_W:0] PQ_FULL = PROFILE_DEPTH[PQ_INDEX_W:0];
    localparam [PQ_INDEX_W:0] PQ_COUNT_ONE = {{PQ_INDEX_W{1'b0}}, 1'b1};
    localparam [PQ_INDEX_W-1:0] PQ_LAST_INDEX = PROFILE_DEPTH[PQ_INDEX_W-1:0] - 1'b1;

    reg  [PQ_W-1:0]       pq_mem [0:PROFILE_DEPTH-1];
    reg  [PQ_INDEX_W-1:0] pq_write_q, pq_read_q;
    reg  [PQ_INDEX_W:0]   pq_count_q;
    wire                  stage_take;
    wire                  segment_load = accept;
    assign profile_room = (pq_count_q != PQ_FULL);

    function [PQ_INDEX_W-1:0] pq_next;
        input [PQ_INDEX_W-1:0] index;
        begin
            pq_next = (index == PQ_LAST_INDEX) ? {PQ_INDEX_W{1'b0}}
                                               : index + {{(PQ_INDEX_W-1){1'b0}}, 1'b1};
        end
    endfunction

    always @(posedge clk) begin
        if (segment_load && !flush) pq_mem[pq_write_q] <= {pend_cont_q, profile_q};
    end
    always @(posedge clk) begin
        if (rst || flush) begin
            pq_write_q <= {PQ_INDEX_W{1'b0}};
            pq_read_q <= {PQ_INDEX_W{1'b0}};
            pq_count_q <= {(PQ_INDEX_W+1){1'b0}};
        end else begin
            if (segment_load) pq_write_q <= pq_next(pq_write_q);
            if (stage_take) pq_read_q <= pq_next(pq_read_q);
            if (segment_load && !stage_take) pq_count_q <= pq_count_q + PQ_COUNT_ONE;
            else if (stage_take && !segment_load) pq_count_q <= pq_count_q - PQ_COUNT_ONE;
        end
    end
    // pq_count_q != 0 as a register beside the count, for the take
    reg pq_valid_q;
    always @(posedge clk) begin
        if (rst || flush) begin
            pq_valid_q <= 1'b0;
        end else begin
            pq_valid_q <= segment_load || (pq_count_q > PQ_COUNT_ONE)
                          || (pq_valid_q && !stage_take);
        end
    end

    wire [PQ_W-1:0]      pq_head = pq_mem[pq_read_q];
    wire                 pq_valid = pq_valid_q;
    wire [PROFILE_W-1:0] next_profile = pq_head[PROFILE_W-1:0];
    wire                 next_cont = pq_head[PROFILE_W];

    // ------------------------------------------------------------------
    // Profile stage
    // ------------------------------------------------------------------
    // Whether every axis the head move steps is ready for its direction, a
    // register: at each edge it is computed for the head after the edge from
    // the step generators' lookahead, for both outcomes of the pop (a popped
    // move's axes are busy at the next clock), and the pop selects.  It equals
    // the readiness of the head's axes on every clock, so the pop is a
    // function of flip-flops (halfpoint.spec.stepgen StepGenModel.lookahead).
    // the generators' own readiness is not needed by the logic; the core's
    // tests check steps_ready_q against it on every clock
    wire [NA-1:0] unused_ready_pos, unused_ready_neg, stepgen_busy;
    wire [NA-1:0] stepgen_direction, next_ready_same, next_ready_reverse;
    wire [NA-1:0] pop_step = head_after_pop[NA-1:0];
    wire [NA-1:0] pop_dir  = head_after_pop[2*NA-1:NA];
    wire [NA-1:0] wait_step = head_after_wait[NA-1:0];
    wire [NA-1:0] wait_dir  = head_after_wait[2*NA-1:NA];
    // each axis ready at the next clock for a move in direction move_dir: the
    // lookahead for DIR's present level, or for a reversal.  Every signal it
    // reads is an argument: Icarus re-evaluates a continuous assignment that
    // calls a function only when the arguments change
    function [NA-1:0] ready_next(
        input [NA-1:0] move_dir,
        input [NA-1:0] present_dir,
        input [NA-1:0] ready_same,
        input [NA-1:0] ready_reverse
    );
        ready_next = (~(move_dir ^ present_dir) & ready_same)
                     | ((move_dir ^ present_dir) & ready_reverse);
    endfunction
    // a popped move's axes are busy at the next clock
    wire [NA-1:0] pop_axis_ready = ~head_step
                                   & ready_next(pop_dir, stepgen_direction,
                                                next_ready_same, next_ready_reverse);
    wire [NA-1:0] wait_axis_ready = ready_next(wait_dir, stepgen_direction,
                                               next_ready_same, next_ready_reverse);
    wire          ready_after_pop = &(~pop_step | pop_axis_ready);
    wire          ready_after_wait = &(~wait_step | wait_axis_ready);
    reg           steps_ready_q;
    always @(posedge clk) begin
        if (rst) begin
            steps_ready_q <= 1'b1;     // every generator is ready after reset
        end else begin
            steps_ready_q <= stage_pop ? ready_after_pop : ready_after_wait;
        end
    end
    wire          steps_ready = steps_ready_q;
    wire          stage_holding, stage_busy;
    wire          unused_holding = stage_holding;

    halfpoint_profile #(
        .W   (W),
        .DIV (DIV)
    ) u_profile (
        .clk            (clk),
        .rst            (rst),
        .abort_now      (abort_q),
        .head_valid     (move_valid),
        .head_class     (head_class),
        .head_last      (head_last),
        .ready          (steps_ready),
        .next_valid     (pq_valid),
        .next_v_cruise  (next_profile[31:0]),
        .next_v_exit    (next_profile[63:32]),
        .next_accel     (next_profile[97:64]),
        .next_line_cost (next_profile[115:98]),
        .next_d_exit    (next_profile[116 +: DW]),
        .next_d_stop    (next_profile[116 + DW +: DW]),
        .hold           (hold),
        .stop           (stop_q || flush_q),
        .feed_override  (feed_override),
        .pop            (stage_pop),
        .take           (stage_take),
        .stopped        (stage_stopped),
        .holding        (stage_holding),
        .speed          (speed),
        .dry            (dry),
        .busy           (stage_busy)
    );

    assign flush = abort_q || flush_q;
    assign downstream_idle = !arc_busy && !line_busy && !move_valid && !pq_valid && !stage_busy;

    // ------------------------------------------------------------------
    // Spindle, laser and coolant outputs
    // ------------------------------------------------------------------
    halfpoint_outputs #(
        .PWM_BITS (PWM_BITS)
    ) u_outputs (
        .clk             (clk),
        .rst             (rst),
        .load            (output_load),
        .load_power      (head_payload[payload_bit(`HALFPOINT_CMD_OUTPUT_POWER_LSB)
                                       +: `HALFPOINT_CMD_OUTPUT_POWER_WIDTH]),
        .load_enable     (head_payload[payload_bit(`HALFPOINT_CMD_OUTPUT_ENABLE_LSB)]),
        .load_reverse    (head_payload[payload_bit(`HALFPOINT_CMD_OUTPUT_REVERSE_LSB)]),
        .load_laser      (head_payload[payload_bit(`HALFPOINT_CMD_OUTPUT_LASER_LSB)]),
        .load_dynamic    (head_payload[payload_bit(`HALFPOINT_CMD_OUTPUT_DYNAMIC_LSB)]),
        .load_mist       (head_payload[payload_bit(`HALFPOINT_CMD_OUTPUT_MIST_LSB)]),
        .load_flood      (head_payload[payload_bit(`HALFPOINT_CMD_OUTPUT_FLOOD_LSB)]),
        .off             (flush),
        .speed           (speed),
        .take            (stage_take),
        .take_v_cruise   (next_profile[31:0]),
        .take_set_power  (next_profile[POWER_AT]),
        .take_power      (next_profile[POWER_AT + 1 +: POWER_W]),
        .spindle_enable  (spindle_enable),
        .spindle_reverse (spindle_reverse),
        .pwm             (spindle_pwm),
        .coolant_mist    (coolant_mist),
        .coolant_flood   (coolant_flood),
        .duty            (unused_duty)
    );
    // the move made at this edge (none on a flush edge)
    wire go = stage_pop && !flush;

    // CONT of the stage's current segment
    reg stage_cont_q;
    always @(posedge clk) begin
        if (rst || flush) begin
            stage_cont_q <= 1'b0;
        end else if (stage_take) begin
            stage_cont_q <= next_cont;
        end else if (stage_pop && head_last) begin
            stage_cont_q <= 1'b0;
        end
    end

    // ------------------------------------------------------------------
    // STEP/DIR generators and positions
    // ------------------------------------------------------------------
    genvar a;
    generate
        for (a = 0; a < NA; a = a + 1) begin : g_axis
            halfpoint_stepgen #(
                .TW (TW)
            ) u_stepgen (
                .clk           (clk),
                .rst           (rst),
                .cfg_steplen   (cfg_steplen[a*TW +: TW]),
                .cfg_stepspace (cfg_stepspace[a*TW +: TW]),
                .cfg_dirsetup  (cfg_dirsetup[a*TW +: TW]),
                .cfg_dirhold   (cfg_dirhold[a*TW +: TW]),
                .cfg_step_inv  (cfg_step_inv[a]),
                .cfg_dir_inv   (cfg_dir_inv[a]),
                .req           (go && head_step[a]),
                .req_dir       (head_dir[a]),
                .ready_pos     (unused_ready_pos[a]),
                .ready_neg     (unused_ready_neg[a]),
                .direction          (stepgen_direction[a]),
                .next_ready_same    (next_ready_same[a]),
                .next_ready_reverse (next_ready_reverse[a]),
                .busy          (stepgen_busy[a]),
                .step_pin      (step_pin[a]),
                .dir_pin       (dir_pin[a])
            );
            always @(posedge clk) begin
                if (rst) begin
                    pos[a*W +: W] <= {W{1'b0}};
                end else if (go && head_step[a]) begin
                    // + 1 or + (2^W - 1): one adder, not an adder and a subtractor
                    pos[a*W +: W] <= pos[a*W +: W] + {{(W-1){!head_dir[a]}}, 1'b1};
                end
            end
        end
    endgenerate

    // ------------------------------------------------------------------
    // Status
    // ------------------------------------------------------------------
    assign busy = (count_q != {(INDEX_W+1){1'b0}}) || in_flight_q || arc_busy || line_busy ||
                  move_valid || pq_valid || stage_busy || (|stepgen_busy);

    // the arc unit's reject codes 1, 2, 3
    wire [CODE_W-1:0] arc_code = (arc_error == 2'd1) ? `HALFPOINT_E_ARC_RADIUS
                               : (arc_error == 2'd2) ? `HALFPOINT_E_ARC_RANGE
                               : `HALFPOINT_E_ARC_END;
    wire [CODE_W-1:0] dispatch_code = head_bad_opcode ? `HALFPOINT_E_OPCODE
                                    : head_bad_fit ? `HALFPOINT_E_FIELD
                                    : head_bad_helix ? `HALFPOINT_E_HELIX
                                    : head_bad_profile ? `HALFPOINT_E_PROFILE_FIELD
                                    : `HALFPOINT_E_PROFILE;

    always @(posedge clk) begin
        if (rst) begin
            move <= 1'b0;
            err <= 1'b0;
            err_code <= `HALFPOINT_E_NONE;
            underrun <= 1'b0;
        end else begin
            move <= go;
            err  <= !flush && (dispatch_error || arc_reject || line_reject ||
                               helix_count_error);
            if (!flush) begin
                // an arc's move count error wins over a reject at the same edge
                if (helix_count_error) begin
                    err_code <= `HALFPOINT_E_HELIX_COUNT;
                end else if (dispatch_error) begin
                    err_code <= dispatch_code;
                end else if (arc_reject) begin
                    err_code <= arc_code;
                end else if (line_reject) begin
                    err_code <= `HALFPOINT_E_OPCODE;
                end
                if (stage_pop && head_last && stage_cont_q && !stage_take) underrun <= 1'b1;
            end
        end
    end

`ifdef FORMAL
    // ========================================================================
    // Formal properties (SymbiYosys: formal/halfpoint_core.sby, run by
    // python -m halfpoint.flows.formal).  Verilator, Icarus and the cocotb
    // builds do not define FORMAL, so they see the module above unchanged.
    // ========================================================================
    // The .sby reads this file and the step generators' with FORMAL (the
    // generators' own proven properties then hold here too, and their
    // invariants help the induction); the arc, helix and outputs modules
    // are read without it: their inputs come from this module, and their
    // properties assume things of their inputs that are proven separately.
    // The line unit and the profile stage are read with it in the composed
    // proofs (compose_*), their assumptions about their inputs asserted.
    // Every input is free on every clock (rst high on the first) except the
    // pin polarities, which are setup values: constant.
    // Asserted (a_* the contract, i_* invariants for the induction):
    //   queue    a beat is pushed only while the queue has room; the
    //            dispatcher pops only a present command, each pop for exactly
    //            one reason (a reject, a no-op, a profile loaded, handed to
    //            the arc unit or to the line unit, an OUTPUT loaded); the
    //            commands pop in the order they were pushed, each exactly once
    //            and unchanged (a beat chosen freely at its push, f_choose, is
    //            followed through the queue: it pops exactly when the commands
    //            ahead of it have popped, with the entry decoded from it), and
    //            only a flush (abort_now or a stop at rest) drops any;
    //   steps    steps_ready_q, the registered readiness the pop reads, is on
    //            every clock the readiness of the head move's axes; so every
    //            step request is taken by its generator (none dropped), and
    //            each axis's position equals the steps on its pins: the sum
    //            of STEP pulses begun (+1 with DIR positive, -1 negative),
    //            plus one for a step taken whose pulse waits for dirsetup.
    // F_UNITS (bounded checks only) adds what rests on the units' own
    // behaviour: a command handed to a unit is held by it, and by no other,
    // until it is loaded or rejected, validated within W + 5 clocks, and a
    // unit loads or rejects only the command handed to it (none lost,
    // duplicated or run by the wrong unit between the dispatcher and the
    // units).  F_REST (the bounded check, and the composed proofs, which
    // read the units and the profile stage with their properties and turn
    // their assumptions about their inputs into assertions): every profile in
    // the queue, in force and in the profile queue obeys the profile stage's
    // rules; each unit holds, loads or rejects only the command in flight
    // handed to it (the arc unit's part assumed unless F_ARC_COMPOSED, the
    // composed proofs, or F_UNITS); once the profile stage holds at rest under
    // a hold (from the hold's second clock), no step is requested while the
    // hold stays high.
    // F_LINE_COST_BLU (bounded checks only) assumes PROFILE line costs of at
    // least one BLU.
    reg f_past_valid;
    initial f_past_valid = 1'b0;
    always @(posedge clk)
        f_past_valid <= 1'b1;
    always @(*)
        if (!f_past_valid)
            assume(rst);
    always @(posedge clk)
        if (f_past_valid) begin
            assume(cfg_step_inv == $past(cfg_step_inv));
            assume(cfg_dir_inv == $past(cfg_dir_inv));
        end

`ifdef F_LINE_COST_BLU
    // a PROFILE's line cost of at least one BLU (or 0, an arc's): for the
    // bounded check only (not a rule of the core: a Z line is cheaper when Z's
    // BLU is finer than X's), as in the profile stage's own bounded check,
    // whose step 9 ran past 10 minutes without it
    wire [17:0] f_line_cost = cmd[`HALFPOINT_CMD_PROFILE_LINE_COST_LSB +:
                                  `HALFPOINT_CMD_PROFILE_LINE_COST_WIDTH];
    always @(*)
        if (s_axis_tvalid && is_profile)
            assume(f_line_cost == 18'd0 || f_line_cost >= 18'd65536);
`endif

    // ---- queue ----
    always @(*) begin
        if (f_past_valid) begin
            i_count: assert(count_q <= QUEUE_FULL &&
                            count_q[INDEX_W-1:0] == write_index_q - read_index_q);
            a_push_room: assert(!push || count_q != QUEUE_FULL);
            a_pop_present: assert(!pop || count_q != {(INDEX_W+1){1'b0}});
            a_pop_one_reason: assert(!pop || $onehot({dispatch_error,
                                                    head_ok && head_nop && !head_bad,
                                                    profile_load, arc_take, line_take,
                                                    output_load}));
            a_no_pop_on_flush: assert(!(pop && flush));
        end
    end
    // a decoded entry's flags are consistent: one kind (arc, line, profile,
    // OUTPUT or none), CW only for an arc, each error flag only after the
    // checks before it passed, no-op only for a good line
    function f_flags_ok;
        input [FLAGS_W-1:0] flags;
        begin
            f_flags_ok = ($countones({flags[0], flags[2], flags[7], flags[9]}) <= 1) &&
                         (!flags[1] || flags[0]) &&
                         (!flags[5] || !flags[4]) &&
                         (!flags[10] || (!flags[4] && !flags[5] && flags[0])) &&
                         (!flags[8] || (!flags[4] && flags[7])) &&
                         (!flags[6] || (!flags[4] && !flags[5] && flags[2]));
        end
    endfunction
    always @(*)
        if (f_past_valid)
            a_decode: assert(f_flags_ok(in_flags));
`ifdef F_REST
    // a profile that obeys the profile stage's rules (F_REST below)
    function f_profile_ok;
        input [PROFILE_W-1:0] profile;
        begin
            f_profile_ok = (profile[97:64] != 34'd0) && (profile[63:32] <= profile[31:0]) &&
                           (profile[116 + DW +: DW] <= profile[116 +: DW]);
        end
    endfunction
`endif
    // the flags register is the head's flags, and each queued entry's flags
    // copy is its entry's flags, which are consistent (and, F_REST, a good
    // PROFILE entry obeys the profile stage's rules)
    genvar fi;
    generate
        for (fi = 0; fi < DEPTH; fi = fi + 1) begin : g_f_slot
            wire [INDEX_W-1:0] f_offset = fi[INDEX_W-1:0] - read_index_q;
            wire f_queued = ({1'b0, f_offset} < count_q);
            always @(*)
                if (f_past_valid && f_queued)
                    assert(flags_mem[fi] == queue_mem[fi][FLAGS_W-1:0] &&
                           f_flags_ok(flags_mem[fi]));
`ifdef F_REST
            always @(*)
                if (f_past_valid && f_queued && flags_mem[fi][7] && !flags_mem[fi][8] &&
                    !flags_mem[fi][4])
                    assert(f_profile_ok(profile_of(queue_mem[fi][ENTRY_W-1:FLAGS_W])));
`endif
        end
    endgenerate
    always @(*)
        if (f_past_valid && count_q != {(INDEX_W+1){1'b0}})
            i_head_flags: assert(head_flags_q == flags_mem[read_index_q]);

    // One beat, chosen freely (f_choose) when pushed while none is followed,
    // is followed through the queue: f_ahead_q commands were ahead of it at
    // its push, one fewer after each pop; it must pop exactly when none is
    // ahead, with the entry decoded from it at its push (so every command
    // pops once, in order, unchanged), unless a flush drops the queue.
    (* anyseq *) reg f_choose;
    reg                f_follow_q;
    reg  [INDEX_W:0]   f_ahead_q;
    reg  [INDEX_W-1:0] f_slot_q;
    reg  [ENTRY_W-1:0] f_entry_q;
    wire [INDEX_W:0]   f_count_after_pop = count_q - (pop ? COUNT_ONE : {(INDEX_W+1){1'b0}});
    always @(posedge clk) begin
        if (rst || flush) begin
            f_follow_q <= 1'b0;
        end else if (!f_follow_q) begin
            if (push && f_choose) begin
                f_follow_q <= 1'b1;
                f_ahead_q <= f_count_after_pop;
                f_slot_q <= write_index_q;
                f_entry_q <= in_entry;
            end
        end else if (pop) begin
            if (f_ahead_q == {(INDEX_W+1){1'b0}}) begin
                f_follow_q <= 1'b0;
            end else begin
                f_ahead_q <= f_ahead_q - COUNT_ONE;
            end
        end
    end
    always @(*) begin
        if (f_past_valid && f_follow_q) begin
            i_follow_ahead: assert(f_ahead_q < count_q);
            i_follow_slot: assert(f_slot_q == read_index_q + f_ahead_q[INDEX_W-1:0]);
            i_follow_stored: assert(queue_mem[f_slot_q] == f_entry_q);
            if (pop && f_ahead_q == {(INDEX_W+1){1'b0}})
                a_pop_in_order: assert({head_payload, head_flags_q} == f_entry_q);
        end
    end

    // ---- steps ----
    wire [NA-1:0] f_ready_dir;         // each axis ready for the head move's direction
    wire [NA-1:0] f_active;            // STEP active (pin level with polarity undone)
    wire [NA-1:0] f_positive;          // DIR positive
    genvar fa;
    generate
        for (fa = 0; fa < NA; fa = fa + 1) begin : g_f_axis
            assign f_ready_dir[fa] = head_dir[fa] ? unused_ready_pos[fa] : unused_ready_neg[fa];
            assign f_active[fa] = step_pin[fa] ^ cfg_step_inv[fa];
            assign f_positive[fa] = dir_pin[fa] ^ cfg_dir_inv[fa];
            // the steps on the pins: pulses begun before this clock, this
            // clock's if one begins, and a step taken that waits for dirsetup
            // (the generator busy with STEP inactive)
            reg          f_active_q;
            reg  [W-1:0] f_pins_q;
            wire [W-1:0] f_sign = {{(W-1){!f_positive[fa]}}, 1'b1};    // + 1 or - 1
            wire         f_begins = f_active[fa] && !f_active_q;
            wire         f_waits = stepgen_busy[fa] && !f_active[fa];
            wire [W-1:0] f_pins = f_pins_q + (f_begins ? f_sign : {W{1'b0}});
            always @(posedge clk) begin
                if (rst) begin
                    f_active_q <= 1'b0;
                    f_pins_q <= {W{1'b0}};
                end else begin
                    f_active_q <= f_active[fa];
                    f_pins_q <= f_pins;
                end
            end
            always @(*)
                if (f_past_valid) begin
                    assert(!(go && head_step[fa]) || f_ready_dir[fa]);
                    assert(pos[fa*W +: W] ==
                                       f_pins + (f_waits ? f_sign : {W{1'b0}}));
                end
        end
    endgenerate
    always @(*)
        if (f_past_valid)
            i_steps_ready: assert(steps_ready_q == &(~head_step | f_ready_dir));

    // ---- between the dispatcher and the units ----
    always @(*)
        if (f_past_valid)
            a_one_in_flight: assert(!(arc_take || line_take) || !in_flight_q);
    // the unit the command in flight was handed to (1: the arc unit)
    reg        f_to_arc_q;
    always @(posedge clk)
        if (arc_take || line_take) f_to_arc_q <= arc_take;
`ifdef F_UNITS
    // the clocks the command in flight has been held without being validated
    reg  [5:0] f_wait_q;
    always @(posedge clk) begin
        if (rst || flush || !in_flight_q || arc_pending || line_pending) begin
            f_wait_q <= 6'd0;
        end else if (f_wait_q != 6'd63) begin
            f_wait_q <= f_wait_q + 6'd1;
        end
    end
    always @(*) begin
        if (f_past_valid) begin
            // the command in flight is held by its unit (whose s_ready is low
            // while it holds one; its reject is registered: on that clock the
            // unit is empty again) and by no other
            if (in_flight_q) begin
                a_held_by_its_unit: assert(f_to_arc_q ? (!arc_s_ready || arc_reject)
                                                      : (!line_s_ready || line_reject));
                a_not_by_the_other: assert(f_to_arc_q ? !line_pending && !line_loading &&
                                                         !line_reject
                                                       : !arc_pending && !arc_loading &&
                                                         !arc_reject);
                // validated within the unit's latency (W + 5 clocks, NA + 2)
                a_validated_in_time: assert(f_wait_q <= W + 5);
            end
            // that a unit pends, loads or rejects only the command in flight
            // handed to it is F_REST's arc_handed and a_line_handed (the
            // F_UNITS task defines F_REST too)
        end
    end
`endif
`ifdef F_REST
    // ---- profiles: the profile stage's input rules, kept from the input ----
    // (the composed proofs turn the profile stage's assumptions about its
    // next profile, f_rule_*, into assertions; these invariants carry the
    // input's check, E_PROFILE_FIELD, through the queue (g_f_slot above),
    // the profile in force and the profile queue)
    wire [PQ_INDEX_W+1:0] f_pq_sum = {1'b0, pq_read_q} + {1'b0, pq_count_q};
    wire [PQ_INDEX_W:0]   f_pq_wrap = (f_pq_sum >= PROFILE_DEPTH)
                                      ? f_pq_sum - PROFILE_DEPTH : f_pq_sum;
    genvar fp;
    generate
        for (fp = 0; fp < PROFILE_DEPTH; fp = fp + 1) begin : g_f_pq_slot
            // the slot's place behind the read index, modulo PROFILE_DEPTH (which
            // need not be a power of two)
            wire [PQ_INDEX_W:0] f_slot = fp;
            wire [PQ_INDEX_W:0] f_offset = (f_slot >= {1'b0, pq_read_q})
                                           ? f_slot - {1'b0, pq_read_q}
                                           : f_slot + PROFILE_DEPTH - {1'b0, pq_read_q};
            wire f_queued = (f_offset < pq_count_q);
            always @(*)
                if (f_past_valid && f_queued)
                    assert(f_profile_ok(pq_mem[fp][PROFILE_W-1:0]));
        end
    endgenerate
    // a unit holds a validated command only while it is the one handed to it
    // and in flight, and rejects only that one before it was validated.  The
    // composed proofs (F_ARC_COMPOSED) read both units with their properties
    // and prove it: a unit's slot holds a command only while the unit is not
    // ready, and i_line_in_flight / i_arc_in_flight tie that to the command
    // in flight (the arc unit's protocol properties, F_PROTOCOL_ONLY, are
    // read: handshake, validation, frames; its run stage's invariants are
    // its own tasks').  prove_na2 and prove_na3, which read the arc unit
    // without its properties, assume its part (its own handshake proof shows
    // it of its slot); bmc_na2 (F_UNITS) checks it bounded.
`ifdef F_UNITS
`define F_ARC_CONTRACT assert
`elsif F_ARC_COMPOSED
`define F_ARC_CONTRACT assert
`else
`define F_ARC_CONTRACT assume
`endif
    always @(*)
        if (f_past_valid) begin
            arc_handed: `F_ARC_CONTRACT(!(arc_pending || arc_loading || arc_reject) ||
                                        (in_flight_q && f_to_arc_q));
            arc_reject_unvalidated: `F_ARC_CONTRACT(!arc_reject || !accepted_q);
`ifdef F_ARC_COMPOSED
            // the arc unit is busy with a command only while it is the one in
            // flight, handed to it
            if (!flush)
                i_arc_in_flight: assert(arc_s_ready || (in_flight_q && f_to_arc_q));
`endif
            // the line unit is busy with a command only while it is the one in
            // flight, handed to it
            if (!flush)
                i_line_in_flight: assert(line_s_ready || (in_flight_q && !f_to_arc_q));
            a_line_handed: assert(!(line_pending || line_loading || line_reject) ||
                                  (in_flight_q && !f_to_arc_q));
            a_line_reject_unvalidated: assert(!line_reject || !accepted_q);
        end
`undef F_ARC_CONTRACT
    always @(*)
        if (f_past_valid) begin
            if (profile_valid_q)
                i_profile_in_force: assert(f_profile_ok(profile_q));
            if (in_flight_q)
                i_in_flight_profile: assert(profile_valid_q);
            i_pq_valid: assert(pq_valid_q == (pq_count_q != {(PQ_INDEX_W+1){1'b0}}));
            // the profile queue's count and indices; room for the profile of
            // the command in flight until it enters
            i_pq_count: assert(pq_count_q <= PQ_FULL && pq_read_q <= PQ_LAST_INDEX &&
                               pq_write_q <= PQ_LAST_INDEX);
            i_pq_write: assert({1'b0, pq_write_q} == f_pq_wrap);
            if (in_flight_q && !accepted_q)
                i_pq_room: assert(pq_count_q != PQ_FULL);
            if (accepted_q)
                i_accepted: assert(in_flight_q && (arc_pending || line_pending));
        end
    // once the profile stage holds at rest under a hold, from the hold's
    // second clock on, no step is requested while the hold stays high (on
    // the hold's first clock the profile stage's target is the one registered
    // before it, and the speed may still rise by a step at its edge)
    reg f_rest_q, f_hold_q;
    always @(posedge clk) begin
        f_hold_q <= !rst && hold;
        f_rest_q <= !rst && hold && ((stage_holding && f_hold_q) || f_rest_q);
    end
    always @(*)
        if (f_past_valid && f_rest_q) begin
            i_rest_speed: assert(speed == 38'd0);
            if (hold)
                a_rest_kept: assert(!go);
        end
`endif

    // ---- reachable ----
    always @(*) begin
        if (f_past_valid && !rst) begin
            c_step_x: cover(go && head_step[0]);
            c_step_y: cover(go && head_step[1]);
            c_followed_arc: cover(f_follow_q && arc_take && f_ahead_q == 0);
            c_followed_line: cover(f_follow_q && line_take && f_ahead_q == 0);
            c_holding: cover(stage_holding && hold && move_valid);
            c_full: cover(count_q == QUEUE_FULL);
        end
    end
`endif

endmodule

`default_nettype wire
