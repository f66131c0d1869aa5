; expect 2:7 104
G0 X1 (never closed
M2
