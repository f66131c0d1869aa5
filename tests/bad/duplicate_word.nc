; expect 2:10 202
G0 X1 Y2 X3
M2
