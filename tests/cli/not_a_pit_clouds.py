#!/usr/bin/python3
"""Writes the six clouds of tests/unit/session/test_not_a_pit.cpp (same
shapes, Python's own random numbers) as .xyz files, for the hostile-input
table of docs/reliability.md:

    tests/cli/not_a_pit_clouds.py DIR
    for f in DIR/*.xyz; do build/bin/pitvol measure "$f"; echo "exit $?"; done

Standard library only (the system python3, no venv needed)."""
import math
import os
import random
import sys


def random_cloud(g):
    return [(400 * g.random() - 200, 400 * g.random() - 200, 400 * g.random() - 200)
            for _ in range(100000)]


def sphere_shell(g):
    out = []
    for _ in range(100000):
        x, y, z = g.gauss(0, 1), g.gauss(0, 1), g.gauss(0, 1)
        n = math.sqrt(x * x + y * y + z * z)
        out.append((150 * x / n, 150 * y / n, 150 * z / n))
    return out


def plane(g):
    return [(400 * g.random() - 200, 400 * g.random() - 200, 0.3 * g.gauss(0, 1))
            for _ in range(100000)]


def mound(g):
    out = []
    for _ in range(100000):
        u, t = g.random(), 2 * math.pi * g.random()
        if u < 0.4:
            r = 110 * math.sqrt(g.random())
            out.append((r * math.cos(t), r * math.sin(t), 200 + 0.1 * g.gauss(0, 1)))
        elif u < 0.7:
            out.append((110 * math.cos(t), 110 * math.sin(t), 200 * g.random()))
        else:
            r = 110 + 140 * g.random()
            out.append((r * math.cos(t), r * math.sin(t), 0.1 * g.gauss(0, 1)))
    return out


def add_pit(g, cx, n, out):
    for _ in range(n):
        u, t = g.random(), 2 * math.pi * g.random()
        if u < 0.45:
            r = 100 * math.sqrt(g.random())
            out.append((cx + r * math.cos(t), r * math.sin(t), 0.1 * g.gauss(0, 1)))
        else:
            out.append((cx + 100 * math.cos(t), 100 * math.sin(t), 250 * g.random()))


def two_pits(g):
    out = []
    add_pit(g, -150, 60000, out)
    add_pit(g, 150, 60000, out)
    for _ in range(40000):
        x, y = 600 * g.random() - 300, 300 * g.random() - 150
        if math.hypot(x - 150, y) > 100 and math.hypot(x + 150, y) > 100:
            out.append((x, y, 250))
    return out


def trench(g):
    out = []
    for _ in range(150000):
        u = g.random()
        if u < 0.3:
            out.append((1200 * g.random() - 600, 150 * g.random() - 75, 0.1 * g.gauss(0, 1)))
        elif u < 0.6:
            out.append((1200 * g.random() - 600, -75 if g.random() < 0.5 else 75, 200 * g.random()))
        elif u < 0.65:
            out.append((-600 if g.random() < 0.5 else 600, 150 * g.random() - 75, 200 * g.random()))
        else:
            x, y = 1400 * g.random() - 700, 400 * g.random() - 200
            if abs(x) > 600 or abs(y) > 75:
                out.append((x, y, 200))
    return out


def one_pit(g):
    out = []
    add_pit(g, 0, 150000, out)
    return out


CLOUDS = [("random_cloud", random_cloud), ("sphere_shell", sphere_shell), ("plane", plane),
          ("mound", mound), ("two_pits", two_pits), ("trench_1200mm", trench),
          ("one_pit", one_pit)]


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    os.makedirs(sys.argv[1], exist_ok=True)
    for seed, (name, make) in enumerate(CLOUDS, start=1):
        g = random.Random(seed)
        with open(os.path.join(sys.argv[1], name + ".xyz"), "w") as f:
            for p in make(g):
                f.write("%.3f %.3f %.3f\n" % p)


if __name__ == "__main__":
    main()
