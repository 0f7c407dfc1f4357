#!/usr/bin/python3
"""Scans that hold the pit twice, registered a few mm apart (a handheld
scanner whose tracking slipped), for the doubled-scan tables of
docs/reliability.md: each binary PLY of a corpus (pitvol-sim corpus) with a
copy of its points shifted by MM millimetres in a random 3D direction
(Python's random, seeded per file and copy, so the set is the same on every
machine):

    tests/cli/doubled_scans.py CORPUS_DIR OUT_DIR MM [MM ...]
    for f in OUT_DIR/*.ply; do build/bin/pitvol measure "$f" --json; done

OUT_DIR/<case>-d<MM>.ply keeps the corpus file's exact_volume_cm3 comment
(a rigid copy has the same volume). Standard library only."""
import math
import os
import random
import struct
import sys


def read_ply(path):
    raw = open(path, 'rb').read()
    end = raw.index(b'end_header\n') + len(b'end_header\n')
    head = raw[:end].decode('ascii').splitlines()
    if 'format binary_little_endian 1.0' not in head:
        sys.exit('%s: not a binary little-endian PLY' % path)
    props = [l for l in head if l.startswith('property')]
    if props != ['property float x', 'property float y', 'property float z']:
        sys.exit('%s: expected float x y z only, got %s' % (path, props))
    n = int([l for l in head if l.startswith('element vertex')][0].split()[2])
    return head, raw[end:end + 12 * n], n


def shifted(body, n, v):
    vals = struct.unpack('<%df' % (3 * n), body)
    out = [vals[i] + v[i % 3] for i in range(3 * n)]
    return struct.pack('<%df' % (3 * n), *out)


def main():
    if len(sys.argv) < 4:
        sys.exit(__doc__)
    src, dst = sys.argv[1], sys.argv[2]
    mags = [float(a) for a in sys.argv[3:]]
    os.makedirs(dst, exist_ok=True)
    for name in sorted(os.listdir(src)):
        if not name.endswith('.ply'):
            continue
        head, body, n = read_ply(os.path.join(src, name))
        for mag in mags:
            g = random.Random('%s %g' % (name, mag))
            while True:  # a uniform direction
                u = [g.gauss(0, 1) for _ in range(3)]
                norm = math.sqrt(sum(c * c for c in u))
                if norm > 1e-9:
                    break
            v = [mag * c / norm for c in u]
            head2 = ['element vertex %d' % (2 * n) if l.startswith('element vertex') else l for l in head]
            head2.insert(2, 'comment doubled: a copy shifted by %.4f %.4f %.4f mm' % tuple(v))
            out = os.path.join(dst, '%s-d%g.ply' % (name[:-4], mag))
            with open(out, 'wb') as f:
                f.write(('\n'.join(head2) + '\n').encode('ascii'))
                f.write(body)
                f.write(shifted(body, n, v))
            print(out, '%.4f %.4f %.4f' % tuple(v))


if __name__ == '__main__':
    main()
