; expect 3:1 216
; E is a word letter (M66..M68), not an exponent: a block with E and no code to use it (rs274: "E word with no ... to use it")
E5 G0
M2
