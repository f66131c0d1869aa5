; T beyond int: static_cast<int> of 1e+11 in the interpreter (UBSan float-cast-overflow).
T99999999999
M2
