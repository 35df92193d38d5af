O0680 (manual 6.8 with samples/nc5/man_6_8_mst.il: the example's three codes)
M100
S10000
T3
M30
