(TX-15: die Steuerung rechnet S aus V 25 und X 10 und hält sie)
%
O 15
G 59 X 0 Z 210
N2 G 97 V 25 X 10 T0202 M3
 G0 X0 Z2 M8
 G1 Z-20 F0.1
M 30
%
