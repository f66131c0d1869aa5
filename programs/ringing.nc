%
(ringing.nc: a ringing test, a square wave of short strokes at a printer's speed, as)
(printed for Klipper's resonance calibration. Sharp corners in G64: after each corner the)
(axis that stopped rings at its structural mode while the other one moves on. Run it on)
(programs/machines/ringing-40hz.toml; docs/vibration.md shows the ringing and its cure.)
G21 G17 G90 G94 G64
G0 X0 Y0 Z1
G1 Z0 F600
F6000
G1 X40
G1 Y15
G1 X0
G1 Y30
G1 X40
G1 Y45
G1 X0
G1 Y60
G4 P0.3 (let the last corner ring out)
G0 Z1
M2
%
