; expect 3:6 231
#<r>=-4
G0 X[SQRT[#<r>]]
M2
