// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// ============================================================================
// halfpoint_uart_cmd: the serial link of a board top -- UART 8N1 frames in,
// 256-bit AXI4-Stream commands to the motion core out, replies back: receipt,
// taken, refusals, status (positions, queue level, flags), identification;
// feed hold, resume and a controlled stop as commands
// ============================================================================
// The protocol is defined once, in model/halfpoint/spec/link.py (its
// docstring is the full description); its constants come from the generated
// rtl/halfpoint_link.vh.  In short:
//
//   host -> board  [opcode] [payload] [CRC-8 of both]
//       COMMAND (32-byte command word, little-endian), STATUS, HOLD, RESUME,
//       STOP, IDENT
//   board -> host  RECEIVED (a whole frame, good check), TAKEN (the core took
//       the waiting command), NAK + reason (refused, no effect), STATUS and
//       IDENT replies (first byte, payload, CRC-8)
//
// One command word waits here for the core (m_axis); the host sends the next
// COMMAND after the TAKEN of the previous one, so the core's queue stays full
// and the link never overruns it.  Other frames are taken at any time.  A line
// error (bad check, bad stop bit, unknown opcode, a frame left unfinished)
// discards the frame and is reported (NAK) once the line has been quiet for
// IDLE_BITS bit times, so the host resends the frame whole.
//
// A command the core rejects (cmd_err) latches FAULT with the command's index
// (commands taken since reset, minus the queue level, minus one: the core
// rejects at its queue head, in order) and code, asserts core_stop, drops a
// waiting command (NAK STOPPED) and refuses COMMAND frames until a STOP frame.
// STOP clears FAULT and the hold, drops a waiting command, and asserts
// core_stop until the core is at rest and empty (busy low, queue empty).
//
// Receiver: rx goes through a two-flip-flop synchroniser; a start bit is
// confirmed at its middle, data bits are sampled at their middles, a low
// stop bit is a framing error.  Transmitter: one reply at a time, whole; when
// several wait the order is NAK (line), RECEIVED, NAK (stopped), TAKEN,
// STATUS, IDENT.  A STATUS reply's values are sampled when it starts.
//
// Parameters: see the comment above each (an illegal value stops
// elaboration).
//
// Reset: synchronous, active high; clears the frame in progress, the waiting
// word, the replies, hold, stop, FAULT and the count of commands taken
// (tx idles high).
// ============================================================================
`include "halfpoint_cmd.vh"
`include "halfpoint_link.vh"

module halfpoint_uart_cmd #(
    // clock frequency in Hz (reported in the IDENT reply), 1..2^32-1
    parameter integer CLK_HZ    = 12000000,
    // bit rate; CLK_HZ / BAUD must be at least 8
    parameter integer BAUD      = 115200,
    // bit times of silence after which a partial or bad frame is refused, 12..1000
    parameter integer IDLE_BITS = 40,
    // the core's axes, 2..6 (the STATUS reply carries NA positions)
    parameter integer NA        = 3,
    // the core's position width, 8..32 (positions are sign-extended to 32 bits)
    parameter integer W         = 32,
    // the core's queue depth, 2..256 (reported; sizes queue_level)
    parameter integer DEPTH     = 16,
    // the core's profile tick exponent, 1..24 (reported in the IDENT reply)
    parameter integer DIV       = 10
) (
    input  wire                           clk,
    input  wire                           rst,

    /*
     * Serial line (8N1)
     */
    input  wire                           rx,
    output wire                           tx,

    /*
     * Commands to the motion core (AXI4-Stream master, one command per beat)
     */
    output wire                           m_axis_tvalid,
    input  wire                           m_axis_tready,
    output wire [`HALFPOINT_CMD_BITS-1:0] m_axis_tdata,

    /*
     * The core's status: reject report (err, err_code), positions, queue
     * level, busy, the sticky underrun and dry flags, the abort input
     */
    input  wire                           cmd_err,
    input  wire [`HALFPOINT_ERR_CODE_BITS-1:0] cmd_err_code,
    input  wire [NA*W-1:0]                core_pos,
    input  wire [$clog2(DEPTH):0]         core_level,
    input  wire                           core_busy,
    input  wire                           core_underrun,
    input  wire                           core_dry,
    input  wire                           core_abort,

    /*
     * To the core: feed hold and controlled stop (levels)
     */
    output wire                           core_hold,
    output wire                           core_stop
);

    localparam integer CLOCKS_PER_BIT = CLK_HZ / BAUD;
    localparam integer COUNT_W        = $clog2(CLOCKS_PER_BIT * IDLE_BITS + 1);
    localparam [31:0]  HALF_BIT_32       = CLOCKS_PER_BIT / 2 - 1;
    localparam [31:0]  IDLE_CLOCKS_32    = CLOCKS_PER_BIT * IDLE_BITS;
    localparam integer CMD_BYTES    = `HALFPOINT_LINK_COMMAND_BYTES;
    localparam integer LEVEL_W      = $clog2(DEPTH) + 1;
    // reply frames: first byte, payload, check
    localparam integer STATUS_BYTES = 1 + 4 * NA + `HALFPOINT_LINK_STATUS_TAIL;
    localparam integer IDENT_BYTES  = 1 + `HALFPOINT_LINK_IDENT_PAYLOAD;
    localparam integer FRAME_BYTES  = (STATUS_BYTES > IDENT_BYTES) ? STATUS_BYTES
                                                                   : IDENT_BYTES;
    localparam [31:0]  STATUS_LEN_32 = STATUS_BYTES + 1;
    localparam [31:0]  IDENT_LEN_32  = IDENT_BYTES + 1;
    // the bit-time counters count 0..CLOCKS_PER_BIT - 1
    localparam integer BIT_W = $clog2(CLOCKS_PER_BIT);
    localparam [31:0]  BIT_LAST_32   = CLOCKS_PER_BIT - 1;
    wire [BIT_W-1:0]   bit_last       = BIT_LAST_32[BIT_W-1:0];
    wire [BIT_W-1:0]   half_bit       = HALF_BIT_32[BIT_W-1:0];
    wire [COUNT_W-1:0] idle_clocks    = IDLE_CLOCKS_32[COUNT_W-1:0];

    generate
        if (BAUD <= 0 || CLK_HZ / BAUD < 8) begin : g_bad_baud
            halfpoint_uart_cmd_illegal_parameter_CLK_HZ_over_BAUD_must_be_at_least_8 u_bad ();
        end
        if (IDLE_BITS < 12 || IDLE_BITS > 1000) begin : g_bad_idle
            halfpoint_uart_cmd_illegal_parameter_IDLE_BITS_must_be_12_to_1000 u_bad ();
        end
        if (NA < 2 || NA > 6) begin : g_bad_na
            halfpoint_uart_cmd_illegal_parameter_NA_must_be_2_to_6 u_bad ();
        end
        if (W < 8 || W > 32) begin : g_bad_w
            halfpoint_uart_cmd_illegal_parameter_W_must_be_8_to_32 u_bad ();
        end
        if (DEPTH < 2 || DEPTH > 256) begin : g_bad_depth
            halfpoint_uart_cmd_illegal_parameter_DEPTH_must_be_2_to_256 u_bad ();
        end
        if (DIV < 1 || DIV > 24) begin : g_bad_div
            halfpoint_uart_cmd_illegal_parameter_DIV_must_be_1_to_24 u_bad ();
        end
    endgenerate

    // CRC-8 of the link (spec/link.py crc8): one byte into the register, MSB first
    function [7:0] crc8_byte;
        input [7:0] crc;
        input [7:0] data;
        integer     k;
        reg [7:0]   c;
        begin
            c = crc ^ data;
            for (k = 0; k < 8; k = k + 1) begin
                c = c[7] ? ({c[6:0], 1'b0} ^ `HALFPOINT_LINK_CRC_POLY) : {c[6:0], 1'b0};
            end
            crc8_byte = c;
        end
    endfunction

    // ---------------------------------------------------------------- receiver
    reg [1:0]         rx_sync_q;
    wire              rx_synced = rx_sync_q[1];
    reg               rx_busy_q;
    reg [3:0]         rx_bit_q;         // 0 = start bit, 1..8 = data, 9 = stop
    reg [BIT_W-1:0]   rx_count_q;       // clocks to the next sample point, < CLOCKS_PER_BIT
    reg [7:0]         rx_shift_q;
    reg               byte_valid_q;     // a good byte in rx_shift_q (one clock)
    reg               frame_err_q;      // a bad stop bit (one clock)

    always @(posedge clk) begin
        if (rst) begin
            rx_sync_q <= 2'b11;
        end else begin
            rx_sync_q <= {rx_sync_q[0], rx};
        end
    end

    always @(posedge clk) begin
        byte_valid_q <= 1'b0;
        frame_err_q  <= 1'b0;
        if (rst) begin
            rx_busy_q  <= 1'b0;
            rx_bit_q   <= 4'd0;
            rx_count_q <= {BIT_W{1'b0}};
            rx_shift_q <= 8'd0;
        end else if (!rx_busy_q) begin
            if (!rx_synced) begin
                // falling edge of a start bit: look again at its middle
                rx_busy_q <= 1'b1;
                rx_bit_q  <= 4'd0;
                rx_count_q <= half_bit;
            end
        end else if (rx_count_q != {BIT_W{1'b0}}) begin
            rx_count_q <= rx_count_q - 1'b1;
        end else begin
            rx_count_q <= bit_last;
            if (rx_bit_q == 4'd0) begin
                if (rx_synced) begin
                    rx_busy_q <= 1'b0;          // a glitch, not a start bit
                end
                rx_bit_q <= 4'd1;
            end else if (rx_bit_q != 4'd9) begin
                rx_shift_q <= {rx_synced, rx_shift_q[7:1]};
                rx_bit_q   <= rx_bit_q + 1'b1;
            end else begin
                rx_busy_q    <= 1'b0;
                byte_valid_q <= rx_synced;
                frame_err_q  <= !rx_synced;
            end
        end
    end

    // clocks of silence since the last byte; idle_tick: IDLE_BITS bit times reached
    reg [COUNT_W-1:0] idle_count_q;
    always @(posedge clk) begin
        if (rst || byte_valid_q || frame_err_q || rx_busy_q) begin
            idle_count_q <= {COUNT_W{1'b0}};
        end else if (idle_count_q != idle_clocks) begin
            idle_count_q <= idle_count_q + 1'b1;
        end
    end
    wire idle_tick = !byte_valid_q && !frame_err_q && !rx_busy_q &&
                     idle_count_q == idle_clocks - 1'b1;

    // ------------------------------------------------------------ frame parser
    localparam [1:0] PS_OPCODE  = 2'd0;     // the next byte is an opcode
    localparam [1:0] PS_PAYLOAD = 2'd1;     // a COMMAND's payload
    localparam [1:0] PS_CHECK   = 2'd2;     // the next byte is the check
    localparam [1:0] PS_DISCARD = 2'd3;     // a bad frame: ignore bytes until idle

    reg [1:0]                          parse_q;
    reg [7:0]                          opcode_q;
    reg [5:0]                          payload_left_q;   // payload bytes after this one
    reg [7:0]                          rx_crc_q;
    reg [7:0]                          discard_reason_q;
    reg [`HALFPOINT_CMD_BITS-1:0]      word_q;
    reg                                full_q;           // word_q waits for the core
    reg                                hold_q;
    reg                                stop_q;
    reg                                fault_q;
    reg [15:0]                         taken_q;          // commands the core took
    reg [15:0]                         reject_index_q;
    reg [`HALFPOINT_ERR_CODE_BITS-1:0] reject_code_q;
    // replies waiting for the transmitter
    reg                                nak_line_pend_q;
    reg [7:0]                          nak_line_reason_q;
    reg                                received_pend_q;
    reg                                nak_stopped_pend_q;
    reg                                taken_pend_q;
    reg                                status_pend_q;
    reg                                ident_pend_q;

    wire       take = full_q && m_axis_tready;
    wire [7:0] rx_byte = rx_shift_q;
    wire       check_ok = rx_byte == rx_crc_q;
    wire       opcode_control = rx_byte == `HALFPOINT_LINK_F_STATUS ||
                                rx_byte == `HALFPOINT_LINK_F_HOLD ||
                                rx_byte == `HALFPOINT_LINK_F_RESUME ||
                                rx_byte == `HALFPOINT_LINK_F_STOP ||
                                rx_byte == `HALFPOINT_LINK_F_IDENT;
    // a whole frame with a good check, by kind (one clock)
    wire       frame_ok = byte_valid_q && parse_q == PS_CHECK && check_ok;
    wire       got_command = frame_ok && opcode_q == `HALFPOINT_LINK_F_COMMAND;
    wire       got_stop    = frame_ok && opcode_q == `HALFPOINT_LINK_F_STOP;
    wire       refused     = stop_q || fault_q;   // COMMAND frames are refused
    wire [15:0] level_16   = {{(16 - LEVEL_W){1'b0}}, core_level};
    wire       new_fault   = cmd_err && !fault_q;
    // the waiting word is dropped by a STOP or a reject (unless the core takes it now)
    wire       drop_waiting = full_q && !take && (got_stop || new_fault);
    // the stop ends once the core is at rest and empty
    wire       stop_done = stop_q && !got_stop && !new_fault && !core_busy &&
                           core_level == {LEVEL_W{1'b0}};

    // the transmitter picks a reply when it is free (below)
    wire       pick;
    wire       pick_nak_line    = pick && nak_line_pend_q;
    wire       pick_received    = pick && !nak_line_pend_q && received_pend_q;
    wire       pick_nak_stopped = pick && !nak_line_pend_q && !received_pend_q &&
                                  nak_stopped_pend_q;
    wire       pick_taken       = pick && !nak_line_pend_q && !received_pend_q &&
                                  !nak_stopped_pend_q && taken_pend_q;
    wire       pick_status      = pick && !nak_line_pend_q && !received_pend_q &&
                                  !nak_stopped_pend_q && !taken_pend_q && status_pend_q;
    wire       pick_ident       = pick && !nak_line_pend_q && !received_pend_q &&
                                  !nak_stopped_pend_q && !taken_pend_q && !status_pend_q &&
                                  ident_pend_q;

    always @(posedge clk) begin
        if (rst) begin
            parse_q            <= PS_OPCODE;
            opcode_q           <= 8'd0;
            payload_left_q     <= 6'd0;
            rx_crc_q           <= 8'd0;
            discard_reason_q   <= 8'd0;
            word_q             <= {`HALFPOINT_CMD_BITS{1'b0}};
            full_q             <= 1'b0;
            hold_q             <= 1'b0;
            stop_q             <= 1'b0;
            fault_q            <= 1'b0;
            taken_q            <= 16'd0;
            reject_index_q     <= 16'd0;
            reject_code_q      <= {`HALFPOINT_ERR_CODE_BITS{1'b0}};
            nak_line_pend_q    <= 1'b0;
            nak_line_reason_q  <= 8'd0;
            received_pend_q    <= 1'b0;
            nak_stopped_pend_q <= 1'b0;
            taken_pend_q       <= 1'b0;
            status_pend_q      <= 1'b0;
            ident_pend_q       <= 1'b0;
        end else begin
            // replies handed to the transmitter (a new one of a kind, below, wins)
            if (pick_nak_line)    nak_line_pend_q    <= 1'b0;
            if (pick_received)    received_pend_q    <= 1'b0;
            if (pick_nak_stopped) nak_stopped_pend_q <= 1'b0;
            if (pick_taken)       taken_pend_q       <= 1'b0;
            if (pick_status)      status_pend_q      <= 1'b0;
            if (pick_ident)       ident_pend_q       <= 1'b0;

            // frames
            if (frame_err_q) begin
                parse_q          <= PS_DISCARD;
                discard_reason_q <= `HALFPOINT_LINK_NAK_FRAMING;
            end else if (byte_valid_q) begin
                case (parse_q)
                    PS_OPCODE: begin
                        opcode_q       <= rx_byte;
                        rx_crc_q       <= crc8_byte(8'd0, rx_byte);
                        payload_left_q <= CMD_BYTES[5:0] - 6'd1;
                        if (rx_byte == `HALFPOINT_LINK_F_COMMAND) begin
                            if (full_q) begin
                                parse_q          <= PS_DISCARD;
                                discard_reason_q <= `HALFPOINT_LINK_NAK_BUSY;
                            end else begin
                                parse_q <= PS_PAYLOAD;
                            end
                        end else if (opcode_control) begin
                            parse_q <= PS_CHECK;
                        end else begin
                            parse_q          <= PS_DISCARD;
                            discard_reason_q <= `HALFPOINT_LINK_NAK_OPCODE;
                        end
                    end
                    PS_PAYLOAD: begin
                        rx_crc_q <= crc8_byte(rx_crc_q, rx_byte);
                        word_q   <= {rx_byte, word_q[`HALFPOINT_CMD_BITS-1:8]};
                        payload_left_q <= payload_left_q - 6'd1;
                        if (payload_left_q == 6'd0) begin
                            parse_q <= PS_CHECK;
                        end
                    end
                    PS_CHECK: begin
                        parse_q <= PS_OPCODE;
                        if (!check_ok) begin
                            nak_line_pend_q   <= 1'b1;
                            nak_line_reason_q <= `HALFPOINT_LINK_NAK_CHECK;
                        end
                    end
                    default: ;                  // PS_DISCARD: until the line is idle
                endcase
            end else if (idle_tick && parse_q != PS_OPCODE) begin
                parse_q           <= PS_OPCODE;
                nak_line_pend_q   <= 1'b1;
                nak_line_reason_q <= (parse_q == PS_DISCARD) ? discard_reason_q
                                                              : `HALFPOINT_LINK_NAK_INCOMPLETE;
            end

            // what a good frame does
            if (got_command) begin
                if (refused) begin
                    nak_stopped_pend_q <= 1'b1;
                end else begin
                    full_q          <= 1'b1;
                    received_pend_q <= 1'b1;
                end
            end
            if (frame_ok) begin
                case (opcode_q)
                    `HALFPOINT_LINK_F_STATUS: status_pend_q <= 1'b1;
                    `HALFPOINT_LINK_F_IDENT:  ident_pend_q  <= 1'b1;
                    `HALFPOINT_LINK_F_HOLD: begin
                        hold_q          <= 1'b1;
                        received_pend_q <= 1'b1;
                    end
                    `HALFPOINT_LINK_F_RESUME: begin
                        hold_q          <= 1'b0;
                        received_pend_q <= 1'b1;
                    end
                    `HALFPOINT_LINK_F_STOP: begin
                        hold_q          <= 1'b0;
                        received_pend_q <= 1'b1;
                    end
                    default: ;
                endcase
            end

            // the core
            if (take) begin
                full_q       <= 1'b0;
                taken_q      <= taken_q + 16'd1;
                taken_pend_q <= 1'b1;
            end
            if (drop_waiting) begin
                full_q             <= 1'b0;
                nak_stopped_pend_q <= 1'b1;
            end
            if (got_stop) begin
                fault_q <= 1'b0;
                stop_q  <= 1'b1;
            end else if (new_fault) begin
                fault_q        <= 1'b1;
                stop_q         <= 1'b1;
                reject_code_q  <= cmd_err_code;
                reject_index_q <= taken_q - level_16 - 16'd1;
            end else if (stop_done) begin
                stop_q <= 1'b0;
            end
        end
    end

    assign m_axis_tvalid = full_q;
    assign m_axis_tdata  = word_q;
    assign core_hold     = hold_q;
    assign core_stop     = stop_q;

    // ---------------------------------------------------------------- replies
    // the STATUS payload: positions (sign-extended to 32 bits), level
    // (saturated at 255), flags, taken, reject index, reject code
    wire [32*NA-1:0] pos_32;
    genvar a;
    generate
        for (a = 0; a < NA; a = a + 1) begin : g_pos
            assign pos_32[32*a +: 32] = {{(32 - W){core_pos[W*a + W - 1]}},
                                         core_pos[W*a +: W]};
        end
    endgenerate
    wire [7:0] level_8 = (level_16 > 16'd255) ? 8'd255 : level_16[7:0];
    wire [7:0] flags = (core_busy     ? `HALFPOINT_LINK_FLAG_BUSY     : 8'd0) |
                       (hold_q        ? `HALFPOINT_LINK_FLAG_HOLD     : 8'd0) |
                       (stop_q        ? `HALFPOINT_LINK_FLAG_STOPPING : 8'd0) |
                       (fault_q       ? `HALFPOINT_LINK_FLAG_FAULT    : 8'd0) |
                       (core_underrun ? `HALFPOINT_LINK_FLAG_UNDERRUN : 8'd0) |
                       (core_dry      ? `HALFPOINT_LINK_FLAG_DRY      : 8'd0) |
                       (core_abort    ? `HALFPOINT_LINK_FLAG_ABORT    : 8'd0) |
                       (full_q        ? `HALFPOINT_LINK_FLAG_WAITING  : 8'd0);
    wire [8*STATUS_BYTES-1:0] status_frame = {
        {(8 - `HALFPOINT_ERR_CODE_BITS){1'b0}}, reject_code_q, reject_index_q, taken_q,
        flags, level_8, pos_32, `HALFPOINT_LINK_R_STATUS};
    localparam [31:0] CLK_HZ_32 = CLK_HZ;
    localparam [31:0] BAUD_32   = BAUD;
    localparam [31:0] NA_32     = NA;
    localparam [31:0] W_32      = W;
    localparam [31:0] DEPTH_32  = DEPTH;
    localparam [31:0] DIV_32    = DIV;
    wire [8*IDENT_BYTES-1:0] ident_frame = {
        DIV_32[7:0], BAUD_32, CLK_HZ_32, DEPTH_32[15:0], W_32[7:0], NA_32[7:0],
        `HALFPOINT_LINK_PROTOCOL_VERSION, `HALFPOINT_LINK_R_IDENT};

    // frame sender: the bytes of the reply in progress, first byte lowest
    reg [8*FRAME_BYTES-1:0] frame_shift_q;
    reg [5:0]               frame_left_q;   // bytes still to send (the check included)
    reg                     frame_check_q;  // the last byte is the check
    reg [7:0]               tx_crc_q;

    // byte transmitter
    reg [9:0]         tx_shift_q;       // stop, data[7:0], start; LSB on the line
    reg [3:0]         tx_left_q;        // bit times still to send: 10 bits + 1 whole stop bit
    reg [BIT_W-1:0]   tx_count_q;       // clocks to the next bit, < CLOCKS_PER_BIT
    reg               tx_q;
    wire              tx_idle = tx_left_q == 4'd0;
    assign pick = tx_idle && frame_left_q == 6'd0;
    wire [7:0]        next_byte = (frame_left_q == 6'd1 && frame_check_q) ? tx_crc_q
                                                                          : frame_shift_q[7:0];

    always @(posedge clk) begin
        if (rst) begin
            frame_shift_q <= {(8 * FRAME_BYTES){1'b0}};
            frame_left_q  <= 6'd0;
            frame_check_q <= 1'b0;
            tx_crc_q      <= 8'd0;
        end else if (pick) begin
            tx_crc_q <= 8'd0;
            if (pick_nak_line) begin
                frame_shift_q <= {{(8 * FRAME_BYTES - 16){1'b0}}, nak_line_reason_q,
                                  `HALFPOINT_LINK_R_NAK};
                frame_left_q  <= 6'd2;
                frame_check_q <= 1'b0;
            end else if (pick_received) begin
                frame_shift_q <= {{(8 * FRAME_BYTES - 8){1'b0}}, `HALFPOINT_LINK_R_RECEIVED};
                frame_left_q  <= 6'd1;
                frame_check_q <= 1'b0;
            end else if (pick_nak_stopped) begin
                frame_shift_q <= {{(8 * FRAME_BYTES - 16){1'b0}}, `HALFPOINT_LINK_NAK_STOPPED,
                                  `HALFPOINT_LINK_R_NAK};
                frame_left_q  <= 6'd2;
                frame_check_q <= 1'b0;
            end else if (pick_taken) begin
                frame_shift_q <= {{(8 * FRAME_BYTES - 8){1'b0}}, `HALFPOINT_LINK_R_TAKEN};
                frame_left_q  <= 6'd1;
                frame_check_q <= 1'b0;
            end else if (pick_status) begin
                frame_shift_q <= {{(8 * (FRAME_BYTES - STATUS_BYTES)){1'b0}}, status_frame};
                frame_left_q  <= STATUS_LEN_32[5:0];
                frame_check_q <= 1'b1;
            end else if (pick_ident) begin
                frame_shift_q <= {{(8 * (FRAME_BYTES - IDENT_BYTES)){1'b0}}, ident_frame};
                frame_left_q  <= IDENT_LEN_32[5:0];
                frame_check_q <= 1'b1;
            end
        end else if (tx_idle && frame_left_q != 6'd0) begin
            frame_shift_q <= {8'd0, frame_shift_q[8*FRAME_BYTES-1:8]};
            frame_left_q  <= frame_left_q - 6'd1;
            tx_crc_q      <= crc8_byte(tx_crc_q, next_byte);
        end
    end

    always @(posedge clk) begin
        if (rst) begin
            tx_shift_q <= 10'h3ff;
            tx_left_q  <= 4'd0;
            tx_count_q <= {BIT_W{1'b0}};
            tx_q       <= 1'b1;
        end else if (tx_idle) begin
            tx_q <= 1'b1;
            if (frame_left_q != 6'd0) begin
                tx_shift_q <= {1'b1, next_byte, 1'b0};
                tx_left_q  <= 4'd11;
                tx_count_q <= {BIT_W{1'b0}};
            end
        end else if (tx_count_q != {BIT_W{1'b0}}) begin
            tx_count_q <= tx_count_q - 1'b1;
        end else begin
            tx_q       <= tx_shift_q[0];
            tx_shift_q <= {1'b1, tx_shift_q[9:1]};
            tx_left_q  <= tx_left_q - 1'b1;
            tx_count_q <= bit_last;
        end
    end

    assign tx = tx_q;

endmodule

`default_nettype wire
