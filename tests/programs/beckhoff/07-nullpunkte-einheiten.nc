%nullpunkte
(Nullpunktverschiebungen G54/G55, G53 abwaehlen; Zolleingabe G70)
N10 G17 G90 G71
N20 T4 D4
N30 S2000 M03
N40 G54 G00 X0 Y0 Z5
N50 G01 Z-1 F300
N60 X50
N70 G00 Z5
N80 G55 X0 Y0
N90 G70 (ab hier Zoll)
N100 G01 Z-0.04 F12
N110 X2
N120 G00 Z0.2
N130 G71 G53 (metrisch, ohne Nullpunktverschiebung)
N140 G00 Z100
N150 M30
