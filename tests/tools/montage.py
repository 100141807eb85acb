#!/usr/bin/env python3
"""Puts RGB PNG pictures side by side, each enlarged by a whole factor (every pixel drawn as a
square), with white gaps between them: the docs' before-and-after pictures.
Usage: montage.py [--scale N] [--gap PIXELS] IN.png... -o OUT.png"""
import argparse
import struct
import zlib

from same_pictures import png_pixels


def write_png(path, width, height, rows):
    def chunk(kind, body):
        return struct.pack('>I', len(body)) + kind + body + struct.pack('>I', zlib.crc32(kind + body))
    raw = b''.join(b'\0' + row for row in rows)
    with open(path, 'wb') as out:
        out.write(b'\x89PNG\r\n\x1a\n' + chunk(b'IHDR', struct.pack('>IIBBBBB', width, height, 8, 2, 0, 0, 0))
                  + chunk(b'IDAT', zlib.compress(raw, 9)) + chunk(b'IEND', b''))


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('pictures', nargs='+')
    parser.add_argument('--scale', type=int, default=1)
    parser.add_argument('--gap', type=int, default=8)
    parser.add_argument('-o', dest='out', required=True)
    args = parser.parse_args()
    pictures = []
    for path in args.pictures:
        width, height, depth, colour, pixels = png_pixels(path)
        if depth != 8 or colour != 2:
            raise SystemExit(f'montage.py: {path} is not an 8-bit RGB PNG')
        pictures.append((width, height, pixels))
    height = max(h for _, h, _ in pictures) * args.scale
    gap = b'\xff\xff\xff' * args.gap
    rows = []
    for y in range(height):
        parts = []
        for width, h, pixels in pictures:
            source = y // args.scale
            line = pixels[source * width * 3:(source + 1) * width * 3] if source < h else bytes(width * 3)
            parts.append(b''.join(line[3 * x:3 * x + 3] * args.scale for x in range(width)))
        rows.append(gap.join(parts))
    total = sum(w for w, _, _ in pictures) * args.scale + args.gap * (len(pictures) - 1)
    write_png(args.out, total, height, rows)


if __name__ == '__main__':
    main()
