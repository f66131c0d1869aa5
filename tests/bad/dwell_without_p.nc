; expect 2:1 209
G4 S100
M2
