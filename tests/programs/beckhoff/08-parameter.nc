%parameter
(Rechnen mit Parametern: Lochkreis-Anfahrpunkte, Tiefe als Parameter)
N10 P1 = 40 (Mitte X)
N20 P2 = 30 (Mitte Y)
N30 P3 = 2 (Tiefe)
N40 T2 D2
N50 S4000 M03
N60 G00 X=P1 Y=P2 Z2
N70 G01 Z=-P3 F150
N80 G01 X=P1+15 F300
N90 G03 I=-15 (Vollkreis R15)
N100 G01 X=P1
N110 G00 Z20
N120 M30
