(TX-44: 4 Querbohrungen im Abstand von 90 Grad; der Abschnitt N100 bis N200 läuft einmal und dann dreimal)
%
O102
G59 X0 Z150
N7 T707 M5
G94 M22 M23
B061000
G0 X30 Z-10 M8
N100 G1 X10 F100
G0 X30
N200 B074090 (Hauptspindel um 90 Grad positionieren)
G22 P100 Q200 H3
G26
M30
%
