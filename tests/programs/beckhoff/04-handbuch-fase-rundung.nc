%fase
(Fasen und Rundungen: zwischen je zwei Verfahrsaetzen hoechstens ein G301 oder G302)
N05 T4 D4
N06 S1800 M03
N10 G17 G00 G90 X-10 Y-10 Z2
N20 G01 Z-2 F300
N30 X0 Y0
N40 G01 X100 F500
N50 G301 I10 (Fase 10 x 45 Grad)
N60 Y60
N70 G302 I15 (Rundung R15, I bleibt gespeichert)
N80 X0
N90 G302 (R15 aus dem letzten G302)
N100 Y0
N110 G00 Z20
N120 M30
