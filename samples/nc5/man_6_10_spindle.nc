O0610 (manual 6.10 with samples/nc5/man_6_10_spindle.il)
S1000
M03          ; forward: the flow ends at speed
G04 P200
M04          ; reverse: through 0 to -1000 rpm
M05          ; stop: ends at zero speed
M19          ; orientation: ends when oriented
M30
