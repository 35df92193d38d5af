"""VS positioning (manual ch. 8): the pulse axes' moves (moves.py: JOGF ... PLSV), homing
(ZRN), positioning tables (DTBL), absolute reads (DABS), the hand wheel (MPG) and linear
interpolation (LIR/LIA). The axis motion itself is the engine's (mlctool/sim/motion.py)."""
