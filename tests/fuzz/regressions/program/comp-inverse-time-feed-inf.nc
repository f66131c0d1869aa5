; G93 under G42: F1e308 over a 10 mm compensated line handed on a feed of inf mm/min
; (the range check was made on moves outside compensation only).
T1 M6
G0 X-8 Y0
G42 G1 X0 Y0 F400
G93 G1 X10 F[10 ** 308]
M2
