; expect 3:14 114
#1=2
G0 X[COS[#1] PLUS 1]
M2
