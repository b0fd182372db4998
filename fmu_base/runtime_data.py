"""The compiled runtime's input container: named typed arrays in one versioned binary blob.

The offline preparation (Python) writes, the runtime (C, ``native/src/common/data.c``) reads and checks. Layout,
version 1 (every integer little-endian; ``native/include/wec_data.h`` is the reference, docs/runtime.md explains
it)::

    offset  size      content
    0       8         magic b"WECRTDAT"
    8       4         uint32 format version (1)
    12      4         uint32 number of arrays C
    16      16        kind, ASCII, NUL-padded ("hydro"; the multibody runtime will use its own)
    32      8         uint64 total size in bytes
    40      8         reserved, 0
    48      128 C     directory: per array 64 bytes name (letters, digits, "_", ".", NUL-padded), 1 byte dtype
                      (1 float64, 2 int64, 3 uint8), 1 byte ndim (0..4), 6 bytes 0, 4 uint64 shape (unused 0),
                      uint64 offset (multiple of 8), uint64 size in bytes, 8 bytes 0
    ...               array data, C order, each at its offset

Scalars are 0-d arrays. The order of the arrays is the order given (deterministic bytes for the same input, so
caches keyed on the data stay valid). :func:`read` is the Python reader (inspection, tests); it makes the same
checks as the C reader.
"""

from __future__ import annotations

import re
import struct

import numpy as np

MAGIC = b"WECRTDAT"
VERSION = 1
HEADER = struct.Struct("<8sII16sQQ")
ENTRY = struct.Struct("<64sBB6x4QQQ8x")
DTYPES = {np.dtype("<f8"): 1, np.dtype("<i8"): 2, np.dtype("u1"): 3}
CODES = {code: dtype for dtype, code in DTYPES.items()}
MAX_DIMS = 4
_NAME = re.compile(r"[A-Za-z0-9_.]{1,63}")


class RuntimeDataError(ValueError):
    """Runtime data that cannot be written (a bad name or type) or read (corrupt)."""


def _as_array(name: str, value: object) -> np.ndarray:
    a = np.asarray(value)
    if a.dtype.kind == "b":
        a = a.astype(np.uint8)
    elif a.dtype.kind in "iu" and a.dtype != np.uint8:
        a = a.astype("<i8")
    elif a.dtype.kind == "f":
        a = a.astype("<f8")
    if a.dtype.newbyteorder("<") not in DTYPES or a.dtype.kind == "c":
        raise RuntimeDataError(f"runtime data: array {name!r} has dtype {a.dtype}; only float64, int64 and uint8 "
                               "(complex as a trailing axis of 2)")
    if a.ndim > MAX_DIMS:
        raise RuntimeDataError(f"runtime data: array {name!r} has {a.ndim} dimensions (at most {MAX_DIMS})")
    return np.array(a, dtype=a.dtype.newbyteorder("<"), order="C")  # (ascontiguousarray would make scalars 1-d)


def write(kind: str, arrays: dict[str, object]) -> bytes:
    """The container of ``kind`` holding ``arrays`` (name -> array or scalar), in the order given."""
    if not (kind.isascii() and 0 < len(kind) <= 16):
        raise RuntimeDataError(f"runtime data: kind {kind!r} must be 1-16 ASCII characters")
    items = []
    for name, value in arrays.items():
        if not _NAME.fullmatch(name):
            raise RuntimeDataError(f"runtime data: array name {name!r} must be 1-63 letters, digits, '_' or '.'")
        items.append((name, _as_array(name, value)))
    offset = HEADER.size + ENTRY.size * len(items)
    directory, blobs = [], []
    for name, a in items:
        offset = -(-offset // 8) * 8
        shape = list(a.shape) + [0] * (MAX_DIMS - a.ndim)
        directory.append(ENTRY.pack(name.encode(), DTYPES[a.dtype], a.ndim, *shape, offset, a.nbytes))
        blobs.append((offset, a.tobytes()))
        offset += a.nbytes
    total = offset
    out = bytearray(total)
    out[: HEADER.size] = HEADER.pack(MAGIC, VERSION, len(items), kind.encode(), total, 0)
    out[HEADER.size : HEADER.size + ENTRY.size * len(items)] = b"".join(directory)
    for start, blob in blobs:
        out[start : start + len(blob)] = blob
    return bytes(out)


def read(data: bytes, kind: str | None = None) -> tuple[str, dict[str, np.ndarray]]:
    """(kind, arrays) of a container, checked as the C reader checks it (:class:`RuntimeDataError` if not)."""
    data = bytes(data)
    if len(data) < HEADER.size:
        raise RuntimeDataError(f"runtime data: {len(data)} bytes, shorter than the header")
    magic, version, count, raw_kind, total, reserved = HEADER.unpack_from(data)
    if magic != MAGIC:
        raise RuntimeDataError("runtime data: does not start with the magic b'WECRTDAT'")
    if version != VERSION:
        raise RuntimeDataError(f"runtime data: format version {version}, this reader reads {VERSION}")
    found = raw_kind.rstrip(b"\0").decode("ascii", "replace")
    if kind is not None and found != kind:
        raise RuntimeDataError(f"runtime data: of kind {found!r}, expected {kind!r}")
    if total != len(data) or reserved:
        raise RuntimeDataError(f"runtime data: the header gives {total} bytes, the buffer holds {len(data)}")
    if count > (len(data) - HEADER.size) // ENTRY.size:
        raise RuntimeDataError(f"runtime data: {count} arrays announced, no room for their directory")
    end = HEADER.size + ENTRY.size * count
    arrays: dict[str, np.ndarray] = {}
    spans = []
    for k in range(count):
        raw_name, code, ndim, *rest = ENTRY.unpack_from(data, HEADER.size + ENTRY.size * k)
        shape, offset, nbytes = rest[:MAX_DIMS], rest[MAX_DIMS], rest[MAX_DIMS + 1]
        name = raw_name.rstrip(b"\0").decode("ascii", "replace")
        if not _NAME.fullmatch(name) or name in arrays:
            raise RuntimeDataError(f"runtime data: array {k} has a malformed or repeated name")
        if code not in CODES or ndim > MAX_DIMS or any(shape[ndim:]):
            raise RuntimeDataError(f"runtime data: array {name!r} has a bad dtype code or rank")
        dims = tuple(shape[:ndim])
        size = CODES[code].itemsize * int(np.prod(dims, dtype=object))
        if size != nbytes or offset % 8 or offset < end or offset + nbytes > len(data):
            raise RuntimeDataError(f"runtime data: array {name!r} does not fit the data")
        arrays[name] = np.frombuffer(data, dtype=CODES[code], count=size // CODES[code].itemsize,
                                     offset=offset).reshape(dims).copy()
        spans.append((offset, offset + nbytes, name))
    spans.sort()
    for (_, stop, first), (start, _, second) in zip(spans, spans[1:], strict=False):
        if start < stop:
            raise RuntimeDataError(f"runtime data: arrays {first!r} and {second!r} overlap")
    return found, arrays
