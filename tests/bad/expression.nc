; expect 2:7 230
G0 X[1/0]
M2
