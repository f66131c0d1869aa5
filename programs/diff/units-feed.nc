(units-feed.nc: feed across G20/G21 changes; LinuxCNC executes F before G20/G21 in a block)
(and its canon keeps the physical feed rate when the length units change)
G21 G17 G90 G94
G1 X10 F600
G20
G1 X1
G1 X2 F10
G21 G1 X60
G20 G1 X3 F50
G1 Y1
G21
G1 Y30 F100
M2
