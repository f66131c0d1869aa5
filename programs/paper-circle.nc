%
(paper-circle.nc: the circle test of Chen & Lee 1998, Fig. 13 and Fig. 17)
(R = 4000 BLU = 4 mm at 1 um BLU; V_tan = 15000 BLU/s = 15 mm/s = 900 mm/min; T = 4 ms)
(three full turns so the middle of the arc is in steady state for every profile)
G21 G17 G90 G61
G0 X4 Y0
G3 X4 Y0 I-4 J0 P3 F900
M2
%
