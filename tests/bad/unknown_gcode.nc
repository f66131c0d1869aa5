; expect 2:1 204
G41 D1
M2
