(inverse-time.nc: G93 feeds become units/min over the path length, helix included)
G21 G17 G90
G93 G1 X10 F2
G1 X40 Y40 F1
G2 X80 Y0 I20 J-20 Z5 F3
G0 X0 Y0 Z0
G1 X5 F10
G94 G1 X0 F100
M2
