$H
$X
Z5.0 ; grbl starts in G0: a bare axis word moves
(pcb2gcode-style isolation pass, grbl 1.1)
G94 ( Millimeters per minute feed rate. )
G21 ( Units == Millimeters. )
G90 ( Absolute coordinates. )
G91.1
$32=0
S10000 ( RPM spindle speed. )
M3 ( Spindle on clockwise. )
G04 P1.0
G00 Z2.0
X12.5 Y8.25
G01 Z-0.05 F100
G01 X30.0 Y8.25 F400
X30.0 Y20.0
G02 X25.0 Y25.0 I-5.0 J0.0
G01 X12.5 Y25.0
X12.5 Y8.25
G00 Z2.0
M5
