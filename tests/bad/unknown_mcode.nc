; expect 2:1 205
M98 P100
M2
