O0611 (manual 6.11 with samples/nc5/man_6_11_gear.il)
M61      ; gear 1
M62      ; gear 2
M64      ; gear 4
M30
