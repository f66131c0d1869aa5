; expect 2:5 106
G0 X#1
M2
