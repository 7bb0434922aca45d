#!/usr/bin/env python3
"""Prints what an 8-bit PNG written by `prw render` shows, for corpus checks (standard library only):

    scripts/png_stats.py FILE.png

one line "covered C lit L clipped K distinct D chroma S verdict V":
  covered   fraction of pixels that differ from the corner colour (the background),
  lit       fraction of covered pixels brighter than 8/255,
  distinct  number of distinct colours (6 bits per channel) among covered pixels,
  clipped   fraction of covered pixels with every channel >= 250 (over-exposed white),
  chroma    mean |max(R,G,B) - min(R,G,B)| / 255 over covered pixels,
  verdict   "image" when at least 0.5 % of the pixels are covered and lit and there are at least
            8 distinct colours; else "black" (nothing lit), "empty" (nothing but background) or
            "flat" (a single colour: a silhouette) or "clipped" (a quarter or more of the covered pixels
            over-exposed).
Exit status 0 for "image", 1 otherwise, 2 for a file this reader cannot decode."""
import struct
import sys
import zlib


def read_png(path):
    with open(path, "rb") as f:
        data = f.read()
    if data[:8] != b"\x89PNG\r\n\x1a\n":
        raise ValueError("not a PNG file")
    pos, idat, w = 8, b"", None
    while pos + 8 <= len(data):
        n, kind = struct.unpack(">I4s", data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + n]
        if kind == b"IHDR":
            w, h, depth, ctype, _, _, interlace = struct.unpack(">IIBBBBB", body)
            if depth != 8 or ctype not in (2, 6) or interlace:
                raise ValueError("only 8-bit RGB/RGBA, not interlaced (depth %d, colour type %d)" % (depth, ctype))
            bpp = 3 if ctype == 2 else 4
        elif kind == b"IDAT":
            idat += body
        elif kind == b"IEND":
            break
        pos += 12 + n
    if w is None:
        raise ValueError("no IHDR chunk")
    raw = zlib.decompress(idat)
    stride = w * bpp
    rows, prev = [], bytearray(stride)
    for y in range(h):
        ft = raw[y * (stride + 1)]
        line = bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
        for i in range(stride):
            a = line[i - bpp] if i >= bpp else 0
            b = prev[i]
            c = prev[i - bpp] if i >= bpp else 0
            if ft == 1:
                line[i] = (line[i] + a) & 255
            elif ft == 2:
                line[i] = (line[i] + b) & 255
            elif ft == 3:
                line[i] = (line[i] + (a + b) // 2) & 255
            elif ft == 4:
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                line[i] = (line[i] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
        rows.append(line)
        prev = line
    return w, h, bpp, rows


def stats(path):
    """The figures of the one-line summary, as a dict (raises OSError / ValueError on bad files)."""
    try:
        w, h, bpp, rows = read_png(path)
    except (zlib.error, struct.error) as err:
        raise ValueError(str(err))
    bg = tuple(rows[0][0:3])
    covered = lit = clipped = 0
    chroma = 0.0
    colours = set()
    for line in rows:
        for x in range(w):
            px = tuple(line[x * bpp:x * bpp + 3])
            if px == bg:
                continue
            covered += 1
            if max(px) > 8:
                lit += 1
            if min(px) >= 250:
                clipped += 1
            chroma += (max(px) - min(px)) / 255.0
            colours.add((px[0] >> 2, px[1] >> 2, px[2] >> 2))
    n = w * h
    if covered == 0:
        verdict = "empty"
    elif lit < 0.005 * n:
        verdict = "black"
    elif clipped >= 0.25 * covered:
        verdict = "clipped"
    elif len(colours) < 8:
        verdict = "flat"
    else:
        verdict = "image"
    return {"covered": covered / n, "lit": lit / max(covered, 1), "clipped": clipped / max(covered, 1),
            "distinct": len(colours), "chroma": chroma / max(covered, 1), "verdict": verdict}


def describe(st):
    return "covered %.3f lit %.3f clipped %.3f distinct %d chroma %.3f verdict %s" % (
        st["covered"], st["lit"], st["clipped"], st["distinct"], st["chroma"], st["verdict"])


def main():
    if len(sys.argv) != 2:
        print(__doc__, file=sys.stderr)
        return 2
    try:
        st = stats(sys.argv[1])
    except (OSError, ValueError) as err:
        print("%s: %s" % (sys.argv[1], err), file=sys.stderr)
        return 2
    print(describe(st))
    return 0 if st["verdict"] == "image" else 1


if __name__ == "__main__":
    sys.exit(main())
