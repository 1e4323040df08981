(TX-07: Messschnitt in Ausblendsätzen, Passung 28,02)
%
O 7
G 59 X 0 Z 210
N6 G96 V250 T0606 M04 (Aufruf Schlichtwerkzeug)
/G00 X28,5 Z1 M08
/G01 Z-30 F0,15 (Meßschnitt)
/G01 X42
/G26
/M00 
/T0606
G00 X28,02 Z1 M08
G01 Z-30 F0,15 (Passung 28,02 drehen)
G26
M30
%
