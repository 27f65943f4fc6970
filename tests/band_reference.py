"""An independent estimate of shear-band directions, to check tools/bands.py against.

usage: /usr/bin/python3 tests/band_reference.py FRAME.vtu [FRAME.vtu ...] [--reference] [--body 0]
       prints, per arm of every band bands.py finds, its angle and this method's, and the difference

Written apart from bands.py and by a different route: no line is fitted anywhere.
 1. The particles' gamma is put on a square grid (cell = the mean particle spacing) and smoothed
    by normalised convolution with a Gaussian (sd 1.5 cells): smoothed(sum of gamma) /
    smoothed(count), so the body's edge does not darken the field. Cells less than 95 % covered
    by the body are left out (derivatives there would see the edge).
 2. The Hessian of the smoothed field (Gaussian derivatives, the same sd) gives at every cell the
    ridge direction: the eigenvector of the eigenvalue of smaller magnitude; across the ridge
    the other eigenvalue is strongly negative (Steger 1998, "An unbiased detector of curvilinear
    structures").
 3. Ridge cells: line-like (larger magnitude eigenvalue negative and at least 2 times the
    other's magnitude), on the crest (the extremum of the second-order Taylor expansion along
    the normal lies within half a cell), and high (smoothed gamma above the median + 0.25 of the
    range to the 99.5th percentile).
 4. Arms: 8-connected groups of ridge cells of one sense (direction 15-85 deg or -85 to -15 deg
    from horizontal); a crossing is no ridge (both eigenvalues negative and alike) and, in a
    deformed X, its neck is nearly horizontal, so the groups part there. Groups shorter than
    8 cells are dropped.
 5. An arm's angle is the median of its cells' ridge directions, each cell counting once (one
    cell length of ridge): the direction most of the arm has, which for an arm that is straight
    over most of its length and bent near an end is the straight part's.
"""
import argparse
import math
import os
import sys

import numpy as np

try:
    from scipy import ndimage
except ImportError:  # pragma: no cover - Debian's python3-scipy is expected
    ndimage = None

HERE = os.path.dirname(os.path.abspath(__file__))
TOOLS = os.path.join(HERE, "..", "tools")


def _weighted_median(values, weights):
    order = np.argsort(values)
    v, w = values[order], weights[order]
    c = np.cumsum(w)
    return float(v[np.searchsorted(c, 0.5 * c[-1])])


def reference_arms(x, y, gamma, sigma_cells=1.5, min_cells=8):
    """Arms of the ridges of gamma(x, y). Returns a list of dicts: angle (deg, (-90, 90], > 0
    rising to the right), x, y (centroid of the arm's ridge cells, m), cells, x0, y0, x1, y1
    (ends of the arm's cells along its direction)."""
    if ndimage is None:
        raise ImportError("band_reference needs scipy (python3-scipy)")
    x, y, g = (np.asarray(a, dtype=float) for a in (x, y, gamma))
    h = math.sqrt(np.ptp(x) * np.ptp(y) / len(x))
    pad = 4 * sigma_cells * h
    nx = int(math.ceil((np.ptp(x) + 2 * pad) / h)) + 1
    ny = int(math.ceil((np.ptp(y) + 2 * pad) / h)) + 1
    ox, oy = x.min() - pad, y.min() - pad
    ix = np.clip(np.floor((x - ox) / h).astype(int), 0, nx - 1)
    iy = np.clip(np.floor((y - oy) / h).astype(int), 0, ny - 1)
    total = np.zeros((ny, nx))
    count = np.zeros((ny, nx))
    np.add.at(total, (iy, ix), g)
    np.add.at(count, (iy, ix), 1.0)
    # The body: occupied cells, gaps closed (particles spread apart in a band leave empty
    # cells) and holes filled; `inside` keeps the cells 2 sd away from its edge.
    body = ndimage.binary_fill_holes(ndimage.binary_closing(count > 0, structure=np.ones((3, 3)),
                                                            iterations=2))
    inside = ndimage.binary_erosion(body, iterations=int(math.ceil(2 * sigma_cells)))
    den = ndimage.gaussian_filter(count, sigma_cells)
    field = ndimage.gaussian_filter(total, sigma_cells) / np.maximum(den, 1e-300)
    # Derivatives of the normalised field, which extends the body's values smoothly a few cells
    # past its edge (beyond, where it is undefined, zero; those cells are not `inside`).
    filled = np.where(den > 1e-3 * den.max(), field, 0.0)
    gy = ndimage.gaussian_filter(filled, sigma_cells, order=(1, 0)) / h
    gx = ndimage.gaussian_filter(filled, sigma_cells, order=(0, 1)) / h
    hyy = ndimage.gaussian_filter(filled, sigma_cells, order=(2, 0)) / h ** 2
    hxx = ndimage.gaussian_filter(filled, sigma_cells, order=(0, 2)) / h ** 2
    hxy = ndimage.gaussian_filter(filled, sigma_cells, order=(1, 1)) / h ** 2
    # Eigen-decomposition of [[hxx, hxy], [hxy, hyy]] per cell.
    mean = 0.5 * (hxx + hyy)
    rad = np.sqrt((0.5 * (hxx - hyy)) ** 2 + hxy ** 2)
    lam_a, lam_b = mean - rad, mean + rad  # lam_a <= lam_b
    # Normal (across the ridge): eigenvector of lam_a, the most negative curvature.
    theta_n = 0.5 * np.arctan2(2 * hxy, hxx - hyy) + 0.5 * np.pi  # direction of lam_a
    nxv, nyv = np.cos(theta_n), np.sin(theta_n)
    d1 = gx * nxv + gy * nyv
    d2 = lam_a
    step = np.where(d2 < 0, -d1 / np.where(d2 < 0, d2, -1.0), np.inf)
    on_crest = (np.abs(step * nxv) <= 0.5 * h) & (np.abs(step * nyv) <= 0.5 * h)
    line_like = (lam_a < 0) & (np.abs(lam_a) >= 2 * np.abs(lam_b))
    vals = field[inside]
    med, top = np.median(vals), np.percentile(vals, 99.5)
    high = field > med + 0.25 * (top - med)
    ridge = inside & on_crest & line_like & high
    # Ridge direction = normal + 90 deg, folded into (-90, 90].
    along = np.degrees(theta_n) - 90.0
    along = (along + 90.0) % 180.0 - 90.0
    along = np.where(along <= -90.0, along + 180.0, along)
    arms = []
    for sense, (lo, hi) in ((1, (15.0, 85.0)), (-1, (-85.0, -15.0))):
        cells = ridge & (along >= lo) & (along <= hi)
        labels, n = ndimage.label(cells, structure=np.ones((3, 3)))
        for k in range(1, n + 1):
            jy, jx = np.nonzero(labels == k)
            if len(jy) < min_cells:
                continue
            ang = along[jy, jx]
            wts = np.ones(len(jy))  # each cell: one cell length of ridge
            a = _weighted_median(ang, wts)
            px, py = ox + (jx + 0.5) * h, oy + (jy + 0.5) * h
            c, s = math.cos(math.radians(a)), math.sin(math.radians(a))
            mx, my = float(np.average(px, weights=wts)), float(np.average(py, weights=wts))
            u = (px - mx) * c + (py - my) * s
            arms.append(dict(angle=a, x=mx, y=my, cells=int(len(jy)), sense=sense,
                             x0=mx + u.min() * c, y0=my + u.min() * s,
                             x1=mx + u.max() * c, y1=my + u.max() * s,
                             cell_x=px, cell_y=py, cell_angle=ang))
    arms.sort(key=lambda d: -d["cells"])
    return arms


def match_arms(bands, ref_arms):
    """Pairs every arm of every band (bands.py) with this method's estimate over the same stretch.

    For a bands.py arm, `reference` is the median direction of the reference ridge cells of the
    same sense lying along its straight part (within half a band width of the segment, projecting
    inside it): the same stretch seen by the other method. `reference_arm` is the whole
    reference arm's angle (the arm nearest to the straight part's middle). Returns a list of
    dicts: band, arm (indices), angle (bands.py), reference, reference_arm, difference (angle -
    reference), x, y (middle of the straight part), length (of the straight part)."""
    out = []
    for i, b in enumerate(bands):
        for j, a in enumerate(b.arms):
            mx, my = 0.5 * (a["x0"] + a["x1"]), 0.5 * (a["y0"] + a["y1"])
            c, s = math.cos(math.radians(a["angle"])), math.sin(math.radians(a["angle"]))
            half_len = 0.5 * a["length"]
            angles, best, dist = [], None, None
            for r in ref_arms:
                if (r["angle"] > 0) != (a["angle"] > 0):
                    continue
                u = (r["cell_x"] - mx) * c + (r["cell_y"] - my) * s
                v = -(r["cell_x"] - mx) * s + (r["cell_y"] - my) * c
                near = (np.abs(u) <= half_len) & (np.abs(v) <= max(0.5 * b.width, 1e-3))
                angles.extend(r["cell_angle"][near])
                d = _point_segment(mx, my, r["x0"], r["y0"], r["x1"], r["y1"])
                if d <= max(0.5 * a["length"], 2 * b.width) and (dist is None or d < dist):
                    best, dist = r, d
            ref = float(np.median(angles)) if len(angles) >= 4 else None
            out.append(dict(band=i, arm=j, angle=a["angle"], reference=ref, kinked=a["kinked"],
                            clear=b.clear, reference_arm=best["angle"] if best else None,
                            difference=None if ref is None else a["angle"] - ref, x=mx, y=my,
                            length=a["length"]))
    return out


def _point_segment(px, py, x0, y0, x1, y1):
    dx, dy = x1 - x0, y1 - y0
    L2 = dx * dx + dy * dy
    u = 0.0 if L2 == 0 else min(1.0, max(0.0, ((px - x0) * dx + (py - y0) * dy) / L2))
    return math.hypot(px - x0 - u * dx, py - y0 - u * dy)


def compare_frame(path, body=0, reference=False, field="max_shear_strain"):
    """bands.py against this method on one tsuchi frame.

    Returns (bands, pairs): bands from bands.bands_of_frame, pairs from match_arms, plus per band
    its angle and the reference's (length-weighted over its matched arms) as
    pairs entries with arm = None."""
    sys.path.insert(0, TOOLS)
    from bands import bands_of_frame

    bands, x, y, g = bands_of_frame(path, body=body, field=field, reference=reference)
    pairs = match_arms(bands, reference_arms(x, y, g))
    for i, b in enumerate(bands):
        # As bands.py does: kinked arms do not count for the band's angle.
        mine = [p for p in pairs if p["band"] == i and p["reference"] is not None and not p["kinked"]]
        ref = None
        if mine:
            wsum = sum(p["length"] for p in mine)
            ref = sum(p["length"] * p["reference"] for p in mine) / wsum
        pairs.append(dict(band=i, arm=None, angle=b.angle, reference=ref, reference_arm=None,
                          kinked=False, clear=b.clear,
                          difference=None if ref is None else b.angle - ref, x=b.cx, y=b.cy,
                          length=b.straight_length))
    return bands, pairs


def describe_pairs(pairs):
    lines = ["band  arm   middle x,y (mm)   bands.py  reference  difference   whole reference arm  note"]
    for p in sorted(pairs, key=lambda p: (p["band"], -1 if p["arm"] is None else p["arm"])):
        arm = "all" if p["arm"] is None else str(p["arm"] + 1)

        def f(v, spec):
            return "-" if v is None else format(v, spec)

        lines.append(f"{p['band'] + 1:<5d} {arm:<5s} ({1e3 * p['x']:5.1f}, {1e3 * p['y']:5.1f})  "
                     f"{p['angle']:+8.2f}  {f(p['reference'], '+8.2f'):>9s}  "
                     f"{f(p['difference'], '+6.2f'):>10s}   {f(p['reference_arm'], '+8.2f'):>9s}           "
                     + ("kinked " if p["kinked"] else "") + ("" if p["clear"] else "not clear"))
    return "\n".join(lines)


def main(argv=None):
    p = argparse.ArgumentParser(description="bands.py against an independent ridge estimate.")
    p.add_argument("frames", nargs="+")
    p.add_argument("--body", type=int, default=0)
    p.add_argument("--reference", action="store_true", help="particles at their initial positions")
    a = p.parse_args(argv)
    for path in a.frames:
        _, pairs = compare_frame(path, body=None if a.body < 0 else a.body, reference=a.reference)
        print(f"{path}{' (initial positions)' if a.reference else ''}")
        print(describe_pairs(pairs) if pairs else "no band found")
    return 0


if __name__ == "__main__":
    sys.exit(main())
