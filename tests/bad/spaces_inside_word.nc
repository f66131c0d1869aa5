; expect 2:13 201
G 0 1 X 1 0 G0
M2
