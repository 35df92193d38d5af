O0620 (manual 6.2 with samples/nc5/man_6_2_cycle.il: a cut, an optional stop, a skippable block)
N10 G90 G01 X10. F600    ; 10 mm at 600 mm/min: 1 s at 100 %
N20 M01                  ; stops here only while optional stop (M21009) is On
/N30 G01 Y5.             ; skipped while block skip (M21010) is On
N40 G04 P200             ; dwell 0.2 s
N50 X0                   ; back at the F in force
N60 M30
