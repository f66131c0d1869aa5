%
(syntax.nc: forms LinuxCNC accepts: lower case, spaces inside words, signs, leading dots,)
(N words, ; comments, comment-only and blank lines, multiple comments)
g21 g17 g90
N10 g0 x 1.5 y -.5 z+2
N20 G1 X 0002.500 F 1 2 0 (mid-line comment) Y1 (another)
   G1 Z0.   ; trailing comment

G4 P.25
g2 x4.5 y1 i1 J+0
M2
%
