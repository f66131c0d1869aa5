; expect 2:5 206
G21 X10
M2
