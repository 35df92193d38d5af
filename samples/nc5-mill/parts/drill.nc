O2001 (four holes 5 mm deep at the corners of a 40 x 30 mm rectangle, with tool 3)
T3 M06                  ; tool change: the magazine turns to tool 3, the arm swaps it in
S1200 M03               ; spindle forward, the program waits until it is at speed
M08                     ; coolant on
G90 G00 X-120. Y-80.    ; first hole
Z-45.                   ; 5 mm above the part (its top at Z-50.)
G01 Z-55. F600          ; drill
G00 Z-45.
X-80.                   ; second hole
G01 Z-55.
G00 Z-45.
Y-50.                   ; third hole
G01 Z-55.
G00 Z-45.
X-120.                  ; fourth hole
G01 Z-55.
G00 Z0                  ; spindle up
M09                     ; coolant off
M05                     ; spindle stop, waits until it stands
M30
