"""Test fixtures: GX Works2 project files (.gxw) written by the project's own code, for the
subset mlctool reads (mlctool/gxw.py). Not an exporter: a file GX Works2 opens needs state this
writer does not make (MAIN.res's copy of the program, compiler state, parameters; docs/formats.md).

- compound_file(): a compound file after the public [MS-CFB] specification, version 3
  (512-byte sectors, 64-byte mini sectors, cutoff 4096): header, FAT, MiniFAT, directory, the
  mini stream in the root entry, streams of 4096 bytes and more in sectors. One storage (the
  root) holding streams; up to 109 FAT sectors (the header's DIFAT), no DIFAT sectors.
- pou(): a program POU: a 0x4F-byte header (the length field twice at 0x37/0x3B), the tokens,
  24 zero bytes (or 20, as in public projects); instructions encoded by mlctool/gxw_tokens.toml
  read backwards (every header shape: basic, 2-byte [opcode steps], application with or without
  a form byte), a comment line a text record `82 00 text`.
- project(): the outer file: projectdatalist.xml and history.xml naming the POUs' numbered
  streams in _hdb, itself a compound file.
- il_project(): IL (the target's, `.dialect fx`) -> a project, in FX spelling (M9000 -> M8000)
  by mlctool.exports.family_rows.
"""

from __future__ import annotations

import base64
import hashlib
import math
import re
import struct

from mlctool.gxw import DIGITS, HEADER, LENGTH_BIAS, LENGTH_FIELDS, TRAILERS, registry

SECTOR, MINI, CUTOFF = 512, 64, 4096
FREE, END, FATSECT, NOSTREAM = 0xFFFFFFFF, 0xFFFFFFFE, 0xFFFFFFFD, 0xFFFFFFFF
SIGNATURE = bytes.fromhex("d0cf11e0a1b11ae1")


def _chain(fat: list[int], first: int, count: int) -> None:
    for k in range(count):
        fat[first + k] = first + k + 1 if k + 1 < count else END


def _key(name: str) -> tuple[int, str]:
    """[MS-CFB] 2.6.4: siblings compare by name length, then by the upper-cased names."""
    return len(name), name.upper()


def compound_file(streams: dict[str, bytes]) -> bytes:
    names = sorted(streams, key=_key)
    for n in names:
        if not 0 < len(n) <= 31 or any(c in n for c in "/\\:!"):
            raise ValueError(f"stream name {n!r}: 1-31 characters, none of / \\ : !")
    small = [n for n in names if 0 < len(streams[n]) < CUTOFF]
    large = [n for n in names if len(streams[n]) >= CUTOFF]
    mini_start, mini_data = {}, bytearray()
    minifat: list[int] = []
    for n in small:
        count = math.ceil(len(streams[n]) / MINI)
        mini_start[n] = len(minifat)
        minifat += [0] * count
        _chain(minifat, mini_start[n], count)
        mini_data += streams[n] + bytes(count * MINI - len(streams[n]))
    entries = 1 + len(names)
    n_dir = math.ceil(entries * 128 / SECTOR)
    n_minifat = math.ceil(len(minifat) * 4 / SECTOR)
    n_mini = math.ceil(len(mini_data) / SECTOR)
    n_large = [math.ceil(len(streams[n]) / SECTOR) for n in large]
    data_sectors = n_dir + n_minifat + n_mini + sum(n_large)
    n_fat = 1
    while n_fat * SECTOR // 4 < n_fat + data_sectors:
        n_fat += 1
    if n_fat > 109:
        raise ValueError("more than 109 FAT sectors: DIFAT sectors are not written")
    total = n_fat + data_sectors
    fat = [FREE] * (n_fat * SECTOR // 4)
    for k in range(n_fat):
        fat[k] = FATSECT
    at = n_fat
    dir_start = at
    _chain(fat, at, n_dir)
    at += n_dir
    minifat_start = at if n_minifat else END
    _chain(fat, at, n_minifat)
    at += n_minifat
    mini_sector = at if n_mini else END
    _chain(fat, at, n_mini)
    at += n_mini
    large_start = {}
    for n, count in zip(large, n_large):
        large_start[n] = at
        _chain(fat, at, count)
        at += count
    assert at == total

    def entry(name: str, kind: int, start: int, size: int, child: int = NOSTREAM, left: int = NOSTREAM,
              right: int = NOSTREAM) -> bytes:
        raw = name.encode("utf-16-le") + b"\0\0"
        return (raw.ljust(64, b"\0") + struct.pack("<HBB3I", len(raw), kind, 1, left, right, child)
                + bytes(16 + 4 + 16) + struct.pack("<IQ", start, size))

    # the streams as a balanced binary tree of siblings (all black: olefile and the
    # specification's readers do not rebalance)
    links: dict[int, tuple[int, int]] = {}

    def tree(lo: int, hi: int) -> int:
        if lo >= hi:
            return NOSTREAM
        mid = (lo + hi) // 2
        links[mid] = (tree(lo, mid), tree(mid + 1, hi))
        return mid + 1  # entry 0 is the root

    top = tree(0, len(names))
    directory = bytearray(entry("Root Entry", 5, mini_sector, len(mini_data), child=top))
    for k, n in enumerate(names):
        start = mini_start.get(n, large_start.get(n, END))
        directory += entry(n, 2, start, len(streams[n]), left=links[k][0], right=links[k][1])
    unused = bytes(64) + struct.pack("<HBB3I", 0, 0, 0, NOSTREAM, NOSTREAM, NOSTREAM) + bytes(16 + 4 + 16 + 4 + 8)
    directory += unused * (n_dir * SECTOR // 128 - entries)
    difat = list(range(n_fat)) + [FREE] * (109 - n_fat)
    header = (SIGNATURE + bytes(16) + struct.pack("<HHHHH", 0x3E, 3, 0xFFFE, 9, 6) + bytes(6)
              + struct.pack("<9I", 0, n_fat, dir_start, 0, CUTOFF, minifat_start, n_minifat, END, 0)
              + struct.pack("<109I", *difat))
    assert len(header) == SECTOR

    def pad(b: bytes | bytearray, sectors: int) -> bytes:
        return bytes(b) + bytes(sectors * SECTOR - len(b))

    minifat += [FREE] * (n_minifat * SECTOR // 4 - len(minifat))  # the unused tail is free
    body = [pad(struct.pack(f"<{len(fat)}I", *fat), n_fat), pad(directory, n_dir),
            struct.pack(f"<{len(minifat)}I", *minifat), pad(mini_data, n_mini)]
    body += [pad(streams[n], count) for n, count in zip(large, n_large)]
    return header + b"".join(body)


# --- program POUs -------------------------------------------------------------------------

def _reverse():
    """The registry backwards: mnemonic -> its headers, each with its form. One mnemonic may
    have several (SET [23] of Y/M, SET [23 02] of S or a special relay; OUT [20], OUT T/C [21 03]):
    instruction() takes the first whose slots take the operands."""
    reg = registry()
    heads: dict[str, list[tuple[bytes, object]]] = {}
    for op, f in reg.basic.items():
        heads.setdefault(f.mnemonic, []).append((bytes([op]), f))
    for payload, f in reg.short.items():
        heads.setdefault(f.mnemonic, []).append((payload, f))
    for (family, subtype, *form), f in reg.application.items():
        width = 1 + 2 * sum(reg.slot[s].words for s in f.slots)
        heads.setdefault(f.mnemonic, []).append((bytes([family, width, subtype, *form]), f))
    return reg, heads


def _frame(payload: bytes) -> bytes:
    n = len(payload) + 2
    return bytes([n]) + payload + bytes([n])


def _minimal(value: int) -> bytes:
    return value.to_bytes(max(1, (value.bit_length() + 7) // 8), "little")


def operand(text: str, slot: str) -> bytes:
    """One operand's tokens, as GX Works2 writes them in a slot of that kind (a digit group KnM0:
    the modifier [F1 n], then its bit device)."""
    reg = registry()
    group = re.fullmatch(r"K([1-8])([XYMS][0-9]+)", text.upper())
    if group and reg.slot[slot].digits:
        devices = {reg.operand[t]["device"]: t for t in reg.slot[slot].digits}
        if group[2][0] not in devices or int(group[1]) > reg.slot[slot].most_digits:
            raise ValueError(f"{text}: no digit group of the {slot} slot")
        return _frame(bytes([DIGITS, int(group[1])])) + operand(group[2], "contact")  # the device as a contact's
    device, rest = text[0].upper(), text[1:]
    for t in sorted(reg.slot[slot].types):
        kind = reg.operand[t]
        if kind["device"] != device:
            continue
        if device == "K":
            value, width = int(rest), kind["bits"]
            if not -(1 << (width - 1)) <= value < 1 << (width - 1):
                raise ValueError(f"{text}: outside a {width}-bit K")
            raw = value.to_bytes(width // 8, "little", signed=True) if value < 0 else _minimal(value)
        elif device == "H":
            raw = _minimal(int(rest, 16))
        else:
            raw = _minimal(int(rest, 8 if kind.get("octal") else 10))
        lo, hi = reg.slot[slot].numbers.get(t, (0, 1 << 32))
        if len(raw) > kind.get("bits", 32) // 8 or not (device in "KH" or lo <= int(rest, 8 if kind.get("octal") else 10) <= hi):
            raise ValueError(f"{text}: outside the subset")
        return _frame(bytes([t]) + raw)
    raise ValueError(f"{text}: no {slot} operand of the subset")


def instruction(mnemonic: str, operands: list[str]) -> bytes:
    """One instruction's tokens: the first header of the mnemonic whose slots take the operands."""
    _, heads = _reverse()
    for payload, form in heads.get(mnemonic, []):
        if len(operands) != len(form.slots):
            continue
        try:
            return _frame(payload) + b"".join(operand(o, s) for o, s in zip(operands, form.slots))
        except ValueError:
            continue
    raise ValueError(f"{mnemonic} {operands}: not in the subset")


STATEMENT, NOTE = b"\x80\x00", b"\x82\x00"


def text(line: str, kind: bytes = STATEMENT) -> bytes:
    """A text record (a line statement, or a note on the instruction before it): printable ASCII
    (the reader writes any other byte as \\xNN, which this writer turns back into the byte)."""
    raw = re.sub(rb"\\x([0-9A-F]{2})", lambda m: bytes([int(m[1], 16)]), line.encode("ascii"))
    return _frame(kind + raw)


def label(pointer: str) -> bytes:
    """A label line (P1:): the label header [3C] and its pointer."""
    (payload, slot), = registry().label.items()
    return _frame(payload) + operand(pointer, slot)


def tokens(lines: list[tuple[str, list[str]]]) -> bytes:
    """Instructions (mnemonic, operands) -> their tokens; (";", [text]) a line statement, ("note",
    [text]) a note on the instruction before it, ("label", [P1]) a label."""
    special = {";": lambda ops: text(ops[0]), "note": lambda ops: text(ops[0], NOTE), "label": lambda ops: label(ops[0])}
    return b"".join(special[m](ops) if m in special else instruction(m, ops) for m, ops in lines)


def pou(body: bytes, trailer: int = TRAILERS[0]) -> bytes:
    """A program POU around a token stream, `trailer` zero bytes after it (24 as in the notes' samples, 20
    as GX Works2 saved the public projects of docs/formats.md)."""
    header = bytearray(HEADER)
    struct.pack_into("<8H", header, 0x22, 2024, 1, 1, 1, 12, 0, 0, 0)  # a save time (SYSTEMTIME)
    for at in LENGTH_FIELDS:
        struct.pack_into("<I", header, at, len(body) + LENGTH_BIAS)
    return bytes(header) + body + bytes(trailer)


def program(lines: list[tuple[str, list[str]]]) -> bytes:
    return pou(tokens(lines))


# --- projects -----------------------------------------------------------------------------

def _xml(dataset: str, rows: list[dict[str, str]], row: str, diffgram: bool) -> str:
    body = "".join(f"<{row}>" + "".join(f"<{k}>{v}</{k}>" for k, v in r.items()) + f"</{row}>" for r in rows)
    data = f'<{dataset} xmlns="http://tempuri.org/{dataset}.xsd">{body}</{dataset}>'
    if not diffgram:
        return '<?xml version="1.0" standalone="yes"?>' + data
    # an ADO.NET diffgram: the `before` copy holds a stale row that is no current one
    stale = f"<{row}><iID>99</iID><szName>OLD.Program.pou</szName></{row}>"
    return ('<?xml version="1.0" standalone="yes"?><diffgr:diffgram xmlns:diffgr="urn:schemas-microsoft-com:'
            f'xml-diffgram-v1">{data}<diffgr:before>{stale}</diffgr:before></diffgr:diffgram>')


def project(pous: dict[str, bytes], numbers: dict[str, int] | None = None, comments: bytes | None = None,
            encoding: str = "utf-8", diffgram: bool = False, history: dict[str, dict[str, str]] | None = None,
            extra: dict[str, bytes] | None = None) -> bytes:
    """A .gxw: `pous` {program name (MAIN): POU bytes} in numbered streams of _hdb (`numbers`,
    default from 12 on), a COMMENT.qcd if given, the metadata naming them."""
    objects = {f"{name}.Program.pou": data for name, data in pous.items()}
    if comments is not None:
        objects["COMMENT.qcd"] = comments
    numbers = numbers or {}
    ids = {name: numbers.get(name.removesuffix(".Program.pou"), 12 + 4 * k) for k, name in enumerate(objects)}
    inner = {str(ids[name]): data for name, data in objects.items()} | (extra or {})
    rows = [{"iID": str(ids[n]), "szName": n, "bScrapFlag": "false"} for n in objects]
    rows.append({"iID": "7", "szName": "DELETED.Program.pou", "bScrapFlag": "true"})  # no current object
    hist = [{"iProjectdataID": str(ids[n]), "szProjectdataName": n, "iFileSize": str(len(d)),
             "szMD5val": base64.b64encode(hashlib.md5(d).digest()).decode("ascii")} | (history or {}).get(n, {})
            for n, d in objects.items()]
    outer = {"projectdatalist.xml": _xml("DSPROJECTDATA", rows, "D_Projectdata", diffgram).encode(encoding),
             "history.xml": _xml("DSHISTORY", hist, "D_History", diffgram).encode(encoding),
             "_hdb": compound_file(inner)}
    return compound_file(outer)


def il_lines(text: str, target, nop: bool = False) -> list[tuple[str, list[str]]]:
    """IL of the target (`.dialect fx`) -> FX instructions (mnemonic, operands), as an export
    writes them (M9000 -> M8000), a comment line a line statement (";", [text]), an instruction's
    trailing comment a note after it ("note", [text]), a P label ("label", [P1]); `nop`: NOP
    lines kept (a GX Developer body's empty frame). Anything else has no place in the subset."""
    from mlctool.exports import family_rows

    rows, _, errors = family_rows("p.il", text, target, "fx")
    if rows is None:
        raise ValueError([d.message for d in errors])
    out: list[tuple[str, list[str]]] = []
    for _, statement, mnemonic, operands, note in rows:
        if statement:
            out.append((";", [statement]))
            continue
        if re.fullmatch(r"P[0-9]+", mnemonic) and not operands:
            out.append(("label", [mnemonic]))
        elif operands or registry_takes_none(mnemonic) or nop and mnemonic == "NOP":
            out.append((mnemonic, operands))
        else:
            raise ValueError(f"no place in the subset for {mnemonic!r}")
        if note:
            out.append(("note", [note]))
    return out


def registry_takes_none(mnemonic: str) -> bool:
    """Whether the registry has the mnemonic without operands (END, ORB, MPS ...)."""
    _, heads = _reverse()
    return any(not form.slots for _, form in heads.get(mnemonic, []))


def il_project(text: str, target, **kw) -> bytes:
    return project({"MAIN": program(il_lines(text, target))}, **kw)
