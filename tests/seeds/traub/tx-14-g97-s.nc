(TX-14: Bohrer 10 mm, V = 25 m/min ergibt S = 795,8, programmiert S800)
%
O 14
G 59 X 0 Z 210
N2 G 97 S 800 T0202 M3
 G0 X0 Z2 M8
 G1 Z-20 F0.1
M 30
%
