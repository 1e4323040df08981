(TX-17: G0/G1/G2/G3 - Uebersichtskontur, mit Werkzeugaufruf und Programmende ergaenzt)
G95
G97 S1200 T0101 M4
G0 X20 Z2 M8
G1 Z-15 F0.2
G2 X40 Z-25 R10
G1 Z-40
G3 X60 Z-50 R10
G1 Z-75
G0 X100 Z50 M9
M30
