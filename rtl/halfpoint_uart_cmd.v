// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// ============================================================================
// halfpoint_uart_cmd: serial command port for the motion core (UART 8N1 in,
// 256-bit AXI4-Stream commands out, one acknowledge byte back per command)
// ============================================================================
// Receives bytes at BAUD (8 data bits, no parity, 1 stop bit, LSB first),
// assembles 32 of them into one command word (byte k -> m_axis_tdata[8k+7:8k],
// i.e. the command's little-endian byte string; the width comes from the
// generated halfpoint_cmd.vh, see model/halfpoint/spec/encoding.py) and
// offers it on m_axis.  When the core takes the word
// (tvalid & tready) one acknowledge byte is sent on `tx`:
//
//   bit 7    1 (marks an acknowledge)
//   bit 6    a line error since the last acknowledge: a bad stop bit, a byte
//            that arrived while a word was waiting for the core (dropped), or
//            a partial word discarded by the idle timeout
//   bit 5    the core rejected a command since the last acknowledge
//            (cmd_err pulses)
//   bit 4    0
//   bits 3:0 the error code of the latest rejected command (0 if none)
//
// Flow control is by the acknowledge: the host sends a command's 32 bytes,
// then waits for its acknowledge before sending the next one, so a word
// never waits while more bytes arrive; the core's own queue keeps motion
// going while the host waits.  A word the host started but did not finish
// within IDLE_BITS bit times of silence is discarded (and flagged), so the
// byte count resynchronises after a host restart.
//
// Receiver: rx goes through a two-flip-flop synchroniser; a start bit is
// confirmed at its middle, data bits are sampled at their middles, a low
// stop bit is a framing error (byte dropped, flagged).
//
// Parameters: see the comment above each (an illegal value stops
// elaboration).
//
// Reset: synchronous, active high; clears the partial word, the pending word,
// the flags and the transmitter (tx idles high).
// ============================================================================
`include "halfpoint_cmd.vh"

module halfpoint_uart_cmd #(
    // clock frequency in Hz
    parameter integer CLK_HZ    = 12000000,
    // bit rate; CLK_HZ / BAUD must be at least 8
    parameter integer BAUD      = 115200,
    // bit times of silence after which a partial word is discarded, 12..1000
    parameter integer IDLE_BITS = 40
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
     * The core's reject report (its err and err_code outputs)
     */
    input  wire                           cmd_err,
    input  wire [`HALFPOINT_ERR_CODE_BITS-1:0] cmd_err_code
);

    localparam integer CLOCKS_PER_BIT = CLK_HZ / BAUD;
    localparam integer COUNT_W        = $clog2(CLOCKS_PER_BIT * IDLE_BITS + 1);
    localparam [31:0]  CLOCKS_PER_BIT_32 = CLOCKS_PER_BIT;
    localparam [31:0]  HALF_BIT_32       = CLOCKS_PER_BIT / 2 - 1;
    localparam [31:0]  IDLE_CLOCKS_32    = CLOCKS_PER_BIT * IDLE_BITS;
    localparam integer CMD_BYTES    = `HALFPOINT_CMD_BITS / 8;     // bytes of a command
    localparam integer BYTE_COUNT_W = $clog2(CMD_BYTES);
    localparam [31:0]  LAST_BYTE_32 = CMD_BYTES - 1;
    localparam [BYTE_COUNT_W-1:0] LAST_BYTE = LAST_BYTE_32[BYTE_COUNT_W-1:0];
    wire [COUNT_W-1:0] clocks_per_bit = CLOCKS_PER_BIT_32[COUNT_W-1:0];
    wire [COUNT_W-1:0] half_bit       = HALF_BIT_32[COUNT_W-1:0];
    wire [COUNT_W-1:0] idle_clocks    = IDLE_CLOCKS_32[COUNT_W-1:0];

    generate
        if (BAUD <= 0 || CLK_HZ / BAUD < 8) begin : g_bad_baud
            halfpoint_uart_cmd_illegal_parameter_CLK_HZ_over_BAUD_must_be_at_least_8 u_bad ();
        end
        if (IDLE_BITS < 12 || IDLE_BITS > 1000) begin : g_bad_idle
            halfpoint_uart_cmd_illegal_parameter_IDLE_BITS_must_be_12_to_1000 u_bad ();
        end
    endgenerate

    // ---------------------------------------------------------------- receiver
    reg [1:0]         rx_sync_q;
    wire              rx_synced = rx_sync_q[1];
    reg               rx_busy_q;
    reg [3:0]         rx_bit_q;         // 0 = start bit, 1..8 = data, 9 = stop
    reg [COUNT_W-1:0] rx_count_q;       // clocks to the next sample point
    reg [7:0]         rx_shift_q;
    reg               byte_valid_q;     // a good byte in rx_shift_q (one clock)
    reg               frame_err_q;      // a bad stop bit or start glitch (one clock)

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
            rx_count_q <= {COUNT_W{1'b0}};
            rx_shift_q <= 8'd0;
        end else if (!rx_busy_q) begin
            if (!rx_synced) begin
                // falling edge of a start bit: look again at its middle
                rx_busy_q <= 1'b1;
                rx_bit_q  <= 4'd0;
                rx_count_q <= half_bit;
            end
        end else if (rx_count_q != {COUNT_W{1'b0}}) begin
            rx_count_q <= rx_count_q - 1'b1;
        end else begin
            rx_count_q <= clocks_per_bit - 1'b1;
            if (rx_bit_q == 4'd0) begin
                if (rx_synced) begin
                    rx_busy_q <= 1'b0;          // a glitch, not a start bit
                end
                rx_bit_q <= 4'd1;
            end else if (rx_bit_q != 4'd9) begin
                rx_shift_q <= {rx_synced, rx_shift_q[7:1]};
                rx_bit_q   <= rx_bit_q + 1'b1;
            end else begin
                // stop bit: wait for the line to be high again before idling
                rx_busy_q    <= 1'b0;
                byte_valid_q <= rx_synced;
                frame_err_q  <= !rx_synced;
            end
        end
    end

    // --------------------------------------------------------------- assembler
    reg [`HALFPOINT_CMD_BITS-1:0]      word_q;
    reg [BYTE_COUNT_W-1:0]             byte_count_q;  // bytes of the word received so far
    reg                                full_q;        // word_q waits for the core
    reg [COUNT_W-1:0]                  idle_count_q;  // clocks of silence since the last byte
    reg                                line_err_q;    // sticky until the next acknowledge
    reg                                cmd_err_q;
    reg [`HALFPOINT_ERR_CODE_BITS-1:0] cmd_code_q;
    reg                                ack_req_q;     // an acknowledge byte is to be sent
    reg [7:0]                          ack_byte_q;
    wire                               take = full_q && m_axis_tready;
    wire                               ack_start;     // the transmitter takes the acknowledge

    always @(posedge clk) begin
        if (rst) begin
            word_q       <= {`HALFPOINT_CMD_BITS{1'b0}};
            byte_count_q <= {BYTE_COUNT_W{1'b0}};
            full_q       <= 1'b0;
            idle_count_q <= {COUNT_W{1'b0}};
            line_err_q   <= 1'b0;
            cmd_err_q    <= 1'b0;
            cmd_code_q   <= {`HALFPOINT_ERR_CODE_BITS{1'b0}};
            ack_req_q    <= 1'b0;
            ack_byte_q   <= 8'd0;
        end else begin
            if (byte_valid_q || rx_busy_q) begin
                idle_count_q <= {COUNT_W{1'b0}};
            end else if (idle_count_q != idle_clocks) begin
                idle_count_q <= idle_count_q + 1'b1;
            end
            if (byte_valid_q) begin
                if (full_q) begin
                    line_err_q <= 1'b1;         // host did not wait: byte dropped
                end else begin
                    word_q       <= {rx_shift_q, word_q[`HALFPOINT_CMD_BITS-1:8]};
                    byte_count_q <= byte_count_q + 1'b1;
                    if (byte_count_q == LAST_BYTE) begin
                        full_q <= 1'b1;
                    end
                end
            end else if (idle_count_q == idle_clocks - 1'b1 &&
                         byte_count_q != {BYTE_COUNT_W{1'b0}}) begin
                byte_count_q <= {BYTE_COUNT_W{1'b0}};   // an unfinished word: discard
                line_err_q <= 1'b1;
            end
            if (frame_err_q) begin
                line_err_q <= 1'b1;
            end
            if (cmd_err) begin
                cmd_err_q  <= 1'b1;
                cmd_code_q <= cmd_err_code;
            end
            if (take) begin
                full_q     <= 1'b0;
                ack_req_q  <= 1'b1;
                // flags raised in this very clock are reported with this word
                ack_byte_q <= {1'b1, line_err_q | frame_err_q | (byte_valid_q & full_q),
                               cmd_err_q | cmd_err, 1'b0,
                               cmd_err ? cmd_err_code : cmd_code_q};
                line_err_q <= 1'b0;
                cmd_err_q  <= 1'b0;
                cmd_code_q <= {`HALFPOINT_ERR_CODE_BITS{1'b0}};
            end else if (ack_start) begin
                ack_req_q <= 1'b0;
            end
        end
    end

    assign m_axis_tvalid = full_q;
    assign m_axis_tdata  = word_q;

    // ------------------------------------------------------------- transmitter
    reg [9:0]         tx_shift_q;       // stop, data[7:0], start; LSB on the line
    reg [3:0]         tx_left_q;        // bit times still to send: 10 bits + 1 whole stop bit
    reg [COUNT_W-1:0] tx_count_q;
    reg               tx_q;

    assign ack_start = ack_req_q && tx_left_q == 4'd0;

    always @(posedge clk) begin
        if (rst) begin
            tx_shift_q <= 10'h3ff;
            tx_left_q  <= 4'd0;
            tx_count_q <= {COUNT_W{1'b0}};
            tx_q       <= 1'b1;
        end else if (tx_left_q == 4'd0) begin
            tx_q <= 1'b1;
            if (ack_req_q) begin
                tx_shift_q <= {1'b1, ack_byte_q, 1'b0};
                tx_left_q  <= 4'd11;
                tx_count_q <= {COUNT_W{1'b0}};
            end
        end else if (tx_count_q != {COUNT_W{1'b0}}) begin
            tx_count_q <= tx_count_q - 1'b1;
        end else begin
            tx_q       <= tx_shift_q[0];
            tx_shift_q <= {1'b1, tx_shift_q[9:1]};
            tx_left_q  <= tx_left_q - 1'b1;
            tx_count_q <= clocks_per_bit - 1'b1;
        end
    end

    assign tx = tx_q;

endmodule

`default_nettype wire
