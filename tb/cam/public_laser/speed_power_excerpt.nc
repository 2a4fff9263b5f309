(Source: github.com/doug-harriman/3018-Mill, laser/gcode/speed-power-tuning.nc, commit)
(605892fb0390; an excerpt: header, three glyphs, three of 63 squares. MIT, c 2021 Doug Harriman)
(Speed & Power Tuning Print)
(Document size: 58.1,69.0 )
()
(Speeds: [ 200  300  400  500  600  700  800  900 1000])
(Powers: [20 30 40 50 60 70 80])
()
(Square Count: 63)
(Square Size : 5)
()

(Machine Setup)
G90  (Absolute Position Mode)
G21  (Units = millimeters)

(Grid cell 0,0 )
( *Empty Cell* )
(Grid cell 0,1 )
(Text: "POWER")
G0 X25.833 Y67.000 F3000.0
G0 Z0.000
G1 F500.0
(Character: P)
G1 X25.833 Y67.000
M4 S400.0 (Laser on @ 40%)
G1 F500.0
G1 X25.833 Y68.778
G1 X26.056 Y69.000
G1 X26.722 Y69.000
G1 X26.944 Y68.778
G1 X26.944 Y68.111
G1 X26.722 Y67.889
G1 X25.833 Y67.889
M5        (Laser off)
G0 F3000.0
(Character: O)
G1 X27.611 Y67.222
M4 S400.0 (Laser on @ 40%)
G1 F500.0
G1 X27.611 Y68.778
G1 X27.833 Y69.000
G1 X28.500 Y69.000
G1 X28.722 Y68.778
G1 X28.722 Y67.222
G1 X28.500 Y67.000
G1 X27.833 Y67.000
G1 X27.611 Y67.222
M5        (Laser off)
G0 F3000.0
(Character: W)
G1 X29.389 Y69.000
M4 S400.0 (Laser on @ 40%)
G1 F500.0
G1 X29.833 Y67.000
G1 X30.056 Y69.000
G1 X30.278 Y67.000
G1 X30.722 Y69.000
M5        (Laser off)
G0 F3000.0
M5        (Laser off)
(Grid cell 1,1 )
(Power=20%, Speed=1000)
G0 X10.111 Y57.000 F3000.0
G0 Z0.000
G1 F1000.0
M4 S200.0 (Laser on @ 20%)
G1 X10.111 Y62.000 (Left)
G1 X15.111 Y62.000 (Top)
G1 X15.111 Y57.000 (Right)
G1 X10.111 Y57.000 (Bottom)
M5        (Laser off)
(Grid cell 1,2 )
(Power=30%, Speed=1000)
G0 X17.111 Y57.000 F3000.0
G0 Z0.000
G1 F1000.0
M4 S300.0 (Laser on @ 30%)
G1 X17.111 Y62.000 (Left)
G1 X22.111 Y62.000 (Top)
G1 X22.111 Y57.000 (Right)
G1 X17.111 Y57.000 (Bottom)
M5        (Laser off)
(Grid cell 1,3 )
(Power=40%, Speed=1000)
G0 X24.111 Y57.000 F3000.0
G0 Z0.000
G1 F1000.0
M4 S400.0 (Laser on @ 40%)
G1 X24.111 Y62.000 (Left)
G1 X29.111 Y62.000 (Top)
G1 X29.111 Y57.000 (Right)
G1 X24.111 Y57.000 (Bottom)
M5        (Laser off)
