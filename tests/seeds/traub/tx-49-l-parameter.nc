(TX-49: Wertzuweisung vor dem Aufruf; L 2 = [L 1 + 5] rechnet)
%
O 49
G 59 X 0 Z 210
G 97 S 800 T 0101 M 3
L 1 = 20
L 2 = 25
G 22 A 8010
L 2 = [L 1 + 5]
M 30
%
%
O 8010
G 0 X L2 Z 2
G 1 Z-L1 F 0,1
G 0 X[L2 + 10]
M 99
%
