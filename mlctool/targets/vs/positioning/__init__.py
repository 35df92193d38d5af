"""VS positioning (manual ch. 8): the pulse axes' moves (moves.py: JOGF ... PLSV), homing
(ZRN), positioning tables (DTBL), absolute reads (DABS), the hand wheel (MPG) and linear
interpolation (LIR/LIA).

Belongs here: the positioning instructions' routines. Does not belong here: the axis motion
itself (the engine's, mlctool/sim/hardware/motion.py), pulse outputs PLSY/PWM/PLSR (pulse_out.py).
"""
