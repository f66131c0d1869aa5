; G43 H beyond int: static_cast<int> of 1e+11 before the tool-table lookup (UBSan).
G43 H99999999999
M2
