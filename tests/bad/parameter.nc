; expect 2:5 235
G0 X#<depth>
M2
