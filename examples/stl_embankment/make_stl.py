#!/usr/bin/env python3
"""Writes embankment.stl: a trapezoidal embankment 2 m high with a 2 m crest and 1:1.5 side
slopes (8 m at its base), from x = 2 to 10 m, y = 2 to 4 m, extruded along z from 0 to 2 m. ASCII
STL in m, triangles wound counter-clockwise seen from outside (as CAD exporters write them)."""
import sys

H, crest, slope, x0, y0, L = 2.0, 2.0, 1.5, 2.0, 2.0, 2.0
base = crest + 2 * slope * H
section = [(x0, y0), (x0 + base, y0), (x0 + base - slope * H, y0 + H), (x0 + slope * H, y0 + H)]  # CCW in x-y


def tri(a, b, c):
    return "  facet normal 0 0 0\n    outer loop\n" + "".join(
        f"      vertex {p[0]:.6f} {p[1]:.6f} {p[2]:.6f}\n" for p in (a, b, c)) + "    endloop\n  endfacet\n"


def main(path):
    front = [(x, y, L) for x, y in section]   # z = L faces +z: CCW seen from +z
    back = [(x, y, 0.0) for x, y in section]  # z = 0 faces -z: reversed
    out = ["solid embankment\n", tri(front[0], front[1], front[2]), tri(front[0], front[2], front[3]),
           tri(back[0], back[2], back[1]), tri(back[0], back[3], back[2])]
    n = len(section)
    for i in range(n):  # the sides: outward for a CCW section
        j = (i + 1) % n
        out += [tri(back[i], back[j], front[j]), tri(back[i], front[j], front[i])]
    out.append("endsolid embankment\n")
    with open(path, "w") as f:
        f.write("".join(out))


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "embankment.stl")
