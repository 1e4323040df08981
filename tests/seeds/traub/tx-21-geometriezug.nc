(TX-21: Geometriezuege G1)
G95
G97 S1000 T0101 M4
(erstes Beispiel: Startpunkt X40 Z0 angenommen; R2 E0.08 ist eine Randnotiz, kein NC-Text)
G0 X40 Z1 M8
G1 Z0 F0.2
G1 A105
G1 X100 Z-50 A-30
G0 X104
(zweites Beispiel)
G0 X40 Z1
G1 Z-25 F0.2
G1 X20 A210 F0.1
G1 A180 F0.2
G1 X60 Z-85 A-45
G0 X100 Z50 M9
M30
