(TX-28: Abwahl der Schneidenradiuskompensation, Fall 1)
G95
G97 S1000 T0101 M4
G46
G0 X60 Z1 M8
G1 Z-30 F0.2
G1 X90 A135
G40
G0 X120 Z50 M9
M30
