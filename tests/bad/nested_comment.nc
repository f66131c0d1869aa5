; expect 2:10 105
G0 X1 (a (b) c)
M2
