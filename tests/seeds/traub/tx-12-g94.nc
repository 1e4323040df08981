(TX-12: Querbohren mit angetriebenem Werkzeug, 800 1/min x 0,1 mm/U = F80 mm/min)
%
O 12
G 59 X 0 Z 210
N5 T0505 M5 M22 M23 B060800
G00 Z-20
G00 X50 M8
G94
G01 X20 F80
G00 X50
G95
M 30
%
