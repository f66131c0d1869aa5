; expect 2:1 204
G12 X1
M2
