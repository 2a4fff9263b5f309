# SPDX-License-Identifier: Apache-2.0
# Generic clock constraint for a design with the halfpoint core: the core,
# its serial port and its STEP/DIR generators all run on one clock, `clk`.
# Set the period to your board's clock (nanoseconds).  make synth uses this
# file for the iCE40-HX8K Breakout Board (12 MHz); the ULX3S flow takes its
# clock from FREQUENCY in ulx3s.lpf.
create_clock -period 83.333 -name clk [get_ports clk]
