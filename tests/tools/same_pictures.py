#!/usr/bin/env python3
"""Compares two picture sets (tests/picture_set.sh output folders): every file must be in both,
PNG files must decode to the same size, colour type and pixels (their compressed bytes may
differ: zlib level and filters are an encoder's choice), every other file must be byte-identical.
Prints each difference; exits 1 if there is any. Usage: same_pictures.py DIR_A DIR_B"""
import os
import struct
import sys
import zlib


def png_pixels(path):
    """(width, height, bit depth, colour type, unfiltered rows) of a non-interlaced PNG."""
    data = open(path, 'rb').read()
    if data[:8] != b'\x89PNG\r\n\x1a\n':
        raise ValueError('not a PNG')
    pos, idat, header = 8, [], None
    while pos < len(data):
        length, kind = struct.unpack('>I4s', data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + length]
        if kind == b'IHDR':
            header = struct.unpack('>IIBBBBB', body)
        elif kind == b'IDAT':
            idat.append(body)
        pos += 12 + length
    width, height, depth, colour, _, _, interlace = header
    if interlace:
        raise ValueError('interlaced PNG')
    channels = {0: 1, 2: 3, 3: 1, 4: 2, 6: 4}[colour]
    bpp = max(1, channels * depth // 8)
    stride = (width * channels * depth + 7) // 8
    raw = zlib.decompress(b''.join(idat))
    rows, previous = [], bytearray(stride)
    for y in range(height):
        kind = raw[y * (stride + 1)]
        line = bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
        for i in range(stride):
            a = line[i - bpp] if i >= bpp else 0
            b = previous[i]
            c = previous[i - bpp] if i >= bpp else 0
            if kind == 1:
                line[i] = (line[i] + a) & 255
            elif kind == 2:
                line[i] = (line[i] + b) & 255
            elif kind == 3:
                line[i] = (line[i] + (a + b) // 2) & 255
            elif kind == 4:
                pa, pb, pc = abs(b - c), abs(a - c), abs(a + b - 2 * c)
                line[i] = (line[i] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
        rows.append(bytes(line))
        previous = line
    return width, height, depth, colour, b''.join(rows)


def files_under(root):
    found = set()
    for folder, _, names in os.walk(root):
        for name in names:
            found.add(os.path.relpath(os.path.join(folder, name), root))
    return found


def main():
    a_root, b_root = sys.argv[1], sys.argv[2]
    a_files, b_files = files_under(a_root), files_under(b_root)
    problems = [f'only in {a_root}: {f}' for f in sorted(a_files - b_files)]
    problems += [f'only in {b_root}: {f}' for f in sorted(b_files - a_files)]
    png_checked = 0
    for name in sorted(a_files & b_files):
        a, b = os.path.join(a_root, name), os.path.join(b_root, name)
        a_bytes, b_bytes = open(a, 'rb').read(), open(b, 'rb').read()
        if a_bytes == b_bytes:
            continue
        if name.endswith('.png'):
            png_checked += 1
            if png_pixels(a) != png_pixels(b):
                problems.append(f'pixels differ: {name}')
        else:
            problems.append(f'bytes differ: {name}')
    for problem in problems:
        print(problem)
    print(f'{len(a_files & b_files)} files in both, {png_checked} PNG files with other bytes compared by pixels, '
          f'{len(problems)} differences')
    return 1 if problems else 0


if __name__ == '__main__':
    sys.exit(main())
