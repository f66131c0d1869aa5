; expect 3:1 207
G21
G1 X10
M2
