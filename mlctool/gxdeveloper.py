"""The header GX Developer's project files share: a program body (`.wpg`, mlctool/wpg.py) and
a device comment file (`.wcd`, mlctool/wcd.py) start with the same 0x40 bytes (docs/formats.md:
what every public file holds).

- 0x00: u16 0x0040 (the header's length), then `22 01`: the signature;
- 0x04-0x23: a 32-byte title (spaces or text; not read);
- 0x26: u16, the CPU type, as the project's Gppw.gps stores it (lCpuType).

One table of the FX CPUs for both readers, so a project's body and its comments are read, or
refused, alike.
"""

from __future__ import annotations

import struct

SIGNATURE = b"\x40\x00\x22\x01"
HEADER = 0x40
CPU_AT = 0x26

# MX Component's CPU type codes of the FX family (its public ActDefine headers), the code GX
# Developer writes at 0x26 and as lCpuType in the project's Gppw.gps (120 of the 121 public
# bodies agree with their project's, docs/formats.md). FX numbers X and Y in octal; the A and
# Q CPUs (0x01xx, 0x00xx) number them in hexadecimal, and their specials and step counts are
# another series': their programs and comments are another PLC's devices.
FX_CPUS = {
    0x0201: "FX0/FX0S", 0x0202: "FX0N", 0x0203: "FX1", 0x0204: "FX2/FX2C", 0x0205: "FX2N/FX2NC",
    0x0206: "FX1S", 0x0207: "FX1N/FX1NC", 0x0208: "FX3U/FX3UC", 0x0209: "FX3G/FX3GC", 0x020A: "FX3S",
}
OTHER_SERIES = {0x01: "an A-series CPU", 0x00: "a Q/QnA-series CPU"}  # by the code's high byte


def is_gx_developer_file(head: bytes) -> bool:
    """A GX Developer project file (a body or a comment file) by its first bytes."""
    return head[:len(SIGNATURE)] == SIGNATURE


def cpu_type(data: bytes) -> int:
    """The CPU type of a header at least CPU_AT + 2 bytes long."""
    return struct.unpack_from("<H", data, CPU_AT)[0]


def not_fx(cpu: int) -> str:
    """Why a CPU type is no FX CPU to read ("" for an FX CPU)."""
    if cpu in FX_CPUS:
        return ""
    return OTHER_SERIES.get(cpu >> 8, "no FX CPU")
