(rectangular pocket with rounded corners, finishing pass climb-milled with G4G17
G90 G0 X#<_fz925x> Y#<_fz925y> Z#<_fz925z>
G54
S12000 M3
G0 X50 Y30
G0 Z5
G1 Z-4 F300
G41 D1 G1 X60 Y30 F1600 (lead-in line)
G0 X0
(lead-in andé“ead-out arcs, concave corners line to arc and arc to line)
#<_fz906z> = #5422
G1 Z-1. F150.
G00 Z1.000
(XZ plane compensation with G41.1/G42.1 D, lines and arcs, radius md-in line)
G0 X0
(lead-in andé“ead-out arcs, concave corners line to arc and arc to line)
#<_fz906z> = #5422
G1 Z-1. F150.
G00 Z1.000
(XZ plane compensation with G41.1/G42.1 D, lines and arcs, radius mode)
G1 Y20.
G0 Z1.
G4 P0.1
(DEBUG, x = #<_x>)
G3 X70 Y40 R10 (lead-in arc)
  G1 Z-0.05
  X0.2 Z-0.1
  Z-0.4
  G1 Z-0.05
  X0.2 Z-0.1
N138 G69
  Z-0.4
  G3 X0.4 Z-0.2 R0.2
N10 G0 X[#1 * 15.] Y360 Z1.
G1 Z-1. F150.
G00 Z1.000
  G1 Z-0.3
  G2 X0.3 Z-0.15 I0.15 K0
  G3 X0.4 Z-0.2 R0.2
IF [#1 LT 3] GOTO 10
(grbl_pcb_isolation.nc as LinuxCNC reads it: no $ lines, G0 written, M2 added)
G0 Z1000.000 ; grbl starts in G0: a bare axis word moves
(pcb2gcode-style isolation pass, grbl 1.1)
G94 ( Millimeters per minute feed rate. )
G20 ( Units == Millimeters. )
  G1 Z-0.3
G0 Z5
  G2 X0.3 Z-0.15 I0.15 K0
  G1 Z-1000000.000
  X0.2
G1 Y60
G3 X60 Y70 I-10 J0
G1 X20
  M73
  S1200 M4 M7
  G1 X5 Y5 F200
  M9
o<rough> endsub
#<_row> = 200
G21 G90 G17
S3000 M3 M8
G3 X10 Y60 J-10
G1 Y20
G3 X20 Y10 I10
G1 X60
G3 X70 Y20 J10
G1 Y40
G3 X60 Y50 I-10 (lead-out arc)
G40 G1 X50 Y40
G0 Z5
G53 G0 Z0
M5
M30
