%radius
(Radiusprogrammierung nach dem Handbuch: beide Beispiele ergeben Halbkreise mit Radius 50)
N05 T1 D1
N06 S1200 M03
N10 G90 G01 X0 Y0 F500
N20 G02 X100 R50
N30 G03 X200 R50
N40 G00 Z10
N50 G00 X0 Y-50
N60 G01 Z0 F500
N70 G02 R=50 (In this block still no motion)
N80 X100 (Motion block)
N90 G03 X200 (R50 gilt weiter)
N100 G00 Z10
N110 M30
