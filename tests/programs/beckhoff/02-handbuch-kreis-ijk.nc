%kreis
(Kreise mit Mittelpunkt: I J K relativ mit G162 in der Grundstellung, absolut mit G161; Vollkreis mit I allein)
N05 T4 D4
N06 S1800 M03
N10 G17 G90 G00 X20 Y40 Z2
N20 G01 Z-2 F300
N30 G02 X60 Y40 I20 J0 F400
N40 G02 I-20 (Vollkreis um X40 Y40)
N50 G161 G03 X100 Y40 I80 J40 (Mittelpunkt absolut)
N60 G162
N70 G91 G02 X-40 I-20 (Kettenmass, Y und J weggelassen)
N80 G90 G00 Z20
N90 M30
