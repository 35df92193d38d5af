O2003 (the slot of slot.nc, 2 mm deep in two passes; the second pass' depth mistyped)
T11 M06
S3000 M03
M08
G90 G00 X-150. Y-100.
Z-49.
G01 Z-51. F400
X-90. F1200
G01 Z-70. F400          ; meant Z-52.: below Z's first soft limit (-60 mm)
X-150. F1200
G00 Z0
M09
M05
M30
