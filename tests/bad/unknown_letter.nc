; expect 3:4 203
G21
G0 L5
M2
