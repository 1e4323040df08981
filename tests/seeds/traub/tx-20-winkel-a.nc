(TX-20, erstes Beispiel; Startpunkt X40 Z1 wie in TX-21)
G0 X40 Z1 M8
G1 Z-25 F0.2
G1 X20 A 210 F0.1
G1 Z-65 F0.2
G1 X60 A135
(zweites Beispiel; Startpunkt X40 Z-60 angenommen)
G0 X40 Z-60
G1 X20 A-45 F0.1
G1 Z-37.32 F0.2
G1 X40 A30
G1 Z0
