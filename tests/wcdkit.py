"""Test fixtures: GX Developer device-comment files (`COMMENT.wcd`) laid out as mlctool/wcd.py
describes them (the layout every public file holds). Not GX Developer's own files: written here
from a {(device type, number): (alias, comment)} table.

- wcd(): the file: the 0x40-byte header (title of spaces, version 04 02, the CPU type, 0xFF
  fill), the device table (consecutive numbers of a type make one run), one record a device
  (the alias and the comment, each padded with spaces to its width).
"""

from __future__ import annotations

import struct

from mlctool.gxdeveloper import SIGNATURE as MAGIC
from mlctool.wcd import ALIAS_WIDTH, TABLE_HEAD, VERSION

FX3U = 0x0208


def runs(keys) -> list[tuple[int, int, int]]:
    """(type, first number, count) of sorted (type, number) keys, consecutive numbers one run."""
    out: list[list[int]] = []
    for kind, number in sorted(keys):
        if out and out[-1][0] == kind and out[-1][1] + out[-1][2] == number:
            out[-1][2] += 1
        else:
            out.append([kind, number, 1])
    return [(k, f, c) for k, f, c in out]


def wcd(comments: dict[tuple[int, int], tuple[bytes, bytes]], width: int = 32, cpu: int = FX3U) -> bytes:
    head = MAGIC + b" " * 32 + VERSION + struct.pack("<H", cpu) + b"\xff" * 24
    table = runs(comments)
    body = struct.pack("<IHBBH", TABLE_HEAD + 10 * len(table), 0, width, ALIAS_WIDTH, len(table))
    body += b"".join(struct.pack("<HII", *run) for run in table)
    for key in sorted(comments):
        alias, text = comments[key]
        body += alias.ljust(ALIAS_WIDTH, b" ") + text.ljust(width, b" ")
    return head + body
