; expect 2:7 208
G1 X1 F-100
M2
