%
(cam-drill.nc: a CAM-style drilling program, as a post-processor writes one)
(safe start, tool change with length offset, work offset G54, spot, peck drill, G53 retract)
G17 G21 G40 G49 G80 G90
(T4: 5 mm spot drill)
T4 M6
G43 H4
G10 L2 P1 X50 Y40 Z0
G54
S3000 M3
G0 X0 Y0
G0 Z10
G99 G81 X0 Y0 Z-1.5 R2 F150
X20
X20 Y15
X0 Y15
G80
G53 G0 Z0
(T2: 3 mm drill, peck to 12 mm)
T2 M6
G43 H2
S4500 M3
G0 X0 Y0
G0 Z10
G98 G83 X0 Y0 Z-12 R2 Q3 F120
X20
X20 Y15
X0 Y15
G80
M5
G53 G0 Z0
G28 G91 Z0
G90
M30
%
