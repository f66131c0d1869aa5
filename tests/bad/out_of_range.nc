; expect 2:5 102
G0 X1e400
M2
