; expect 3:1 117
G0 X1
(ABORT, tool #<_current_tool> not measured)
G0 X2
M2
