; expect 2:5 107
G0 X[1+1]
M2
