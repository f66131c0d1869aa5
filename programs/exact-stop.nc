%
(exact-stop.nc: the same square as square.nc in exact-stop mode G61:)
(each block waits for the Acc/Dec output to settle, so the corners are sharp and it takes longer)
G21 G17 G90 G61
G0 X0 Y0 Z1
G1 Z0 F300
G1 X20 F1200
Y20
X0
Y0
G0 Z1
M2
%
