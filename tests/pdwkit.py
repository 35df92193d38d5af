"""Test fixtures: FATEK WinProladder files (.pdw projects, .ldr ladder resources) laid out as the
public notes describe them (mlctool/winproladder.py cites them), for the reader's tests and as
templates for the writer. Not WinProladder's own files: the bytes the notes do not decode (the
transform, the project's other resources) are seeded random bytes here.

- image(): a 40,960-byte program memory image holding `words`, with its fields computed from
  them, or given as they are (`fields`) to test the reader against the notes' own numbers.
- project(): the file: the header strings, the image's 32 records each XOR-ed with one seeded
  random 1,280-byte key (a record of erased memory is then 0xFF ^ key), random bytes after it.
- ldr(): the header strings, one record per network, the last network first, the end mark.
"""

from __future__ import annotations

import random

from mlctool.winproladder import (
    CHECKSUM_AT,
    CODE_AT,
    COMPLEMENT_AT,
    COMPLEMENT_BASE,
    COUNT_AT,
    END_AT,
    IMAGE,
    IMAGE_AT,
    LDR_END,
    LDR_MAGIC,
    LDR_PAYLOAD_AT,
    LENGTH_BYTE_AT,
    MARK,
    MARK_AT,
    MODEL_AT,
    PDW_MAGIC,
    PDW_SIZE_SEEN,
    RECORD,
    SIGNATURE,
    SIGNATURE_AT,
)


def fields_of(words: list[int]) -> dict[int, int]:
    """The 16-bit fields (and the length byte, at LENGTH_BYTE_AT) the notes' formulas give."""
    n = len(words)
    return {COUNT_AT: n, COMPLEMENT_AT: COMPLEMENT_BASE - n, END_AT[0]: CODE_AT + 2 * n, END_AT[1]: CODE_AT + 2 * n,
            CHECKSUM_AT: (sum(words) - 1) & 0xFFFF, LENGTH_BYTE_AT: (0x23 + 4 * n) & 0xFF}


def image(words: list[int], fields: dict[int, int] | None = None, seed: int = 0) -> bytearray:
    rng = random.Random(seed)
    img = bytearray(b"\xff" * IMAGE)
    img[:CODE_AT] = bytes(rng.randrange(256) for _ in range(CODE_AT))  # fields the notes do not name
    img[SIGNATURE_AT:SIGNATURE_AT + len(SIGNATURE)] = SIGNATURE
    img[MARK_AT:MARK_AT + 2] = MARK
    for at, value in (fields if fields is not None else fields_of(words)).items():
        if at == LENGTH_BYTE_AT:
            img[at] = value
        else:
            img[at:at + 2] = value.to_bytes(2, "little")
    for k, w in enumerate(words):
        img[CODE_AT + 2 * k:CODE_AT + 2 * k + 2] = w.to_bytes(2, "little")
    return img


def _header(magic: bytes, kind: bytes, model: str, size: int) -> bytearray:
    head = bytearray(size)
    head[:len(magic)] = magic
    head[0x80:0x80 + len(kind)] = kind
    head[0x90:0x9C] = b"WinProladder"
    head[MODEL_AT:MODEL_AT + len(model)] = model.encode("ascii")
    return head


def project(words: list[int] | None = None, img: bytes | None = None, model: str = "FBs-24MC",
            size: int = PDW_SIZE_SEEN, seed: int = 0) -> bytes:
    rng = random.Random(seed + 1)
    img = image(words or [], seed=seed) if img is None else img
    key = bytes(rng.randrange(256) for _ in range(RECORD))
    out = _header(PDW_MAGIC, b"FB-PLC", model, IMAGE_AT)
    out[0x10C:0x114] = b"Project0"
    out[0x114:0x114 + len(model)] = model.encode("ascii")
    for k in range(0, IMAGE, RECORD):
        out += bytes(a ^ b for a, b in zip(img[k:k + RECORD], key, strict=True))
    out += bytes(rng.randrange(256) for _ in range(max(0, size - len(out))))
    return bytes(out[:size])


def ldr(networks: list[list[int]], model: str = "FBs-24MC", seed: int = 0) -> bytes:
    rng = random.Random(seed)
    out = _header(LDR_MAGIC, b"FB-RES", model, LDR_PAYLOAD_AT)
    for net in reversed(networks):
        code = b"".join(w.to_bytes(2, "little") for w in net)
        out += b"\x12\x10" + (len(code) + 5).to_bytes(2, "little") + len(code).to_bytes(2, "little") + code
        out += bytes(rng.randrange(256) for _ in range(5))
    return bytes(out + LDR_END)
