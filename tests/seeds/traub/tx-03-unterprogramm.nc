(TX-03: Hauptprogramm mit Unterprogramm; die Punkte der Vorlage sind hier ausgefüllt)
%
O 4711
G 59 X 0 Z 210
G 96 V 200 T 0202 M 4
G 22 A 8001
M 30
%
%
O 8001
G 00 X 40 Z 2
G 01 X 20 F 0,2
M 99
%
