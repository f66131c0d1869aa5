; expect 2:13 113
G0 X[1+[2*3]
M2
