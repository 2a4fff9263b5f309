; Source: github.com/meerk40t/meerk40t, test/test_drivers_grbl.py (the gcode_rect string,
; MeerK40t GRBL driver output), commit 04111c50d715. Licence: MIT, (c) 2021 meerk40t.
G90
G94
G21
M4
G0 X19.990 Y205.003 S0.0 F600.0
G1 X19.990 Y215.011 S1000.0 F900.0
G1 X29.997 Y215.011
G1 X29.997 Y205.003
G1 X19.990 Y205.003
G1 S0
M5
