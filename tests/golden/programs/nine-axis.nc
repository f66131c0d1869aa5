(nine axes X Y Z A B C U V W through the whole pipeline, trivial kinematics)
(run with --axes XYZABCUVW; A B C in degrees, U V W parallel linear axes)
G21 G90 G94 G17
G0 X0 Y0 Z5 A0 B0 C0 U0 V0 W0
G1 X20 Y10 F1200                     (XYZ only)
G1 A90 B-45 C30 F3600                (rotary only: deg/min)
G1 U5 V-5 W2 F600                    (U V W only: their own path length)
G1 X30 Y20 Z2 A120 B0 C60 U8 V0 W0 F900 (all nine: X Y Z set the time)
G2 X40 Y10 I0 J-10 A180 W3 F1500     (arc in XY, A and W along)
G93 G1 X20 A90 U0 F120               (inverse time: 0.5 s)
G94 G0 X0 Y0 Z5 A0 B0 C0 U0 V0 W0
M2
