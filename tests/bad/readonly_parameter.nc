; expect 3:1 234
G0 X1
#5420=1
M2
