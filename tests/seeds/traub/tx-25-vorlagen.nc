(TX-25: die Vorlagen der Geometriezuege mit Zahlen)
G95
G97 S1000 T0101 M4
(Gerade - Kreisbogen tangential)
G0 X20 Z1 M8
G1 Z0 F0.2
G1 A180
G2 X40 Z-20 R10
G0 X44
(Kreisbogen - Gerade tangential)
G0 X0 Z1
G1 Z0
G3 R30
G1 X30 Z-30 A0
G0 X34
(Gerade - Kreisbogen H0 und H1)
G0 X40 Z1
G1 Z0
G1 A180
G2 X50 Z-30 P0 Q-30 H0
G0 X54
G0 X40 Z1
G1 Z0
G1 A180
G2 X50 Z-30 P0 Q-30 H1
G0 X54
(Kreisbogen + Fase - Gerade, Kreisbogen + Radius - Gerade)
G0 X0 Z1
G1 Z0
G3 P0 Q-28 D-2 H1
G1 X40 Z-27 A0
G0 X44
G0 X0 Z1
G1 Z0
G3 P0 Q-28 C3 H1
G1 X40 Z-27 A0
G0 X44
(Kreisbogen - Kreisbogen tangential)
G0 X0 Z1
G1 Z0
G3 P0 Q-10
G2 X40 Z-30 R10
G0 X100 Z50 M9
M30
