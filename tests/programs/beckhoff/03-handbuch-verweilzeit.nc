%verweilzeit
(Verweilzeit: die im Handbuch richtigen Formen, jede allein im Satz)
N05 T2 D2
N06 S3000 M03
N10 G00 X10 Y10 Z2
N20 G01 Z-1 F200
N30 G04 X4.13 (wait for 4.13 seconds)
N40 G04 2.13 (wait for 2.13 seconds)
N50 #TIME 1.5 (wait for 1.5 seconds)
N60 G01 X40
N70 G00 Z20
N80 M30
