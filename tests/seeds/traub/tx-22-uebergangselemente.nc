(TX-22: Uebergangselemente D und R)
G95
G97 S1000 T0101 M4
(Fase D0.5 an der Planflaeche)
G0 X0 Z1 M8
G1 Z0 F0.2
G1 X40 D0.5 E0.1
G1 Z-30
G0 X44
G0 Z1
(Radius R0.5)
G0 X0
G1 Z0 F0.2
G1 X40 R0.5 E0.1
G1 Z-30
G0 X44
G0 Z1
(Geometriezug mit Fasenlaenge D-2)
G0 X0
G1 Z0 F0.2
G1 A100 D-2
G1 X86 Z-35 A-30
G0 X90
G0 Z1
(Geometriezug mit Radius R2)
G0 X0
G1 Z0 F0.2
G1 A100 R2
G1 X86 Z-35 A-30
G0 X100
G0 Z1
(Uebergang Gerade - Kreisbogen mit Radius)
G0 X40
G1 Z-20 R6 F0.2
G3 X96 Z-48 R28
G0 X100 Z50 M9
M30
