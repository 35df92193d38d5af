"""GX Developer device comments: a project's `COMMENT.wcd` (and a program's own `MAIN.wcd`,
`SUB1.wcd`, the same layout) -> each commented device, as FX writes it, with its alias and
comment text.

No public document describes the file. The layout below is what every public file holds
(docs/formats.md names the repositories and commits; none is copied into the tests), and each
field is checked: a file that breaks any of it is refused with the offset (E936-E939), never
guessed at.

- 0x00-0x3F, the header a GX Developer program body (.wpg) starts with too (mlctool/gxdeveloper.py:
  the signature, the CPU type at 0x26, the FX CPUs read): `04 02` at 0x24, 0xFF from 0x28.
- 0x40, the device table: u32 its length (10 + 10 x entries), u16 0, u8 the comment width
  (16 or 32 bytes: the project's setting), u8 the alias width (8), u16 the entries; each entry
  `u16 device type, u32 first device number, u32 count`: a run of commented devices, the
  runs sorted by (type, number), never empty, never touching one another.
- Then one record a device, run after run: the alias (8 bytes), the comment (the width),
  padded with spaces. The file ends with the last record.

The text is in the code page of the Windows that wrote the file (CP932 Japanese and CP950
Chinese among the public files) and the file does not say which: ASCII is read as it is, any
other byte needs the encoding named (E939).
"""

from __future__ import annotations

import dataclasses
import struct

from mlctool.gxdeveloper import CPU_AT, FX_CPUS, HEADER, cpu_type, is_gx_developer_file, not_fx

TITLE_AT, TITLE_END = 0x04, 0x24
VERSION_AT, VERSION = 0x24, b"\x04\x02"
FILL_AT = 0x28
TABLE_AT = HEADER
TABLE_HEAD = 10  # u32 length, u16 0, u8 comment width, u8 alias width, u16 entries
ENTRY = 10  # u16 device type, u32 first number, u32 count
ALIAS_WIDTH = 8
COMMENT_WIDTHS = (16, 32)
# The largest public file is 24,466 bytes; every FX device commented at 40 bytes a record is
# under 2 MiB. A larger file is refused unread.
MAX_FILE = 4 * 1024 * 1024

# Device type -> (the FX device, octal numbers, the lowest number). The codes are those of the
# GX Works2 program tokens (mlctool/gxw_tokens.toml) and every public file agrees: X 0x9C and
# Y 0x9D (kacper97 X0-X11, Y0-Y5), M 0x90, T 0xC2 (the T comments of Super0415), D 0xA8
# (maelstro). 0x91 holds the special relays M8000 up (kacper97: M8000, M8002), as a Q CPU's SM.
# DECISION: 0xA9 is the special registers D8000 up, as 0x91 is for M (the public files hold it
# only from an A CPU, D9000 up); 0xC5 is C, the GX Works2 token of a counter (no public .wcd
# holds a C comment). Any other code (S, the state relays, among them: no public file shows its
# code) is refused (E938).
DEVICES = {
    0x90: ("M", False, 0),
    0x91: ("M", False, 8000),
    0x9C: ("X", True, 0),
    0x9D: ("Y", True, 0),
    0xA8: ("D", False, 0),
    0xA9: ("D", False, 8000),
    0xC2: ("T", False, 0),
    0xC5: ("C", False, 0),
}


class WcdError(Exception):
    """A file mlctool cannot read: a code of codes.toml, the offset, what is wrong there."""

    def __init__(self, code: str, offset: int, message: str, *notes: str):
        super().__init__(message)
        self.code, self.offset, self.message, self.notes = code, offset, message, notes

    def __str__(self) -> str:
        return f"offset 0x{self.offset:X}: {self.message}"


@dataclasses.dataclass(frozen=True)
class Comment:
    device: str  # as FX writes it: X17 (octal), M8000, D100
    alias: str  # "" none
    text: str  # "" none
    offset: int  # of its record


@dataclasses.dataclass(frozen=True)
class Comments:
    cpu: str  # FX3U/FX3UC
    width: int  # of a comment, bytes
    comments: tuple[Comment, ...]  # devices with an alias or a comment, in the file's order


def is_wcd(head: bytes) -> bool:
    """A GX Developer file by its first bytes (a comment file, or a program body given in its place)."""
    return is_gx_developer_file(head)


def read(data: bytes, encoding: str | None = None) -> Comments:
    """The comments of a `.wcd` file's bytes; WcdError for anything the layout does not hold.
    `encoding` decodes the text (None: ASCII only)."""
    if len(data) > MAX_FILE:
        raise WcdError("E937", MAX_FILE, f"larger than {MAX_FILE} bytes, which no comment file is")
    width = _header(data)
    runs = _runs(data, width)
    record = ALIAS_WIDTH + width
    offset = TABLE_AT + TABLE_HEAD + ENTRY * len(runs)
    out = []
    for kind, first, count in runs:
        letter, octal, _ = DEVICES[kind]
        for number in range(first, first + count):
            alias = _text(data, offset, ALIAS_WIDTH, encoding)
            text = _text(data, offset + ALIAS_WIDTH, width, encoding)
            if alias or text:  # DECISION: a record of spaces is no comment
                out.append(Comment(f"{letter}{number:o}" if octal else f"{letter}{number}", alias, text, offset))
            offset += record
    return Comments(FX_CPUS[cpu_type(data)], width, tuple(out))


def _header(data: bytes) -> int:
    """The comment width, once the header is checked."""
    if not data:
        raise WcdError("E936", 0, "empty file: neither a device-comment CSV nor a GX Developer comment file")
    if not is_wcd(data):
        raise WcdError("E936", 0, f"starts {data[:4].hex(' ')}, not 40 00 22 01 (a GX Developer file)")
    if len(data) < TABLE_AT + TABLE_HEAD:
        raise WcdError("E937", len(data), f"truncated: the file ends at {len(data)} bytes, inside the header "
                       f"({TABLE_AT + TABLE_HEAD} bytes)")
    if data[VERSION_AT:CPU_AT] != VERSION:
        raise WcdError("E936", VERSION_AT, f"{data[VERSION_AT:CPU_AT].hex(' ')} where every GX Developer file "
                       f"read holds {VERSION.hex(' ')}")
    cpu = cpu_type(data)
    family = not_fx(cpu)
    if family:
        raise WcdError("E936", CPU_AT, f"CPU type 0x{cpu:04X}: {family}, whose X/Y numbering and special "
                       "devices are not FX's (FX: 0x0201-0x020A)",
                       "its devices would become other devices of an FX-style target; comment the program "
                       "by hand, or convert the project to an FX CPU in GX Developer first")
    fill = data[FILL_AT:TABLE_AT]
    if fill != b"\xff" * len(fill):
        at = FILL_AT + next(k for k, b in enumerate(fill) if b != 0xFF)
        raise WcdError("E936", at, f"byte 0x{data[at]:02X} in the header's 0xFF fill (0x{FILL_AT:X}-0x{TABLE_AT - 1:X})")
    _, zero, width, alias, _ = struct.unpack_from("<IHBBH", data, TABLE_AT)
    if zero:
        raise WcdError("E936", TABLE_AT + 4, f"0x{zero:04X} where the comment table's header holds 0")
    if width not in COMMENT_WIDTHS:
        raise WcdError("E936", TABLE_AT + 6, f"comment width {width}: GX Developer writes 16 or 32")
    if alias != ALIAS_WIDTH:
        raise WcdError("E936", TABLE_AT + 7, f"alias width {alias}: GX Developer writes {ALIAS_WIDTH}")
    return width


def _runs(data: bytes, width: int) -> list[tuple[int, int, int]]:
    """The device table's runs (type, first number, count), checked against each other and
    the file's length."""
    length, _, _, _, entries = struct.unpack_from("<IHBBH", data, TABLE_AT)
    if length != TABLE_HEAD + ENTRY * entries:
        raise WcdError("E937", TABLE_AT, f"the comment table says {length} bytes; its {entries} entries take "
                       f"{TABLE_HEAD + ENTRY * entries}")
    records_at = TABLE_AT + length
    if len(data) < records_at:
        raise WcdError("E937", len(data), f"truncated: the file ends at {len(data)} bytes, inside the comment "
                       f"table (it ends at {records_at})")
    runs: list[tuple[int, int, int]] = []
    for k in range(entries):
        at = TABLE_AT + TABLE_HEAD + ENTRY * k
        kind, first, count = struct.unpack_from("<HII", data, at)
        if kind not in DEVICES:
            raise WcdError("E938", at, f"device type 0x{kind:04X}: not one mlctool reads (X Y M T C D, "
                           "M8000 and D8000 up)", "docs/formats.md lists the device types read and why")
        if count == 0:
            raise WcdError("E937", at + 6, "a run of no devices")
        if first < DEVICES[kind][2] or first + count > 1 << 32:
            raise WcdError("E937", at + 2, f"devices {first}-{first + count - 1} of type 0x{kind:02X}: outside "
                           f"its numbers ({DEVICES[kind][2]} up)")
        if runs and (kind, first) <= runs[-1][:2]:
            raise WcdError("E937", at, "the runs are out of order (sorted by device type and number in every "
                           "file read)")
        if runs and kind == runs[-1][0] and first <= runs[-1][1] + runs[-1][2]:
            raise WcdError("E937", at, f"this run (from {first}) meets the one before it "
                           f"({runs[-1][1]}-{runs[-1][1] + runs[-1][2] - 1}): GX Developer writes one run")
        runs.append((kind, first, count))
    total = sum(c for _, _, c in runs)
    end = records_at + total * (ALIAS_WIDTH + width)
    said = f"the table's {total} records of {ALIAS_WIDTH + width} bytes end at {end}"
    if len(data) < end:
        raise WcdError("E937", len(data), f"truncated: the file ends at {len(data)} bytes; {said}")
    if len(data) > end:
        raise WcdError("E937", end, f"{len(data) - end} bytes after the last record: {said}")
    return runs


def _text(data: bytes, at: int, width: int, encoding: str | None) -> str:
    """A field's text, the padding stripped; WcdError for a control byte or text the encoding
    does not give."""
    raw = data[at:at + width]
    for k, b in enumerate(raw):
        if b < 0x20 or b == 0x7F:
            raise WcdError("E939", at + k, f"byte 0x{b:02X} (a control code) in a comment record")
        if b >= 0x80 and encoding is None:
            raise WcdError("E939", at + k, f"byte 0x{b:02X}: the comment is not ASCII and the file does not "
                           "name its code page", "name it with --encoding: cp932 (Japanese), cp950 "
                           "(Traditional Chinese), cp936 (Simplified Chinese), cp1252 (Western) ...")
    try:
        text = raw.decode(encoding or "ascii")
    except UnicodeDecodeError as e:
        raise WcdError("E939", at + e.start, f"byte 0x{raw[e.start]:02X}: not {encoding} text") from None
    bad = next((k for k, c in enumerate(text) if 0x80 <= ord(c) <= 0x9F), None)
    if bad is not None:
        raise WcdError("E939", at + len(text[:bad].encode(encoding or "ascii")),
                       f"{text[bad]!r} (a control code in {encoding}) in a comment record")
    return text.strip(" ")
