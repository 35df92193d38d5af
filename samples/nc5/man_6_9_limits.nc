O0690 (manual 6.9's program, one word group a line; '/' added before M90: see below)
G90 G54 X100.
G0 Z-50.
/M90          ; skipped while block skip is On: the stimulus shows the alarm M90 avoids
G0 Z134.      ; past the first soft limit (70), inside the second (140)
M30
