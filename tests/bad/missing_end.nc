; expect 3:1 401
G1 F100 X1
G1 X2
