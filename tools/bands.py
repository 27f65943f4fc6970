"""Finds shear bands (ridges of high shear strain, straight or curved) in a particle field.

Library:

    from bands import find_bands
    bands = find_bands(x, y, gamma)          # x, y, gamma: 1-D arrays, one entry per particle
    for b in bands:
        print(b.angle, b.sense, b.width, b.clear)
        for arm in b.arms:                   # dicts: angle, x0, y0, x1, y1 of the straight part
            print(arm["angle"], arm["bend"])

Command line (reads one tsuchi frame, keeps the particles of one body):

    /usr/bin/python3 tools/bands.py results/particles_000015.vtu [--body 0] [--json]
        [--field max_shear_strain] [--max-bands 4] [--reference] [--plot bands.png]

Angles are measured from the horizontal (x axis), y up. `angle` is signed in (-90, 90]:
positive = the band rises to the right (goes up as x grows), negative = it rises to the left.
`inclination` = |angle| in [0, 90].

Method (see tools/README-bands.md for the reasoning):
 1. High-strain weights: w = max(gamma - t, 0), t = max(70th percentile, median + 2 robust sd)
    of the particles not yet assigned to a band.
 2. Weighted Hough transform of the centred weights w - mean(w) over those particles: for each
    direction (0.5 deg steps) and each offset strip (one particle spacing wide) the sum of the
    centred weights of the particles in the strip. A line along a band collects a large positive
    sum; a line through a uniform field sums to about zero, whatever its length.
 3. Each candidate line is refined: the across-band profile of gamma gives the background level
    and the width (full width at half maximum above the background); the line is re-fitted by
    weighted total least squares (principal axis) on the particles within one width of it, with
    weights gamma - background, using only the stretches of the band whose cross-section lies
    wholly inside the specimen (a cut end would tilt the fit). Repeated until it settles.
 4. A candidate is accepted as a band when it stands out: its core mean is `min_contrast`
    robust standard deviations above the background, it is a ridge (its flanks are lower than
    its core), long, narrow and line-like enough, and not much fainter than the strongest band
    (see find_bands for the limits). Its particles (within one width) are then set aside, the
    threshold of step 1 is recomputed on the rest, and the next band is searched, up to
    `max_bands`. A last pass refits every band with the others' cores left out.
 5. The line only finds a band; its angle is that of the band's chord, which on a curved X
    (arms flatter at the crossing, steeper at the sides) is several degrees off. So each band's
    ridge is traced slice by slice (_trace_ridge: the crest of the across-band profile at
    stations along the line, following the ridge), split into arms where another band crosses,
    and in each arm the longest straight run (direction turning by less than STRAIGHT_TURN) is
    fitted (_arms). The band's `angle` is the length-weighted mean of its arms' straight parts.

Fit quality, reported per band:
  explained  = (sum of the high-strain weights w of the particles within one width of the band's
               centre line) / (sum of w over all particles), w from the threshold t of the
               whole field. 1 = every high-strain particle lies in this band; an X pair gives
               about 0.5 each (the crossing counts for both).
  r2         = 1 - lambda_min / lambda_max of the weighted covariance of the band's particles:
               how line-like the band is (1 = a perfect line).
  contrast   = (mean gamma in the core - background median) / background robust sd.
  straightness, bend, rms, traced: see Band; clear: the drawing gate (is_clear).
Everything is deterministic (no random sampling).
"""
import argparse
import json
import math
import os
import sys
from dataclasses import asdict, dataclass, field

import numpy as np

ROBUST_SD = 1.4826  # MAD -> standard deviation for a normal distribution


@dataclass
class Band:
    angle: float        # degrees in (-90, 90], from the x axis; > 0 rises to the right
    inclination: float  # |angle|, degrees
    sense: str          # "rising right" | "rising left" | "horizontal" | "vertical"
    cx: float           # a point on the centre line (weighted centre of the band), m
    cy: float
    offset: float       # signed distance of the line from the body's centroid, m, along the
    #                     normal (-sin a, cos a)
    x0: float           # end points of the band (its extent along the line), m
    y0: float
    x1: float
    y1: float
    length: float       # m
    width: float        # full width at half maximum of the across-band profile, m
    explained: float    # see module docstring
    r2: float
    contrast: float
    background: float   # median gamma away from the bands
    core_mean: float    # mean gamma within half a width of the centre line
    prominence: float   # (core_mean - higher flank mean) / (core_mean - background)
    coverage: float     # share of the band's length along which its core is high
    line_angle: float = 0.0   # angle of one straight line fitted to the whole band (the chord)
    straight_length: float = 0.0  # total length of the arms' straight parts, m
    straightness: float = 0.0  # straight_length / traced length of the ridge (1 = straight)
    bend: float = 0.0         # largest change of the ridge's direction along an arm, degrees
    rms: float = 0.0          # rms distance of the ridge points from their straight parts, m
    traced: float = 0.0       # share of the slices along the band's high-strain stretch (ends
    #                           as fitted by one line), crossings left out, where a ridge was found
    clear: bool = False       # passes the drawing gate (see is_clear)
    arms: list = field(default_factory=list)   # per arm: dict of Arm fields
    ridge: list = field(default_factory=list)  # traced ridge points [x, y], m, along the band


def _robust(values):
    """Median and robust standard deviation (scaled MAD)."""
    if len(values) == 0:
        return 0.0, 0.0
    med = float(np.median(values))
    return med, ROBUST_SD * float(np.median(np.abs(values - med)))


def _wrap_angle(deg):
    """Line direction angle folded into (-90, 90]."""
    a = math.fmod(deg, 180.0)
    if a <= -90.0:
        a += 180.0
    elif a > 90.0:
        a -= 180.0
    return a


def _sense(angle, tol=1e-9):
    if abs(angle) < tol:
        return "horizontal"
    if abs(angle - 90.0) < tol:
        return "vertical"
    return "rising right" if angle > 0 else "rising left"


class _Field:
    """The particle cloud plus the quantities every step needs."""

    def __init__(self, x, y, gamma):
        self.x = np.asarray(x, dtype=float)
        self.y = np.asarray(y, dtype=float)
        self.g = np.asarray(gamma, dtype=float)
        if not (self.x.shape == self.y.shape == self.g.shape) or self.x.ndim != 1:
            raise ValueError("x, y and gamma must be 1-D arrays of the same length")
        self.n = len(self.x)
        self.cx, self.cy = float(self.x.mean()), float(self.y.mean())
        self.wx = float(np.ptp(self.x))
        self.wy = float(np.ptp(self.y))
        self.size = min(self.wx, self.wy)
        # Mean particle spacing from the bounding box; slightly high for a bulged specimen,
        # which only makes the strips a little wider.
        self.spacing = math.sqrt(max(self.wx * self.wy, 1e-300) / self.n)
        med, sd = _robust(self.g)
        self.median, self.sd = med, sd
        scale = max(float(np.max(np.abs(self.g))), 1e-300)
        self.sd_floor = 1e-9 * scale

    def frame(self, angle, px, py):
        """Along (s) and across (t) coordinates of every particle for the line through (px, py)."""
        a = math.radians(angle)
        dx, dy = self.x - px, self.y - py
        s = dx * math.cos(a) + dy * math.sin(a)
        t = -dx * math.sin(a) + dy * math.cos(a)
        return s, t


def _hough(f, wc, angles, bin_width):
    """Sum of the centred weights wc per (angle, offset strip). Returns accumulator and offsets."""
    # Offset bins symmetric about the centroid, so that flipping a direction by 180 deg (which
    # flips the offset's sign) maps bin j onto bin nbins - 1 - j.
    nbins = int(math.ceil((math.hypot(f.wx, f.wy) + 4 * bin_width) / bin_width))
    half = 0.5 * nbins * bin_width
    acc = np.zeros((len(angles), nbins))
    dx, dy = f.x - f.cx, f.y - f.cy
    for i, a in enumerate(np.radians(angles)):
        rho = -dx * math.sin(a) + dy * math.cos(a)
        idx = np.floor((rho + half) / bin_width).astype(int)
        acc[i] = np.bincount(idx, weights=wc, minlength=nbins)[:nbins]
    # A band is several strips wide; a 3-strip running sum makes the peak sit on its centre
    # instead of on whichever strip the noise favours.
    kernel = np.ones(3)
    acc = np.apply_along_axis(lambda r: np.convolve(r, kernel, mode="same"), 1, acc)
    centres = -half + (np.arange(nbins) + 0.5) * bin_width
    return acc, centres


def _peaks(acc, angles, centres, count, angle_sep, offset_sep):
    """Up to `count` accumulator maxima, each suppressing its neighbourhood (angles wrap at 180)."""
    acc = acc.copy()
    out = []
    step = angles[1] - angles[0]
    na = int(round(angle_sep / step))
    no = max(1, int(round(offset_sep / (centres[1] - centres[0]))))
    for _ in range(count):
        i, j = np.unravel_index(int(np.argmax(acc)), acc.shape)
        if acc[i, j] <= 0:
            break
        out.append((float(angles[i]), float(centres[j]), float(acc[i, j])))
        for di in range(-na, na + 1):
            ii = i + di
            jj = j
            if ii < 0 or ii >= len(angles):
                # Wrapping past +-90 deg flips the normal, so the offset changes sign.
                ii %= len(angles)
                jj = len(centres) - 1 - j
            acc[ii, max(0, jj - no):jj + no + 1] = -np.inf
    return out


def _profile_width(t, g, bg, window, nbin_width):
    """FWHM (above bg) of the across-band profile of gamma, from strip means; None if no ridge."""
    edges = np.arange(-window, window + 1e-12 * window + nbin_width, nbin_width)
    if len(edges) < 4:
        return None
    sel = np.abs(t) < window
    idx = np.digitize(t[sel], edges) - 1
    nb = len(edges) - 1
    ok = (idx >= 0) & (idx < nb)
    cnt = np.bincount(idx[ok], minlength=nb)[:nb]
    tot = np.bincount(idx[ok], weights=g[sel][ok], minlength=nb)[:nb]
    mid = 0.5 * (edges[:-1] + edges[1:])
    have = cnt > 0
    if have.sum() < 3:
        return None
    prof = np.interp(mid, mid[have], tot[have] / cnt[have])
    # Peak near the centre line (the fit has already put the line on the ridge).
    centre = np.abs(mid) <= max(2 * nbin_width, 0.25 * window)
    k0 = int(np.argmax(np.where(centre, prof, -np.inf)))
    peak = prof[k0]
    if peak <= bg:
        return None
    half = bg + 0.5 * (peak - bg)

    def crossing(direction):
        k = k0
        while 0 <= k + direction < nb:
            k2 = k + direction
            if prof[k2] < half:
                # Linear interpolation between the strip centres.
                frac = (prof[k] - half) / (prof[k] - prof[k2])
                return abs(mid[k] + frac * (mid[k2] - mid[k]) - mid[k0])
            k = k2
        return None

    left, right = crossing(-1), crossing(+1)
    if left is None and right is None:
        return None
    # A band along an edge has only one flank inside the body: mirror it.
    if left is None:
        left = right
    if right is None:
        right = left
    return left + right


def _fit_line(f, angle, px, py, excluded, w_hi, opts):
    """Refines one candidate line. Returns a dict of band properties, or None."""
    h = opts["initial_halfwidth"]
    max_h = 0.25 * f.size
    bg, bg_sd = f.median, max(f.sd, f.sd_floor)
    width = None
    for _ in range(12):
        s, t = f.frame(angle, px, py)
        # Background: particles well away from this line and from bands already found.
        far = (np.abs(t) > 3 * h) & ~excluded
        if far.sum() >= 10:
            bg, sd = _robust(f.g[far])
            bg_sd = max(sd, f.sd_floor)
        width = _profile_width(t[~excluded], f.g[~excluded], bg, max(4 * h, 6 * f.spacing), f.spacing)
        if width is None:
            return None
        new_h = min(max(width, 1.5 * f.spacing), max_h)

        # Keep the stretches whose cross-section (|t| < h on both sides) is complete: count all
        # particles per side in slices along the line and compare with a typical full slice.
        inside = (np.abs(t) < new_h) & ~excluded
        if inside.sum() < 5:
            return None
        slice_len = max(2 * f.spacing, new_h)
        sl = np.floor(s / slice_len).astype(int)
        band_all = np.abs(t) < new_h
        smin = sl[band_all].min()
        nsl = sl[band_all].max() - smin + 1
        left = np.bincount(sl[band_all & (t < 0)] - smin, minlength=nsl)
        right = np.bincount(sl[band_all & (t >= 0)] - smin, minlength=nsl)
        full = np.median(np.maximum(left, right)[np.maximum(left, right) > 0])
        complete = (left >= 0.85 * full) & (right >= 0.85 * full)
        keep = inside & complete[np.clip(sl - smin, 0, nsl - 1)]
        # A band that dies out inside the body ends in an oblique cut too: leave out two widths
        # at each end of the high-strain stretch.
        ridge = inside & (f.g > 0.5 * (bg + f.g[inside].max()))
        if ridge.sum() >= 5:
            r_lo, r_hi = np.percentile(s[ridge], [1, 99])
            if r_hi - r_lo > 8 * new_h:
                keep &= (s > r_lo + 2 * new_h) & (s < r_hi - 2 * new_h)
        if keep.sum() < 5:
            keep = inside  # short band: better a slightly biased fit than none

        u = np.maximum(f.g[keep] - bg, 0.0)
        if u.sum() <= 0:
            return None
        xs, ys = f.x[keep], f.y[keep]
        mx, my = np.average(xs, weights=u), np.average(ys, weights=u)
        cov = np.cov(np.vstack([xs - mx, ys - my]), aweights=u, bias=True)
        evals, evecs = np.linalg.eigh(cov)
        d = evecs[:, 1]
        new_angle = _wrap_angle(math.degrees(math.atan2(d[1], d[0])))
        moved = abs(_wrap_angle(new_angle - angle)) + math.hypot(mx - px, my - py) / max(f.size, 1e-300)
        angle, px, py = new_angle, mx, my
        converged = moved < 1e-4 and abs(new_h - h) <= 0.01 * h
        h = new_h
        if converged:
            break

    s, t = f.frame(angle, px, py)
    core = (np.abs(t) <= 0.5 * width) & ~excluded
    if core.sum() < 5:
        return None
    core_mean = float(f.g[core].mean())
    # Flanks between one and two widths away, each side on its own: a ridge is lower on both
    # sides (a side outside the body, as for a band along an edge, is skipped).
    flank_means = []
    for side in (-1, 1):
        fl = (side * t >= width) & (side * t <= 2 * width) & ~excluded
        if fl.sum() >= 5:
            flank_means.append(float(f.g[fl].mean()))
    rise = core_mean - bg
    prominence = (core_mean - max(flank_means)) / rise if flank_means and rise > 0 else 0.0
    # Extent: particles in the core that are clearly part of the ridge.
    strong = core & (f.g > bg + 0.5 * rise)
    if strong.sum() < 3:
        return None
    s_lo, s_hi = np.percentile(s[strong], [1, 99])
    # Continuity: the share of the stretch [s_lo, s_hi], cut into slices, whose core is high.
    # A straight line that merely crosses two other ridges has high ends but a low middle.
    slice_len = max(2 * f.spacing, width)
    along = core & (s >= s_lo) & (s <= s_hi)
    sl = np.floor((s[along] - s_lo) / slice_len).astype(int)
    cnt = np.bincount(sl)
    high = np.bincount(sl, weights=f.g[along]) > (bg + 0.5 * rise) * cnt
    coverage = float(high[cnt > 0].mean()) if (cnt > 0).any() else 0.0
    a = math.radians(angle)
    within = np.abs(t) <= width
    evals = np.linalg.eigvalsh(np.cov(np.vstack([f.x[core], f.y[core]]),
                                      aweights=np.maximum(f.g[core] - bg, 1e-300), bias=True))
    return dict(
        angle=angle, cx=px, cy=py,
        offset=-(px - f.cx) * math.sin(a) + (py - f.cy) * math.cos(a),
        x0=px + s_lo * math.cos(a), y0=py + s_lo * math.sin(a),
        x1=px + s_hi * math.cos(a), y1=py + s_hi * math.sin(a),
        length=float(s_hi - s_lo), width=float(width),
        explained=float(w_hi[within].sum() / max(w_hi.sum(), 1e-300)),
        r2=float(1 - evals[0] / evals[1]) if evals[1] > 0 else 0.0,
        contrast=float(rise / bg_sd), background=bg, core_mean=core_mean,
        prominence=prominence, coverage=coverage, t=t)


@dataclass
class Arm:
    """One arm of a band: a stretch of its traced ridge, between the band's ends and crossings."""
    angle: float          # degrees in (-90, 90], of the arm's straight part
    x0: float             # ends of the straight part, m
    y0: float
    x1: float
    y1: float
    length: float         # length of the straight part, m
    traced_length: float  # length of the whole traced arm, m
    bend: float           # direction of the ridge at its far end minus at its near end, degrees
    #                       (ends: the first and last quarter of the arm, each fitted by a line)
    rms: float            # rms distance of the straight part's ridge points from its line, m
    kinked: bool = False  # bend > MAX_ARM_BEND: the trace has likely left the band (seen on a
    #                       diffuse X at initial positions); not used for the band's angle, not drawn


def _ridge_profile(tt, gg, tc, half_window, spacing, sigma):
    """Across-band profile of one slice, smoothed by a Gaussian of sd sigma, on a fine grid.

    Returns (grid, profile, has_data)."""
    tg = np.arange(tc - half_window, tc + half_window + 1e-12, 0.5 * spacing)
    k = np.exp(-0.5 * ((tg[:, None] - tt[None, :]) / sigma) ** 2)
    dens = k.sum(axis=1)
    prof = (k * gg[None, :]).sum(axis=1) / np.maximum(dens, 1e-300)
    have = dens > 0.3 * np.median(dens[dens > 0]) if (dens > 0).any() else dens > 0
    return tg, prof, have


def _trace_ridge(f, fit, other):
    """Follows a band's ridge slice by slice along its fitted line.

    At stations every ds along the line, the particles of a slice 2 ds thick (others' cores
    `other` left out) give the across-band profile of gamma; the profile is smoothed by a Gaussian
    of sd max(0.6 spacing, width / 8) and the ridge position is the centroid of its top fifth
    (above background + 0.8 (peak - background)): the crest. A station is
    dropped where the ridge is lost (peak under 0.3 of the band's rise), cut by the body's edge
    (the profile does not fall to half on both sides inside the body) or crossed by another band
    (more than 10 % of the particles within one width are in another band's core). The window
    follows the ridge: each of the 3 passes centres it on the previous pass's ridge,
    extrapolated linearly past its ends.

    Returns (s, t, crossed): arrays over the stations, t = nan where no ridge was found, crossed =
    True where another band crosses; s, t in the frame of the fitted line."""
    angle, px, py, w = fit["angle"], fit["cx"], fit["cy"], fit["width"]
    bg = fit["background"]
    rise = fit["core_mean"] - bg
    s, t = f.frame(angle, px, py)
    ds = max(1.5 * f.spacing, 0.25 * w)
    half_window = max(1.5 * w, 4 * f.spacing)
    sigma = max(0.6 * f.spacing, w / 8)
    stations = np.arange(s.min() + 0.5 * ds, s.max(), ds)
    order = np.argsort(s)
    s_sorted = s[order]
    centre = np.zeros(len(stations))
    ridge = np.full(len(stations), np.nan)
    crossed = np.zeros(len(stations), dtype=bool)
    for _ in range(3):
        ridge = np.full(len(stations), np.nan)
        crossed[:] = False
        for k, sk in enumerate(stations):
            lo, hi = np.searchsorted(s_sorted, [sk - ds, sk + ds])
            idx = order[lo:hi]
            idx = idx[np.abs(t[idx] - centre[k]) < half_window]
            if len(idx) < 5:
                continue
            core = np.abs(t[idx] - centre[k]) < w
            if core.any() and other[idx[core]].mean() > 0.1:
                crossed[k] = True
                continue
            idx = idx[~other[idx]]
            tg, prof, have = _ridge_profile(t[idx], f.g[idx], centre[k], half_window, f.spacing, sigma)
            cand = have & (np.abs(tg - centre[k]) < 0.75 * half_window)
            if not cand.any():
                continue
            k0 = int(np.argmax(np.where(cand, prof, -np.inf)))
            if prof[k0] - bg < 0.3 * rise:
                continue
            def extent(level):
                a = k0
                while a > 0 and have[a - 1] and prof[a - 1] >= level:
                    a -= 1
                b = k0
                while b < len(tg) - 1 and have[b + 1] and prof[b + 1] >= level:
                    b += 1
                return a, b

            # The profile must fall under half its height on both sides within the body, with
            # data a quarter width beyond (else the band is cut by the edge and biased).
            a, b = extent(bg + 0.5 * (prof[k0] - bg))
            margin = max(1, int(round(0.25 * w / (tg[1] - tg[0]))))
            if a - margin < 0 or b + margin >= len(tg) or not have[a - margin:b + margin + 1].all():
                continue
            # The crest: centroid of the profile's top fifth (the half-height region's centroid
            # would follow a skewed flank, as next to an X's crossing).
            level = bg + 0.8 * (prof[k0] - bg)
            a, b = extent(level)
            u = prof[a:b + 1] - level
            if u.sum() <= 0:
                u = np.ones(b - a + 1)
            ridge[k] = float((u * tg[a:b + 1]).sum() / u.sum())
        ok = np.isfinite(ridge)
        # Outliers: a ridge point far (0.3 width) from the median of its neighbours.
        for k in np.flatnonzero(ok):
            nb = ok & (np.abs(np.arange(len(stations)) - k) <= 2)
            if nb.sum() >= 3 and abs(ridge[k] - np.median(ridge[nb])) > 0.3 * w:
                ridge[k] = np.nan
        ok = np.isfinite(ridge)
        if ok.sum() < 3:
            break
        # Next pass: window on this ridge, extrapolated linearly past its ends.
        ks = np.flatnonzero(ok)
        centre = np.interp(stations, stations[ks], ridge[ks])
        for end, k_end, outside in ((ks[:3], ks[0], stations < stations[ks[0]]),
                                    (ks[-3:], ks[-1], stations > stations[ks[-1]])):
            slope = float(np.clip(np.polyfit(stations[end], ridge[end], 1)[0], -1.0, 1.0))
            centre[outside] = ridge[k_end] + slope * (stations[outside] - stations[k_end])
    return stations, ridge, crossed


def _line_fit(x, y):
    """Total least squares line through points: (angle in degrees, mean x, mean y, residuals)."""
    mx, my = x.mean(), y.mean()
    evals, evecs = np.linalg.eigh(np.cov(np.vstack([x - mx, y - my]), bias=True))
    d = evecs[:, 1]
    resid = -(x - mx) * d[1] + (y - my) * d[0]
    return _wrap_angle(math.degrees(math.atan2(d[1], d[0]))), mx, my, resid


# A run of ridge points is straight when its direction turns by less than about this, degrees.
STRAIGHT_TURN = 4.0
# An arm whose direction turns by more than this, degrees, end to end, is `kinked`.
MAX_ARM_BEND = 25.0


def _straight_part(x, y, tol, turn=None, min_points=4):
    """Longest run of consecutive ridge points (3-point running mean) lying within a tolerance
    of their own fitted line (ties: the run nearest the middle). The tolerance is the larger of tol and the sagitta of a
    circular arc as long as the run whose direction turns by `turn` degrees (L turn / 8, turn in
    radians): a run is straight when its direction changes by less than about `turn`. Returns
    (i, j) inclusive, or None."""
    n = len(x)
    best, best_key = None, None
    turn = STRAIGHT_TURN if turn is None else turn
    per_length = math.radians(turn) / 8
    if n >= 5:  # a 3-point running mean takes out slice-to-slice jitter, not gradual bends
        x = np.concatenate([x[:1], (x[:-2] + x[1:-1] + x[2:]) / 3, x[-1:]])
        y = np.concatenate([y[:1], (y[:-2] + y[1:-1] + y[2:]) / 3, y[-1:]])
    for i in range(n - min_points + 1):
        for j in range(n - 1, i + min_points - 2, -1):
            if best_key is not None and j - i < best_key[0]:
                break
            _, _, _, resid = _line_fit(x[i:j + 1], y[i:j + 1])
            length = math.hypot(x[j] - x[i], y[j] - y[i])
            if np.abs(resid).max() <= max(tol, per_length * length):
                key = (j - i, -abs(i + j - (n - 1)))
                if best_key is None or key > best_key:
                    best, best_key = (i, j), key
                break
    return best


def _arms(f, fit, stations, ridge, crossed):
    """Splits a traced ridge into arms and fits the straight part of each. Returns (arms, points):
    a list of Arm and the ridge points as an (n, 2) array."""
    a = math.radians(fit["angle"])
    w = fit["width"]
    ok = np.isfinite(ridge)
    xs = fit["cx"] + stations * math.cos(a) - np.where(ok, ridge, 0) * math.sin(a)
    ys = fit["cy"] + stations * math.sin(a) + np.where(ok, ridge, 0) * math.cos(a)
    points = np.column_stack([xs[ok], ys[ok]])
    # Arms: runs of ridge points broken by a crossing band or by more than 2 missing stations.
    runs, cur, missing = [], [], 0
    for k in range(len(stations)):
        if ok[k]:
            cur.append(k)
            missing = 0
        else:
            missing += 1
            if crossed[k] or missing > 2:
                if cur:
                    runs.append(cur)
                cur = []
    if cur:
        runs.append(cur)
    runs = [r for r in runs if len(r) >= 4]
    # Scatter of the ridge positions (second differences of consecutive points), for the
    # tolerance of "straight": 4 sd of the scatter, but at least 3 % of the band's width and a
    # quarter of the particle spacing. (Looser, a tenth of the width, lets a straight run
    # reach well into a bend and tilts it by a degree or more.)
    d2 = [ridge[r[i + 1]] - 2 * ridge[r[i]] + ridge[r[i - 1]] for r in runs for i in range(1, len(r) - 1)
          if r[i + 1] - r[i - 1] == 2]
    scatter = ROBUST_SD * float(np.median(np.abs(d2))) / math.sqrt(6) if len(d2) >= 3 else 0.0
    tol = max(0.03 * w, 4 * scatter, 0.25 * f.spacing)
    arms = []
    for r in runs:
        x, y = xs[r], ys[r]
        traced = float(np.hypot(np.diff(x), np.diff(y)).sum())
        q = max(3, len(r) // 4)
        bend = abs(_wrap_angle(_line_fit(x[-q:], y[-q:])[0] - _line_fit(x[:q], y[:q])[0]))
        part = _straight_part(x, y, tol)
        if part is None:
            continue
        i, j = part
        ang, mx, my, resid = _line_fit(x[i:j + 1], y[i:j + 1])
        c, s_ = math.cos(math.radians(ang)), math.sin(math.radians(ang))
        along = (x[i:j + 1] - mx) * c + (y[i:j + 1] - my) * s_
        arms.append(Arm(angle=ang, x0=mx + along.min() * c, y0=my + along.min() * s_,
                        x1=mx + along.max() * c, y1=my + along.max() * s_,
                        length=float(np.ptp(along)), traced_length=traced, bend=bend,
                        rms=float(np.sqrt(np.mean(resid ** 2))), kinked=bend > MAX_ARM_BEND))
    return arms, points


def _cores_of_others(fits, k, n):
    """The particles within half a width of every band fit but the k-th."""
    others = np.zeros(n, dtype=bool)
    for j, g in enumerate(fits):
        if j != k:
            others |= np.abs(g["t"]) <= 0.5 * g["width"]
    return others


def find_bands(x, y, gamma, max_bands=4, min_contrast=2.0, min_prominence=0.3,
               min_length=0.4, min_coverage=0.7, max_width=0.4, min_r2=0.8, min_relative=0.25,
               angle_step=0.5, candidates=4, clear_contrast=6.0):
    """Shear bands in the field gamma(x, y), strongest first. See the module docstring.

    max_bands      -- stop after this many bands
    min_contrast   -- core mean at least this many robust sd above the background median
    min_prominence -- (core mean - higher flank mean) / (core mean - background) at least this
    min_length     -- length at least this fraction of the body's smaller dimension
    min_coverage   -- share of the band's length along which its core is high, at least this
    max_width      -- width at most this fraction of the body's smaller dimension
    min_r2         -- line-likeness 1 - lambda_min / lambda_max at least this (a straight band
                      gives about 1 - (width / length)^2)
    min_relative   -- rise above background at least this fraction of the strongest band's
                      (drops faint companions of a dominant band)
    angle_step     -- Hough direction step, degrees
    candidates     -- Hough peaks tried per round before giving up
    Returns a list of Band.
    """
    f = _Field(x, y, gamma)
    if f.n < 20 or f.size <= 0:
        return []
    t_hi = max(float(np.percentile(f.g, 70)), f.median + 2 * f.sd)
    w_hi = np.maximum(f.g - t_hi, 0.0)
    if w_hi.sum() <= 0:
        return []  # a uniform field has nothing above its threshold
    opts = dict(initial_halfwidth=max(4 * f.spacing, 0.1 * f.size))
    angles = np.arange(-90.0 + angle_step, 90.0 + 1e-9, angle_step)
    bin_width = f.spacing

    def passes(fit, strongest_rise=0.0):
        rise = fit["core_mean"] - fit["background"]
        return (fit["contrast"] >= min_contrast and fit["prominence"] >= min_prominence
                and fit["length"] >= min_length * f.size and fit["coverage"] >= min_coverage
                and fit["width"] <= max_width * f.size and fit["r2"] >= min_r2
                and rise >= min_relative * strongest_rise)

    found = []
    excluded = np.zeros(f.n, dtype=bool)
    for _ in range(max_bands):
        # Threshold the particles not yet taken by a band afresh: once the strongest band is out,
        # a weaker one (the second arm of an X) may lie below the first round's threshold.
        rest = ~excluded
        if rest.sum() < 20:
            break
        med, sd = _robust(f.g[rest])
        w = np.maximum(f.g - max(float(np.percentile(f.g[rest], 70)), med + 2 * sd), 0.0)
        if w[rest].sum() <= 0:
            break
        wc = np.where(rest, w - w[rest].mean(), 0.0)
        acc, centres = _hough(f, wc, angles, bin_width)
        strongest = max((g["core_mean"] - g["background"] for g in found), default=0.0)
        accepted = None
        for angle, rho, _score in _peaks(acc, angles, centres, candidates, 5.0, 4 * bin_width):
            a = math.radians(angle)
            px, py = f.cx - rho * math.sin(a), f.cy + rho * math.cos(a)
            fit = _fit_line(f, angle, px, py, excluded, w_hi, opts)
            if fit is None or not passes(fit, strongest) or any(_same_band(fit, g) for g in found):
                continue
            accepted = fit
            break
        if accepted is None:
            break
        found.append(accepted)
        # Take the band out of the search: its particles no longer vote, and the background of
        # later bands is measured away from it.
        excluded |= np.abs(accepted["t"]) <= accepted["width"]

    # Final pass: refit each band with the others' particles left out, so that an X crossing
    # does not pull one arm towards the other; a band that no longer passes the tests (it was
    # made of another band's shoulder) is dropped.
    refits = []
    for k, fit in enumerate(found):
        others = _cores_of_others(found, k, f.n)
        refit = _fit_line(f, fit["angle"], fit["cx"], fit["cy"], others, w_hi, opts)
        if refit is not None:
            refits.append(refit)
    strongest = max((g["core_mean"] - g["background"] for g in refits), default=0.0)
    refits = [g for g in refits if passes(g, strongest)]
    # Each band's ridge traced slice by slice, its arms (split at crossings) and their
    # straight parts: the reported angle is theirs, not the whole band's chord.
    bands = []
    for k, fit in enumerate(refits):
        others = _cores_of_others(refits, k, f.n)
        stations, ridge, crossed = _trace_ridge(f, fit, others)
        a = math.radians(fit["angle"])
        ends = [(fit[xk] - fit["cx"]) * math.cos(a) + (fit[yk] - fit["cy"]) * math.sin(a)
                for xk, yk in (("x0", "y0"), ("x1", "y1"))]
        along = (stations >= min(ends)) & (stations <= max(ends)) & ~crossed
        fit["traced"] = float(np.isfinite(ridge[along]).mean()) if along.any() else 0.0
        arms, points = _arms(f, fit, stations, ridge, crossed)
        bands.append(_to_band(fit, arms, points, f, clear_contrast))
    bands.sort(key=lambda b: -b.explained)
    return bands


def is_clear(band, size, min_contrast=6.0, max_width=0.35, min_traced=0.6):
    """The drawing gate: True when a band is a well-defined ridge worth drawing as a line.

    contrast >= min_contrast (an incipient band at 2 % axial strain has 4-5, a formed one 15 and
    more), width <= max_width * size (size: the body's smaller side), and its ridge traced along
    at least min_traced of its length (a diffuse X, whose crossing is a broad blob, has short
    arms)."""
    return (band.contrast >= min_contrast and band.width <= max_width * size
            and band.traced >= min_traced and any(not a["kinked"] for a in band.arms))


def _same_band(a, b):
    """True when two fits describe the same ridge (nearly parallel and overlapping)."""
    if abs(_wrap_angle(a["angle"] - b["angle"])) > 5.0:
        return False
    ang = math.radians(b["angle"])
    dist = abs(-(a["cx"] - b["cx"]) * math.sin(ang) + (a["cy"] - b["cy"]) * math.cos(ang))
    return dist < max(a["width"], b["width"])


def _to_band(fit, arms, points, f, clear_contrast):
    """A Band from a line fit and its traced arms (straight parts)."""
    line_angle = float(fit["angle"])
    used = [a for a in arms if not a.kinked]
    total = sum(a.length for a in used)
    if total > 0:
        # Length-weighted mean direction of the straight parts (doubled angles: a direction
        # of a line is defined modulo 180 degrees).
        c = sum(a.length * math.cos(math.radians(2 * a.angle)) for a in used)
        s = sum(a.length * math.sin(math.radians(2 * a.angle)) for a in used)
        angle = _wrap_angle(0.5 * math.degrees(math.atan2(s, c)))
        longest = max(used, key=lambda a: a.length)
        cx, cy = 0.5 * (longest.x0 + longest.x1), 0.5 * (longest.y0 + longest.y1)
        traced = sum(a.traced_length for a in used)
        rms = math.sqrt(sum(a.length * a.rms ** 2 for a in used) / total)
    else:  # no ridge could be traced: the chord is all there is
        angle, cx, cy, traced, rms = line_angle, fit["cx"], fit["cy"], 0.0, 0.0
    a = math.radians(angle)
    off = -(cx - f.cx) * math.sin(a) + (cy - f.cy) * math.cos(a)
    if len(points) >= 2:
        (x0, y0), (x1, y1) = points[0], points[-1]
    else:
        x0, y0, x1, y1 = fit["x0"], fit["y0"], fit["x1"], fit["y1"]
    band = Band(angle=angle, inclination=abs(angle), sense=_sense(angle),
                cx=float(cx), cy=float(cy), offset=float(off),
                x0=float(x0), y0=float(y0), x1=float(x1), y1=float(y1),
                length=float(math.hypot(x1 - x0, y1 - y0)), width=fit["width"],
                explained=fit["explained"], r2=fit["r2"], contrast=fit["contrast"],
                background=fit["background"], core_mean=fit["core_mean"],
                prominence=fit["prominence"], coverage=fit["coverage"], line_angle=line_angle,
                straight_length=float(total), straightness=float(total / traced) if traced > 0 else 0.0,
                bend=max((a_.bend for a_ in arms), default=0.0), rms=float(rms),
                traced=float(fit.get("traced", 0.0)),
                arms=[asdict(a_) for a_ in arms], ridge=[[float(p), float(q)] for p, q in points])
    band.clear = is_clear(band, f.size, min_contrast=clear_contrast)
    return band


def bands_of_frame(path, body=0, field="max_shear_strain", reference=False, **kwargs):
    """Reads a .vtu frame and returns (bands, x, y, gamma) for the particles of `body`.

    reference=True places the particles at their initial positions (position - displacement),
    which gives the bands' orientation in the undeformed specimen."""
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    from vtu import read_vtu

    frame = read_vtu(path)
    sel = np.ones(len(frame["points"]), dtype=bool)
    if body is not None and "body" in frame:
        sel = frame["body"] == body
    pos = frame["points"] - frame["displacement"] if reference else frame["points"]
    x, y = pos[sel, 0], pos[sel, 1]
    gamma = frame[field][sel]
    return find_bands(x, y, gamma, **kwargs), x, y, gamma


def describe(bands):
    """Human-readable table of bands, then one line per arm."""
    if not bands:
        return "no shear band found"
    lines = ["band  angle(deg)  sense          chord(deg)  width(mm)  length(mm)  straight  "
             "bend(deg)  traced  explained  contrast  clear"]
    for i, b in enumerate(bands, 1):
        lines.append(f"{i:<5d} {b.angle:+8.2f}    {b.sense:<13s}  {b.line_angle:+8.2f}  "
                     f"{1e3 * b.width:9.2f}  {1e3 * b.length:10.1f}  {b.straightness:8.2f}  "
                     f"{b.bend:9.1f}  {b.traced:6.2f}  {b.explained:9.3f}  {b.contrast:8.1f}  "
                     f"{'yes' if b.clear else 'no'}")
    for i, b in enumerate(bands, 1):
        for j, a in enumerate(b.arms, 1):
            lines.append(f"  band {i} arm {j}: {a['angle']:+7.2f} deg, straight from "
                         f"({1e3 * a['x0']:.1f}, {1e3 * a['y0']:.1f}) to ({1e3 * a['x1']:.1f}, "
                         f"{1e3 * a['y1']:.1f}) mm, {1e3 * a['length']:.1f} of "
                         f"{1e3 * a['traced_length']:.1f} mm traced, bend {a['bend']:.1f} deg"
                         + (", kinked (not used)" if a["kinked"] else ""))
    return "\n".join(lines)


def plot_bands(ax, bands, only_clear=True, **style):
    """Draws the straight part of each arm (not kinked) of the bands on a matplotlib axis; with
    only_clear, only of the bands that pass the drawing gate. Returns the number of lines."""
    kw = dict(color="k", lw=1.0)
    kw.update(style)
    drawn = 0
    for b in bands:
        if only_clear and not b.clear:
            continue
        for a in b.arms:
            if not a["kinked"]:
                ax.plot([a["x0"], a["x1"]], [a["y0"], a["y1"]], **kw)
                drawn += 1
    return drawn


def main(argv=None):
    p = argparse.ArgumentParser(description="Find shear bands in a tsuchi particle frame.")
    p.add_argument("frame", help="particles_NNNNNN.vtu")
    p.add_argument("--body", type=int, default=0, help="body id to analyse (default 0; -1 = all)")
    p.add_argument("--field", default="max_shear_strain")
    p.add_argument("--max-bands", type=int, default=4)
    p.add_argument("--min-contrast", type=float, default=2.0)
    p.add_argument("--reference", action="store_true",
                   help="use the particles' initial positions (bands in the undeformed specimen)")
    p.add_argument("--json", action="store_true", help="print the bands as JSON")
    p.add_argument("--plot", help="write a picture of the field with the bands drawn")
    a = p.parse_args(argv)
    bands, x, y, gamma = bands_of_frame(a.frame, body=None if a.body < 0 else a.body,
                                        field=a.field, reference=a.reference,
                                        max_bands=a.max_bands, min_contrast=a.min_contrast)
    if a.json:
        print(json.dumps([asdict(b) for b in bands], indent=1))
    else:
        print(f"{a.frame}: {len(x)} particles, {a.field} median {np.median(gamma):.4g}, "
              f"max {np.max(gamma):.4g}")
        print(describe(bands))
    if a.plot:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        fig, ax = plt.subplots(figsize=(4, 6))
        sc = ax.scatter(x, y, c=gamma, s=4, cmap="jet", linewidths=0)
        for b in bands:  # the traced ridge, as dots
            if b.ridge:
                r = np.array(b.ridge)
                ax.plot(r[:, 0], r[:, 1], "o", color="w", mec="k", mew=0.4, ms=2.5)
        plot_bands(ax, bands, only_clear=False, color="k", lw=1.6)
        for i, b in enumerate(bands, 1):
            ax.annotate(f"{i}: {b.angle:+.1f}{'' if b.clear else ' (not clear)'}", (b.cx, b.cy),
                        fontsize=8)
        ax.set_title("dots: traced ridge; lines: straight parts", fontsize=8)
        ax.set_aspect("equal")
        fig.colorbar(sc, ax=ax, label=a.field)
        fig.tight_layout()
        fig.savefig(a.plot, dpi=120)
    return 0


if __name__ == "__main__":
    sys.exit(main())
