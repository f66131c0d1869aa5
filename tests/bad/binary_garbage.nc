; expect 3:3 103
G0 X1
G0
M2
