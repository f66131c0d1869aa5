%
(override-replay.nc: a long arc and a line, run with override-replay.csv: the feed override steps)
(100 -> 50 -> 150 % in the middle of the arc, 100 % when the line on line 7 starts, then a hold at 0 % and a resume)
G21 G17 G90 G64
G0 X10 Y0
G3 X-10 Y0 I-10 J0 F1200
G1 X-10 Y-20 F1200
M2
%
