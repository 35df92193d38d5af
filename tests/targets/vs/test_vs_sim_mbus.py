"""MBUS (FNC 149) in the VS coverage table: with no device on the port every request times
out (status 0AH, station in the high byte, error relay M9103). The exchange with a device
model is tested in tests/devices/test_xc100_cosim.py."""

from __future__ import annotations

from tests.targets.vs.test_vs_sim import run  # noqa: F401


def test_mbus_without_a_device_times_out():
    run(".table Q0 MBUS H03 K7 D0 H1000 K1\nLD X0\nMBUS Q0 D100 K1\nLD M9104\nOUT M0",
        "0ms X0=1\n400ms expect M9103=0 D101=1\n600ms expect M9103=1 D100=H070A M0=0\nrun 610ms\n")
