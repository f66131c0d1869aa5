; expect 2:1 205
M97 P100
M2
