; expect 2:1 241
o<pocket> call [10]
M2
