; expect 3:4 203
G21
G0 D5
M2
