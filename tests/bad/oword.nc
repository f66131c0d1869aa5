; expect 2:1 108
o100 sub
M2
