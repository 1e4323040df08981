(TX-26: Bohren und Einstechen mit 0,5 s Verweilzeit)
%
O 26
G 59 X 0 Z 210
G 97 S 1000 T 0202 M 3
G 0 X 0 Z 5 M 8
G 1 Z-30 F0.2
G 4 X0.5 (0,5 sek. Verweilzeit)
G 0 Z 5
G 26
G 96 V 150 T 0303 M 4
G 0 X 61 Z-15 M 8
G 1 X 40 F 0.1
G 4 X 0.5 (0,5 sek. Verweilzeit)
G 0 X 61
G 26
M 30
%
