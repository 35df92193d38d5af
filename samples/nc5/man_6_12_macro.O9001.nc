O9001 (the one-key macro of man_6_12_macro: down 2 mm and back up)
G91 G01 Z-2. F600
Z2.
M99
