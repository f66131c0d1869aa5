(a facing macro called by a computed O-word number, then a Fanuc-style subprogram)
(called with a computed P: both numbers are expressions, as a post with a tool table writes)
G21 G90 G17
#<_tool> = 3
O[#<_tool> * 100] call [40] [25]
M98 P[#<_tool> * 100 + 1] L2
G0 Z20
M30
O300 sub
  G0 X0 Y0 Z5
  G1 Z-1 F200
  G1 X#1 F600
  G1 Y#2
  G1 X0
  G1 Y0
  G0 Z5
O300 endsub
O301
G91 G0 X5
G90
M99
