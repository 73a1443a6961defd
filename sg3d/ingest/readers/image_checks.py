"""Checks of a JPEG or PNG file's structure before it is decoded: the decoders (libjpeg,
libpng) print their own complaints about a damaged file on stderr whatever OpenCV's log level
is, so a damaged file is found here first and named as a skipped frame instead."""
from __future__ import annotations

import re
import struct
import zlib
from typing import Optional

PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"
# In JPEG entropy-coded data 0xFF is followed by 0x00 (a stuffed byte), 0xD0-0xD7 (a restart
# marker) or 0xFF (fill); anything else ends the scan and must be a real marker.
_SCAN_END = re.compile(rb"\xff[^\x00\xd0-\xd7\xff]")
# Markers that may follow a scan: end of image, another table or scan (progressive JPEGs),
# restart interval, comment, application data.
_AFTER_SCAN = frozenset({0xD9, 0xC4, 0xDA, 0xDB, 0xDD, 0xFE, *range(0xE0, 0xF0)})


def jpeg_problem(data: bytes) -> Optional[str]:
    """Why `data` is not a complete, well-formed JPEG (marker structure, segment lengths, the
    end-of-image marker), or None. Damage inside the Huffman-coded data that keeps the markers
    intact is left to the decoder."""
    if not data.startswith(b"\xff\xd8"):
        return "is not a JPEG"
    i, n = 2, len(data)
    while i + 1 < n:
        if data[i] != 0xFF:
            return "is corrupt (a JPEG segment does not start with a marker)"
        marker = data[i + 1]
        if marker == 0xFF:
            i += 1
            continue
        if marker == 0xD9:
            return None
        if 0xD0 <= marker <= 0xD7 or marker == 0x01:
            i += 2
            continue
        if i + 4 > n:
            break
        length = struct.unpack_from(">H", data, i + 2)[0]
        if length < 2:
            return "is corrupt (a JPEG segment has a bad length)"
        i += 2 + length
        if marker == 0xDA:
            end = _SCAN_END.search(data, i)
            if end is None:
                break
            if data[end.start() + 1] not in _AFTER_SCAN:
                return "is corrupt (JPEG data ends in an unknown marker)"
            i = end.start()
    return "is truncated (no JPEG end marker)"


def png_problem(data: bytes) -> Optional[str]:
    """Why `data` is not a complete PNG whose chunks all pass their CRC, or None."""
    if not data.startswith(PNG_SIGNATURE):
        return "is not a PNG"
    i, n = len(PNG_SIGNATURE), len(data)
    while i + 12 <= n:
        length, kind = struct.unpack_from(">I4s", data, i)
        end = i + 12 + length
        if end > n:
            break
        crc = struct.unpack_from(">I", data, end - 4)[0]
        if zlib.crc32(data[i + 4:end - 4]) != crc:
            return f"is corrupt (a PNG {kind.decode('latin-1')!r} chunk fails its CRC)"
        if kind == b"IEND":
            return None
        i = end
    return "is truncated (no PNG end chunk)"


def image_problem(data: bytes, suffix: str) -> Optional[str]:
    """`jpeg_problem` or `png_problem` by the file's suffix; None for other kinds."""
    suffix = suffix.lower()
    if suffix in (".jpg", ".jpeg"):
        return jpeg_problem(data)
    if suffix == ".png":
        return png_problem(data)
    return None
