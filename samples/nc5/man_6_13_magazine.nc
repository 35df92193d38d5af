O0613 (manual 6.13 with samples/nc5/man_6_13_magazine.il)
T5       ; pot 5 from pot 1: 4 forward
T14      ; pot 14 from pot 5: 9 forward is 7 reverse, the short way
T14      ; in the spindle already: nothing to do
T5       ; tool 5 went into pot 14 at the last exchange: at the arm already
M30
