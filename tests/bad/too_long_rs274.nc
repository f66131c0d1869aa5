; expect 3:253 110 (rs274: Command too long; 252 characters and a newline are accepted)
G21 G90
G1 X10 Y10 F500 (roughing pass at full depth, stepover 40 percent, climb milling, coolant on roughing pass at full depth, stepover 40 percent, climb milling, coolant on roughing pass at full depth, stepover 40 percent, climb milling, coolant on roughin)
M2
