; expect 2:8 101
G0 X1 Y
M2
