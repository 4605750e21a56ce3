"""A small PNG decoder for the report checks (python3 standard library only).

Reads 8-bit RGB and RGBA, non-interlaced PNGs: what headless Chromium writes for screenshots.
Rows come back unfiltered as bytes, bpp bytes per pixel. Decoding in pure Python is slow,
so a caller that needs only the top of the image passes max_rows and decoding stops there.
"""
import struct
import zlib
from itertools import accumulate

SIGNATURE = b"\x89PNG\r\n\x1a\n"


class PngImage:
    def __init__(self, width, height, bpp, rows):
        self.width, self.height, self.bpp, self.rows = width, height, bpp, rows

    def pixel(self, x, y):
        """The (r, g, b) of a pixel (alpha, if any, is dropped)."""
        i = x * self.bpp
        return tuple(self.rows[y][i:i + 3])


def _add_bytes(x, y):
    """Bytewise (x + y) mod 256 of two equal-length byte strings, without a per-byte loop:
    a SWAR add on big ints whose top bit per byte is handled apart so no carry crosses bytes."""
    n = len(x)
    low = int.from_bytes(b"\x7f" * n, "big")
    a, b = int.from_bytes(x, "big"), int.from_bytes(y, "big")
    s = ((a & low) + (b & low)) ^ ((a ^ b) & ~low)
    return (s & ((1 << (8 * n)) - 1)).to_bytes(n, "big")


def _unfilter(f, line, prev, bpp):
    """Undoes one scanline's filter (PNG spec 9.2); prev is the unfiltered row above."""
    if f == 0:
        return bytes(line)
    if f == 1:  # Sub: a running sum along each channel; accumulate/map keep the loop in C.
        out = bytearray(len(line))
        for c in range(bpp):
            out[c::bpp] = bytes(map((255).__and__, accumulate(line[c::bpp])))
        return bytes(out)
    if f == 2:  # Up: one bytewise add with the row above.
        return _add_bytes(line, prev)
    out = bytearray(line)
    if f == 3:  # Average
        for i in range(len(out)):
            a = out[i - bpp] if i >= bpp else 0
            out[i] = (out[i] + ((a + prev[i]) >> 1)) & 255
        return bytes(out)
    if f == 4:  # Paeth
        for i in range(len(out)):
            if i >= bpp:
                a, c = out[i - bpp], prev[i - bpp]
            else:
                a = c = 0
            b = prev[i]
            pa, pb, pc = abs(b - c), abs(a - c), abs(a + b - 2 * c)
            out[i] = (out[i] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
        return bytes(out)
    raise ValueError(f"unknown PNG filter type {f}")


def decode(data, max_rows=None):
    """Decodes PNG bytes into a PngImage; with max_rows only the top rows are decoded."""
    if data[:8] != SIGNATURE:
        raise ValueError("not a PNG")
    pos, idat, hdr = 8, [], None
    while pos + 8 <= len(data):
        n, kind = struct.unpack(">I4s", data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + n]
        if len(body) != n:
            raise ValueError("truncated PNG chunk")
        if kind == b"IHDR":
            hdr = struct.unpack(">IIBBBBB", body)
        elif kind == b"IDAT":
            idat.append(body)
        elif kind == b"IEND":
            break
        pos += 12 + n
    if hdr is None:
        raise ValueError("PNG without IHDR")
    w, h, depth, ctype, _, _, interlace = hdr
    if depth != 8 or ctype not in (2, 6) or interlace:
        raise ValueError(f"unsupported PNG: depth {depth}, colour type {ctype}, "
                         f"interlace {interlace}")
    bpp = 3 if ctype == 2 else 4
    stride = w * bpp
    nrows = h if max_rows is None else max(0, min(h, max_rows))
    # Inflate only as much as the wanted rows need.
    raw = zlib.decompressobj().decompress(b"".join(idat), nrows * (stride + 1))
    if len(raw) < nrows * (stride + 1):
        raise ValueError("PNG image data is shorter than its header says")
    rows, prev = [], bytes(stride)
    for y in range(nrows):
        start = y * (stride + 1)
        prev = _unfilter(raw[start], raw[start + 1:start + 1 + stride], prev, bpp)
        rows.append(prev)
    return PngImage(w, h, bpp, rows)


def read(path, max_rows=None):
    with open(path, "rb") as f:
        return decode(f.read(), max_rows)
