(TX-27: Anwahl der Schneidenradiuskompensation, drei Beispiele; Abwahl jeweils mit G0 und A wie TX-28)
G95
G97 S1000 T0101 M4
G 46
G 0 X40 Z1 M8
G 1 Z-30 F0,2
G 0 X44 A180
G 40
G 0 X50 Z5
G 46
G 0 X30 Z1
G 1 Z0
G 1 X40 D2 F0,2 E0,1
G 1 Z-30
G 0 X44 A180
G 40
G 0 X50 Z5
G 46
G 0 X - 1,6 Z 1
G 1 Z 0 F 0,2
G 1 X 0
G 3 R 30
G 1 X 30 Z - 30 A 0
G 0 X 34 A 180
G 40
G 0 X100 Z50 M9
M30
