; expect 3:1 203
G21
E5 G0
M2
