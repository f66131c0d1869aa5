%
(inch.nc: an inch program: a 1 x 0.5 inch slot with R-format arcs at 20 inch/min)
G20 G17 G90 G64
G0 X0 Y0 Z0.1
G1 Z0 F10
G1 X1 F20
G3 X1 Y0.5 R0.25
G1 X0
G3 X0 Y0 R0.25
G0 Z0.1
G21 (back to mm: positions continue in the same machine coordinates)
G0 X0 Y0
M2
%
