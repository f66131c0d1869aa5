%
(pocket.nc: a CAM-style part: a 30 x 20 mm rounded-rectangle pocket, 2 mm deep in two passes,)
(ramped entry, concentric offsets with IJK corner arcs, finishing pass, as a CAM post would write it)
(tool: 6 mm end mill, T1, work offset G54)
G21 G17 G40 G49 G90 G94 G64
T1 M6
G54
S12000 M3
G0 X15 Y10 Z5
(pass 1: ramp down to Z-1 along X)
G1 Z0.5 F300
G1 X20 Z-1 F400
G1 X10 Y10 F400
G1 X15
(offset 1: 10 x 4 mm rectangle around the centre, R1 corners)
G1 X9 Y8 F900
G1 X21 Y8
G3 X22 Y9 I0 J1
G1 X22 Y11
G3 X21 Y12 I-1 J0
G1 X9 Y12
G3 X8 Y11 I0 J-1
G1 X8 Y9
G3 X9 Y8 I1 J0
(offset 2: 20 x 10 mm, R3 corners)
G1 X7 Y5
G1 X23 Y5
G3 X25 Y7 I0 J2
G1 X25 Y13
G3 X23 Y15 I-2 J0
G1 X7 Y15
G3 X5 Y13 I0 J-2
G1 X5 Y7
G3 X7 Y5 I2 J0
(pass 2: ramp to Z-2 and repeat the outer offset)
G1 X15 Y5 Z-2 F400
G1 X23 F900
G3 X25 Y7 I0 J2
G1 X25 Y13
G3 X23 Y15 I-2 J0
G1 X7 Y15
G3 X5 Y13 I0 J-2
G1 X5 Y7
G3 X7 Y5 I2 J0
G1 X15
(finishing pass on the wall, 30 x 20 with R3 corners, tangential arc lead-in)
G3 X15 Y2 R1.5 F600
G1 X27
G3 X30 Y5 R3
G1 Y15
G3 X27 Y18 R3
G1 X3
G3 X0 Y15 R3
G1 Y5
G3 X3 Y2 R3
G1 X15
G0 Z5
M5
G0 X0 Y0
M30
%
