"""Synchronous and transferred axes (5.3.11, 5.3.12, 6.15, 6.16). sync_B=Y makes Y the master
of B (N2.015; '-Y' N2.016's opposite direction). M2x256 with M2x288+ (follow) and M2x257 with
M2x304+ (receive) take effect when 6.15 note 3 says: at once in JOG/MPG, at the end of an M
code's handshake in AUTO/MDI, at the axis' home start in HOME. A follower moves with its
master; the program ignores its own moves; a transfer moves the receiver instead of the
master (in AUTO/MDI only)."""

from __future__ import annotations

from nc5kit import run

JOG = "LDI M0\nMOV K4 D21000\nLD X3\nOUT M21385\n"  # JOG mode; X3 jogs Y + (at 1000 mm/min: 50 %)


def test_gantry_in_jog_follows_at_once_and_the_minus_master_mirrors():
    run(JOG, "model nc5 axes=X,Y,Z,B sync_b=Y\n0ms M21256=1 M21292=1\n20ms X3=1\n"
             "520ms expect NC1.Y.pos=8333 NC1.B.pos=8333 M31468=1 M31484=1\n"  # B moving + with Y
             "520ms X3=0 M21292=0\n600ms X3=1\n700ms expect NC1.B.pos=8333 NC1.Y.pos=10000\n")
    run(JOG, "model nc5 axes=X,Y,Z,B start=0,0,0,50 sync_b=-Y\n0ms M21256=1 M21292=1\n20ms X3=1\n"
             "520ms expect NC1.Y.pos=8333 NC1.B.pos=41667 M31500=1\n")


def test_in_auto_the_m_code_handshake_turns_it_on_and_the_program_leaves_the_follower():
    il = ("LD M31064\nAND= D31048 K171\nSET M21256\nSET M21292\n"
          "LD M31064\nAND= D31048 K172\nRST M21256\nRST M21292\n"
          "LD M31064\nOUT M21016\nLD X2\nOUT M21000\n")
    # before M171: Y to 5, B stays; after it B follows Y 5 -> 10 (its own B-20. ignored);
    # M172: off, Y back to 0, B stays
    run(il, "model nc5 program=part.nc axes=X,Y,Z,B sync_b=Y\n0ms X2=1\n"
            "500ms expect NC1.Y.pos=5000 NC1.B.pos=0 NC1.state=4\n"
            "1000ms expect NC1.Y.pos=9900 NC1.B.pos=4900 M31468=1\n"
            "2200ms expect NC1.Y.pos=0 NC1.B.pos=5000 M31016=0\n",
        "G01 Y5. F600\nM171\nY10. B-20.\nM172\nY0\nM30\n")


def test_transfer_moves_the_receiver_instead_of_the_master_in_auto():
    il = "LDI M0\nOUT M21257\nOUT M21310\nLD M31064\nOUT M21016\nLD X2\nOUT M21000\n"
    run(il, "model nc5 program=part.nc axes=X,Y,Z,U sync_u=Z\n0ms X2=1\n"
            "500ms expect NC1.Z.pos=0 NC1.U.pos=-9600 M31466=0 M31470=1 M31502=1\n"
            "1000ms expect NC1.Z.pos=0 NC1.U.pos=-10000 M31470=0\n", "M171\nG01 Z-10. F1200\nM30\n")


def test_in_home_mode_the_relation_is_checked_at_the_home_start():
    run("LDI M0\nMOV K7 D21000\nOUT M21256\nOUT M21292\nLD X3\nOUT M21321\n",
        "model nc5 axes=X,Y,Z,B start=0,-6,0,-4 sync_b=Y home_speed=600\n"
        "100ms expect NC1.B.pos=-4000 NC1.Y.pos=-6000\n100ms X3=1\n"
        "1000ms expect NC1.Y.pos=0 NC1.B.pos=2000 M31321=1\n")  # B followed Y's 6 mm
