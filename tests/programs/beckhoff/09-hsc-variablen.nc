%hsc
(Befehle der Steuerung, die die Simulation noch nicht nachbildet: je ein Hinweis, die Bewegungen laufen)
N10 #HSC ON [SURFACE CONTOUR_DEVIATION=0.02]
N20 V.L.TIEFE = 3
N30 T2 D2
N40 S6000 M03
N50 G00 X10 Y10 Z2
N60 G01 Z-2 F300
N70 G01 X60
N80 G02 X80 Y30 R20
N90 G01 Y50
N100 #HSC OFF
N110 G00 Z20
N120 M30
