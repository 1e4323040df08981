(TX-24: Schnittpunktangabe H0/H1; Kreisanfang X0 Z0 angenommen, die Zeichnung fehlt)
G95
G97 S1000 T0101 M4
G0 X0 Z1 M8
G1 Z0 F0.2
G3 P0 Q-28 H0
G1 X40 Z-10 A0
G0 X60
G0 X0 Z1
G1 Z0
G3 P0 Q-28 H1
G1 X40 Z-27 A0
G0 X100 Z50 M9
M30
