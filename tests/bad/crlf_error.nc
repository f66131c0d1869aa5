; expect 3:1 207
G21
G1 X1
M2
