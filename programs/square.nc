%
(square.nc: a 20 mm square with sharp corners at 1200 mm/min, continuous mode G64:)
(the Acc/Dec filter blends each corner; compare with exact-stop.nc)
G21 G17 G90 G64
G0 X0 Y0 Z1
G1 Z0 F300
G1 X20 F1200
Y20
X0
Y0
G0 Z1
M2
%
