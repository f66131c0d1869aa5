; expect 2:1 240
o100 endwhile
M2
