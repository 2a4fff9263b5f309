// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// ============================================================================
// halfpoint_uart_top: example board top -- the motion core driven over a
// serial port, STEP/DIR/ENABLE to pins
// ============================================================================
// The top that constraints/ maps onto three boards (iCE40-HX8K Breakout Board:
// constraints/hx8k_breakout.pcf; ULX3S with LFE5U-25F: constraints/
// ulx3s.lpf; iCEBreaker with iCE40UP5K: constraints/icebreaker.pcf).  A
// host (`halfpoint send`) streams commands (model/halfpoint/
// spec/encoding.py) over the board's USB serial port in the frames of the
// serial link (model/halfpoint/spec/link.py, halfpoint_uart_cmd): each
// COMMAND is acknowledged when the core takes it, so the core's queue stays
// full; the host polls the status (positions, queue level, flags), and holds,
// resumes and stops the machine (the core's hold and stop inputs).  A
// rejected command stops the machine (controlled stop) until the host's STOP.
//
//   step[i], dir[i]  STEP/DIR of axis i (timing below, active high)
//   enable_n         low while the drivers may move: high during reset and
//                    while the abort button is held
//   led              [0] busy, [1] a command was rejected (sticky),
//                    [2] underrun (sticky), [3] abort held,
//                    [7:4] queue level (saturated at 15)
//   btn_reset        resets everything (position counters included)
//   btn_abort        stops the motion at once and drops the queue (core's
//                    abort_now) while held
//
// Reset: a power-on reset of 16 clocks from the configuration's initial
// values (the only initialised registers of the project), OR-ed with the
// synchronised reset button, gives the synchronous active-high reset the
// modules use.
//
// Parameters: see the comment above each (an illegal value stops
// elaboration).
// ============================================================================
`include "halfpoint_cmd.vh"

module halfpoint_uart_top #(
    // board clock in Hz (the core runs on it directly)
    parameter integer CLK_HZ         = 12000000,
    // serial bit rate; CLK_HZ / BAUD >= 8
    parameter integer BAUD           = 115200,
    // the core's axes (2..6), see halfpoint_core
    parameter integer NA             = 3,
    // the core's coordinate and position width, 8..32
    parameter integer W              = 32,
    // the core's queue depth, a power of two, 2..256
    parameter integer DEPTH          = 16,
    // STEP/DIR timing in clocks for every axis, 1..65535 each
    parameter integer STEPLEN        = 24,
    parameter integer STEPSPACE      = 24,
    parameter integer DIRSETUP       = 24,
    parameter integer DIRHOLD        = 24,
    // 1 when the buttons pull the pin low when pressed, else 0
    parameter integer BTN_ACTIVE_LOW = 0,
    // the core's profile tick, 2^DIV clocks: the host's profile.choose_div(CLK_HZ)
    // (10 at 12 MHz, 11 at 25 MHz); the machine file's clock_hz must be CLK_HZ
    parameter integer DIV            = 10,
    // bit times of silence after which the serial port refuses a partial frame
    parameter integer IDLE_BITS      = 40
) (
    input  wire          clk,

    /*
     * Buttons (asynchronous; synchronised here)
     */
    input  wire          btn_reset,
    input  wire          btn_abort,

    /*
     * Serial port to the host
     */
    input  wire          uart_rx,
    output wire          uart_tx,

    /*
     * STEP/DIR/ENABLE to the drivers
     */
    output wire [NA-1:0] step,
    output wire [NA-1:0] dir,
    output wire          enable_n,

    /*
     * Spindle (or laser) and coolant, set by OUTPUT commands (M3/M4/M5, S, M7/M8/M9)
     */
    output wire          spindle_enable,
    output wire          spindle_reverse,
    output wire          spindle_pwm,
    output wire          coolant_mist,
    output wire          coolant_flood,

    /*
     * Status LEDs
     */
    output wire [7:0]    led
);

    localparam integer TW = 16;     // width of the core's timing settings

    generate
        if (STEPLEN < 1 || STEPLEN > 65535 || STEPSPACE < 1 || STEPSPACE > 65535 ||
            DIRSETUP < 1 || DIRSETUP > 65535 || DIRHOLD < 1 || DIRHOLD > 65535)
        begin : g_bad_timing
            halfpoint_uart_top_illegal_parameter_step_timing_must_be_1_to_65535 u_bad ();
        end
        if (BTN_ACTIVE_LOW != 0 && BTN_ACTIVE_LOW != 1) begin : g_bad_btn
            halfpoint_uart_top_illegal_parameter_BTN_ACTIVE_LOW_must_be_0_or_1 u_bad ();
        end
    endgenerate

    // ------------------------------------------------------------------ reset
    reg [4:0] power_on_count_q;     // counts to 16 after configuration
    reg [1:0] reset_button_q;       // synchroniser
    reg [1:0] abort_button_q;       // synchroniser
    reg       rst_q;

    // configuration values of the power-on reset (FPGA flip-flops take them)
    initial begin
        power_on_count_q = 5'd0;
        reset_button_q   = 2'b00;
        abort_button_q   = 2'b00;
        rst_q            = 1'b1;
    end
    wire      reset_pressed = btn_reset ^ (BTN_ACTIVE_LOW != 0);
    wire      abort_pressed = btn_abort ^ (BTN_ACTIVE_LOW != 0);

    always @(posedge clk) begin
        reset_button_q <= {reset_button_q[0], reset_pressed};
        abort_button_q <= {abort_button_q[0], abort_pressed};
        if (!power_on_count_q[4]) begin
            power_on_count_q <= power_on_count_q + 1'b1;
        end
        rst_q <= !power_on_count_q[4] || reset_button_q[1];
    end

    // ----------------------------------------------------------- serial port
    wire                               cmd_valid;
    wire                               cmd_ready;
    wire [`HALFPOINT_CMD_BITS-1:0]      cmd_data;
    wire                               err;
    wire [`HALFPOINT_ERR_CODE_BITS-1:0] err_code;
    wire [NA*W-1:0]                    pos;
    wire                               busy;
    wire [$clog2(DEPTH):0]             level;
    wire                               underrun;
    wire                               dry;
    wire                               hold;
    wire                               stop;

    halfpoint_uart_cmd #(
        .CLK_HZ    (CLK_HZ),
        .BAUD      (BAUD),
        .IDLE_BITS (IDLE_BITS),
        .NA        (NA),
        .W         (W),
        .DEPTH     (DEPTH),
        .DIV       (DIV)
    ) u_uart (
        .clk           (clk),
        .rst           (rst_q),
        .rx            (uart_rx),
        .tx            (uart_tx),
        .m_axis_tvalid (cmd_valid),
        .m_axis_tready (cmd_ready),
        .m_axis_tdata  (cmd_data),
        .cmd_err       (err),
        .cmd_err_code  (err_code),
        .core_pos      (pos),
        .core_level    (level),
        .core_busy     (busy),
        .core_underrun (underrun),
        .core_dry      (dry),
        .core_abort    (abort_button_q[1]),
        .core_hold     (hold),
        .core_stop     (stop)
    );

    // ------------------------------------------------------------ motion core
    localparam [31:0] STEPLEN_32   = STEPLEN;
    localparam [31:0] STEPSPACE_32 = STEPSPACE;
    localparam [31:0] DIRSETUP_32  = DIRSETUP;
    localparam [31:0] DIRHOLD_32   = DIRHOLD;
    wire [TW-1:0] steplen_setting   = STEPLEN_32[TW-1:0];
    wire [TW-1:0] stepspace_setting = STEPSPACE_32[TW-1:0];
    wire [TW-1:0] dirsetup_setting  = DIRSETUP_32[TW-1:0];
    wire [TW-1:0] dirhold_setting   = DIRHOLD_32[TW-1:0];

    wire        move;
    wire [37:0] unused_speed;

    halfpoint_core #(
        .NA    (NA),
        .W     (W),
        .DEPTH (DEPTH),
        .TW    (TW),
        .DIV   (DIV)
    ) u_core (
        .clk           (clk),
        .rst           (rst_q),
        .s_axis_tvalid (cmd_valid),
        .s_axis_tready (cmd_ready),
        .s_axis_tdata  (cmd_data),
        .cfg_steplen   ({NA{steplen_setting}}),
        .cfg_stepspace ({NA{stepspace_setting}}),
        .cfg_dirsetup  ({NA{dirsetup_setting}}),
        .cfg_dirhold   ({NA{dirhold_setting}}),
        .cfg_step_inv  ({NA{1'b0}}),
        .cfg_dir_inv   ({NA{1'b0}}),
        .feed_override (8'd128),
        .hold          (hold),
        .stop          (stop),
        .abort_now     (abort_button_q[1]),
        .step_pin      (step),
        .dir_pin       (dir),
        .pos           (pos),
        .move          (move),
        .busy          (busy),
        .queue_level   (level),
        .err           (err),
        .err_code      (err_code),
        .underrun      (underrun),
        .dry           (dry),
        .speed         (unused_speed),
        .spindle_enable  (spindle_enable),
        .spindle_reverse (spindle_reverse),
        .spindle_pwm     (spindle_pwm),
        .coolant_mist    (coolant_mist),
        .coolant_flood   (coolant_flood)
    );

    // move and speed are for a user's own logic (a DRO, a probe latch)
    wire unused_move = move ^ (^unused_speed);

    // ----------------------------------------------------------------- status
    reg       err_seen_q;
    reg [3:0] level_q;
    wire [31:0] level_wide = {{(31 - $clog2(DEPTH)){1'b0}}, level};
    always @(posedge clk) begin
        if (rst_q) begin
            err_seen_q <= 1'b0;
            level_q    <= 4'd0;
        end else begin
            if (err) begin
                err_seen_q <= 1'b1;
            end
            level_q <= (level_wide > 32'd15) ? 4'd15 : level_wide[3:0];
        end
    end

    assign enable_n = rst_q | abort_button_q[1];
    assign led = {level_q, abort_button_q[1], underrun, err_seen_q, busy};

endmodule

`default_nettype wire
