(TX-09: absolut, inkremental und gemischt; U ist ein Radiuswert)
%
O 9
G 59 X 0 Z 210
G 96 V 200 T 0101 M 4
G 0 X 30 Z 10
G 1 X 30 Z -15 F 0,2
G 1 X 60 Z -55
G 0 X 30 Z 10
G 1 Z -15
G 1 U 15 W -40
G 0 X 30 Z 10
G 1 Z -15
G 1 X 60 W -40
M 30
%
