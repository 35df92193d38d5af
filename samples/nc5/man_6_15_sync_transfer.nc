O0615 (man_6_15_sync_transfer: Z moves alone, then with M171 its moves go to V, M172 ends it)
G90 G01 Z-5. F600
M171
Z-15.
M172
Z0
M30
