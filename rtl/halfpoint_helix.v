// SPDX-License-Identifier: Apache-2.0
// ============================================================================
// halfpoint_helix: maps the arc unit's moves onto the core's axes (helical and
// any-plane arcs)
// ============================================================================
// The arc unit makes its moves in its own plane (u, v).  For each arc this
// module knows the plane's two axes, the arc's exact move count N (from the
// host's model) and a signed delta for each of up to two helix slots (the axes
// outside the plane, in increasing order).  For every move of the arc it puts
// the u step on axis u and the v step on axis v, and steps each slot's axis by
// the difference method against N: an accumulator gains |delta| per move;
// when it reaches N the axis steps and the accumulator drops by N.  It starts
// at floor(N/2), so after exactly N moves each slot's axis has made exactly
// |delta| steps, at most one per move (the core rejects |delta| > N).
//
// The accumulator is kept as e = acc + |delta| - N: the next move's step is
// e's sign bit (a register), and each move adds |delta| - N after a step or
// |delta| otherwise (both set when the arc starts).  A core of NA axes has
// min(2, NA - 2) slots, and only those have registers (NA 3: one, NA 2: none).
//
// Moves beyond the N-th step no helix axis; count_error flags the arc's last
// move when the arc made a number of moves other than N (N = 0: not given, a
// flat arc, not checked).  The model is halfpoint.spec.helix (HelixMapper),
// which the core's tests compare on every clock.
//
// Timing: take loads the pending slot (the dispatcher hands the arc to the arc
// unit); load copies it to the running state (the arc unit starts the arc),
// after the running arc's move at the same edge; step and dir are
// combinational from the running state and the arc unit's next move.
//
// Parameters: see the comment above each (an illegal value stops
// elaboration).
//
// Reset: synchronous, active high; flush (abort, stop at rest) clears too.
// ============================================================================
`default_nettype none

module halfpoint_helix #(
    // number of axes of the core, 2..6
    parameter integer NA = 3,
    // coordinate width in bits, 8..32
    parameter integer W  = 32
) (
    input  wire           clk,
    input  wire           rst,
    // abort or stop at rest: back to no arc
    input  wire           flush,

    // the dispatcher hands an arc to the arc unit at this edge
    input  wire           take,
    input  wire [2:0]     take_u,
    input  wire [2:0]     take_v,
    // the arc's exact move count N (0: not given)
    input  wire [31:0]    take_count,
    // |delta| of the helix slots 0 and 1 and their signs (1: negative)
    input  wire [W-1:0]   take_magnitude0,
    input  wire [W-1:0]   take_magnitude1,
    input  wire [1:0]     take_negative,

    // the arc unit starts the pending arc at this edge
    input  wire           load,
    // the running arc makes a move at this edge
    input  wire           move,
    // that move is the arc's last
    input  wire           last,
    // the arc unit's next move in its plane: step and direction of u (bit 0)
    // and v (bit 1)
    input  wire [1:0]     arc_step,
    input  wire [1:0]     arc_dir,

    // the next move on the core's axes
    output reg  [NA-1:0]  step,
    output reg  [NA-1:0]  dir,
    // the move at this edge is the arc's last and its count was not N
    output wire           count_error
);

    initial begin
        if (NA < 2 || NA > 6) begin
            $display("halfpoint_helix: NA must be 2..6");
            $finish;
        end
        if (W < 8 || W > 32) begin
            $display("halfpoint_helix: W must be 8..32");
            $finish;
        end
    end

    // e and the constants added to it: 34-bit signed (|e| < 2^33)
    localparam integer EW = 34;
    localparam [2:0] NO_AXIS = 3'd7;
    // the helix slots a core of NA axes has, min(2, NA - 2): a slot beyond them
    // never has an axis (its slot_axes entry is NO_AXIS), so it has no registers
    localparam integer SLOTS = (NA - 2 < 2) ? NA - 2 : 2;

    // the helix slots' axes: the axes outside {u, v} in increasing order (the
    // first two; NO_AXIS when there are fewer)
    function [5:0] slot_axes;
        input [2:0] u;
        input [2:0] v;
        integer a;
        reg [1:0] found;
        begin
            slot_axes = {NO_AXIS, NO_AXIS};
            found = 2'd0;
            for (a = 0; a < NA; a = a + 1) begin
                if (a[2:0] != u && a[2:0] != v) begin
                    if (found == 2'd0) slot_axes[2:0] = a[2:0];
                    else if (found == 2'd1) slot_axes[5:3] = a[2:0];
                    if (found != 2'd2) found = found + 2'd1;
                end
            end
        end
    endfunction

    // pending slot (each helix slot's magnitude below, with the slot)
    reg [2:0]  pend_u_q, pend_v_q;
    reg [31:0] pend_count_q;
    reg [1:0]  pend_negative_q;

    always @(posedge clk) begin
        if (take) begin
            pend_u_q <= take_u;
            pend_v_q <= take_v;
            pend_count_q <= take_count;
            pend_negative_q <= take_negative;
        end
    end

    // running state
    reg [2:0]    run_u_q, run_v_q;
    reg [5:0]    run_slots_q;
    reg [1:0]    run_negative_q;
    reg [31:0]   remaining_q;
    reg          counted_q;         // N was not 0

    wire          live = (remaining_q != 32'd0);
    wire [1:0]    slot_step;
    assign count_error = move && last && counted_q && (remaining_q != 32'd1);

    wire [EW-1:0] pend_count = {{(EW-32){1'b0}}, pend_count_q};
    wire [EW-1:0] pend_half = {{(EW-31){1'b0}}, pend_count_q[31:1]};

    always @(posedge clk) begin
        if (rst || flush) begin
            run_u_q <= 3'd0;
            run_v_q <= 3'd1;
            run_slots_q <= {NO_AXIS, NO_AXIS};
            run_negative_q <= 2'b00;
            remaining_q <= 32'd0;
            counted_q <= 1'b0;
        end else if (load) begin
            run_u_q <= pend_u_q;
            run_v_q <= pend_v_q;
            run_slots_q <= slot_axes(pend_u_q, pend_v_q);
            run_negative_q <= pend_negative_q;
            remaining_q <= pend_count_q;
            counted_q <= (pend_count_q != 32'd0);
        end else if (move && live) begin
            remaining_q <= remaining_q - 32'd1;
        end
    end

    // Each helix slot the core has: its pending |delta|, e and the two
    // constants added to it (|delta| after no step, |delta| - N after a step)
    genvar slot;
    generate
        for (slot = 0; slot < 2; slot = slot + 1) begin : g_slot
            wire [W-1:0] take_magnitude = (slot == 0) ? take_magnitude0 : take_magnitude1;
            if (slot < SLOTS) begin : g_used
                reg  [W-1:0]  pend_magnitude_q;
                reg  [EW-1:0] e_q;
                reg  [EW-1:0] add_q;        // |delta|
                reg  [EW-1:0] sub_q;        // |delta| - N
                wire [EW-1:0] pend_add = {{(EW-W){1'b0}}, pend_magnitude_q};
                assign slot_step[slot] = live && !e_q[EW-1];
                always @(posedge clk) begin
                    if (take) pend_magnitude_q <= take_magnitude;
                end
                always @(posedge clk) begin
                    if (rst || flush) begin
                        e_q <= {EW{1'b1}};
                        add_q <= {EW{1'b0}};
                        sub_q <= {EW{1'b0}};
                    end else if (load) begin
                        e_q <= pend_half + pend_add - pend_count;
                        add_q <= pend_add;
                        sub_q <= pend_add - pend_count;
                    end else if (move && live) begin
                        e_q <= e_q + (slot_step[slot] ? sub_q : add_q);
                    end
                end
            end else begin : g_absent
                // no axis: the command's delta there is 0 (the core rejects any other)
                assign slot_step[slot] = 1'b0;
                wire unused_magnitude = ^take_magnitude;
            end
        end
        if (SLOTS == 0) begin : g_no_slots
            // NA 2: the count's halves serve the slots only
            wire unused_counts = ^{pend_count, pend_half};
        end
    endgenerate

    // the next move on the core's axes
    integer k;
    always @(*) begin
        step = {NA{1'b0}};
        dir = {NA{1'b0}};
        for (k = 0; k < NA; k = k + 1) begin
            if (k[2:0] == run_u_q) begin
                step[k] = arc_step[0];
                dir[k] = arc_dir[0];
            end
            if (k[2:0] == run_v_q) begin
                step[k] = arc_step[1];
                dir[k] = arc_dir[1];
            end
            if (k[2:0] == run_slots_q[2:0]) begin
                step[k] = slot_step[0];
                dir[k] = !run_negative_q[0];
            end
            if (k[2:0] == run_slots_q[5:3]) begin
                step[k] = slot_step[1];
                dir[k] = !run_negative_q[1];
            end
        end
    end

endmodule

`default_nettype wire
