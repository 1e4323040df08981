(TX-06: das angetriebene Werkzeug wird vor B06 eingeschaltet, M22 und M24)
%
O 6
T 101 M 22 M 24 B 062150
B 06 3500
M 30
%
