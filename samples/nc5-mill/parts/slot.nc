O2002 (a 60 mm slot 2 mm deep, two passes with tool 11, the second pass skippable)
T11 M06                 ; 10 pots forward is 2 reverse: the short way round
S3000 M03
M08
G90 G00 X-150. Y-100.
Z-49.
G01 Z-51. F400          ; first pass, 1 mm into the part (its top at Z-50.)
X-90. F1200
/G01 Z-52. F400         ; second pass (skipped with block skip)
/X-150. F1200
G00 Z0
M09
M05
T11 M06                 ; tool 11 is in the spindle already: nothing to change
M30
