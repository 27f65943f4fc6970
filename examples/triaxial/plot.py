"""Plots the plane-strain triaxial study: stress-strain curves and shear-strain snapshots.

usage: /usr/bin/python3 examples/triaxial/plot.py RESULTS_ROOT [CASE ...] [--no-bands] [--vmax V]

RESULTS_ROOT holds one folder per case (test1_fixed, test1_free, ..., test3_free), each with a
tsuchi run's recorders.csv and particles.pvd; cases that are missing are skipped. Writes
  RESULTS_ROOT/stress_strain.png   q against axial strain for every case, with the Mohr-Coulomb
                                   peak of each test as a dotted horizontal line (in the legend)
  RESULTS_ROOT/CASE/shear_strain.png
                                   maximum shear strain of the deformed specimen at 2, 5, 10, 15 %
                                   axial strain (and 50 % when the run got there), each panel on
                                   its own colour scale (0 to its 99.5th percentile, or 0 to
                                   --vmax for all) with its own colour bar; the cap in grey; the
                                   straight parts of the shear bands that pass the detector's
                                   gate (tools/bands.py, `clear`) drawn as lines
"""
import argparse
import math
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "..", "tools"))
import matplotlib  # noqa: E402

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import matplotlib.patheffects as patheffects  # noqa: E402
from bands import find_bands, plot_bands  # noqa: E402
from vtu import read_pvd, read_vtu  # noqa: E402

# The paper's soil (Kiriyama 2015, table 2) and the three confining pressures, kPa.
COHESION_KPA = 8.5
FRICTION_DEG = 30.5
CONFINING_KPA = {"test1": 10.0, "test2": 50.0, "test3": 100.0}
CASES = [f"{t}_{cap}" for t in ("test1", "test2", "test3") for cap in ("fixed", "free")]
COLOURS = {"test1": "tab:blue", "test2": "tab:orange", "test3": "tab:green"}
SNAPSHOT_STRAINS = (0.02, 0.05, 0.10, 0.15, 0.50)
# Cap velocity / specimen height = 0.02 m/s / 0.1 m: axial strain per second, used only when a
# case has no recorders.csv.
STRAIN_RATE = 0.2
STRAIN_TOL = 0.005  # a snapshot is drawn only if a frame lies within 0.5 % strain of it


def mc_peak(confining_kpa, c=COHESION_KPA, phi_deg=FRICTION_DEG):
    """Mohr-Coulomb peak deviator in plane strain: q = p (N - 1) + 2 c sqrt(N)."""
    s = math.sin(math.radians(phi_deg))
    n_phi = (1 + s) / (1 - s)
    return confining_kpa * (n_phi - 1) + 2 * c * math.sqrt(n_phi)


def test_of(case):
    return case.split("_")[0]


def cap_of(case):
    return case.split("_")[1] if "_" in case else ""


def read_recorders(case_dir):
    """recorders.csv as a dict of column name -> array, or None if it is missing or empty."""
    path = os.path.join(case_dir, "recorders.csv")
    if not os.path.exists(path):
        return None
    data = np.genfromtxt(path, delimiter=",", names=True)
    if data.size == 0:
        return None
    data = np.atleast_1d(data)
    return {name: np.asarray(data[name], dtype=float) for name in data.dtype.names}


def frames_with_strain(case_dir, rec=None):
    """[(axial strain, time, vtu path)] of a case's frames, the strain taken from the recorder."""
    pvd = os.path.join(case_dir, "particles.pvd")
    if not os.path.exists(pvd):
        return []
    frames = [(t, os.path.join(case_dir, name)) for t, name in read_pvd(pvd)]
    frames = [(t, p) for t, p in frames if os.path.exists(p)]
    if rec is None:
        rec = read_recorders(case_dir)
    out = []
    for t, path in frames:
        if rec is not None and "axial_strain" in rec and len(rec["time"]) > 0:
            # The recorder row nearest in time to the frame (frames are written on recorder
            # steps, so this is the frame's own strain, not an interpolation).
            k = int(np.argmin(np.abs(rec["time"] - t)))
            strain = float(rec["axial_strain"][k])
        else:
            strain = STRAIN_RATE * t
        out.append((strain, t, path))
    return out


def frame_near(frames, strain, tol=STRAIN_TOL):
    """The frame whose recorded axial strain is nearest `strain`, or None if none within tol."""
    if not frames:
        return None
    best = min(frames, key=lambda f: abs(f[0] - strain))
    return best if abs(best[0] - strain) <= tol else None


def specimen_bands(frame):
    """Shear bands of the specimen (body 0) in a frame read with read_vtu."""
    sel = frame["body"] == 0
    return find_bands(frame["points"][sel, 0], frame["points"][sel, 1], frame["max_shear_strain"][sel])


def describe_bands(bands):
    """Angles of the clear bands, then the others' in brackets (found, but not drawn)."""
    clear = [f"{b.angle:+.1f}" for b in bands if b.clear]
    faint = [f"{b.angle:+.1f}" for b in bands if not b.clear]
    text = ", ".join(clear) if clear else "none clear"
    return text + (f" ({', '.join(faint)} faint)" if faint else "")


def draw_band_lines(ax, bands):
    """Draws the straight part of every arm of every clear band (bands.py's gate: contrast, width,
    traced share; kinked arms left out); returns the number of lines drawn."""
    outline = [patheffects.Stroke(linewidth=2.4, foreground="k"), patheffects.Normal()]
    return plot_bands(ax, bands, only_clear=True, color="w", lw=1.2, path_effects=outline,
                      solid_capstyle="butt")


def plot_stress_strain(root, cases, out):
    fig, ax = plt.subplots(figsize=(10.5, 5.5))
    tests_drawn, caps_drawn = set(), set()
    for case in cases:
        rec = read_recorders(os.path.join(root, case))
        if rec is None or "q_kPa" not in rec:
            continue
        test = test_of(case)
        ax.plot(100 * rec["axial_strain"], rec["q_kPa"], color=COLOURS.get(test, "k"),
                ls="-" if cap_of(case) == "fixed" else "--", lw=1.2,
                label=f"{test} ({CONFINING_KPA.get(test, 0):g} kPa), cap {cap_of(case)}")
        tests_drawn.add(test)
        caps_drawn.add(cap_of(case))
    for test in sorted(tests_drawn):
        if test not in CONFINING_KPA:
            continue
        q = mc_peak(CONFINING_KPA[test])
        # Labelled in the legend, not by a text at the line's end (which the frame cut).
        ax.axhline(q, color=COLOURS[test], ls=":", lw=1.0, label=f"{test}: Mohr-Coulomb peak {q:.1f} kPa")
    ax.set_xlabel("axial strain (%)")
    ax.set_ylabel("deviator stress q (kPa)")
    ax.set_xlim(left=0)
    ax.set_ylim(bottom=0)
    title = "plane-strain triaxial compression"
    if caps_drawn == {"fixed", "free"}:
        title += " (solid: cap fixed, dashed: cap free)"
    ax.set_title(title)
    ax.grid(alpha=0.3)
    if tests_drawn:
        # Beside the axes: inside, it hides the curves of one case or another at some strain.
        ax.legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0.0)
    fig.tight_layout()
    fig.savefig(out, dpi=120)
    plt.close(fig)


def plot_snapshots(case_dir, title, out, draw_bands=True, vmax=None):
    """Max-shear-strain snapshots of one case; returns [(target strain, frame strain, bands)].

    Each panel has its own colour scale, 0 to the 99.5th percentile of the specimen's strain in
    that frame (or 0 to vmax in every panel when given): a scale shared with the 15 % frame
    left the 2 % panel uniformly dark. The cap (every body but the specimen, body 0) is grey."""
    frames = frames_with_strain(case_dir)
    chosen = []
    for target in SNAPSHOT_STRAINS:
        f = frame_near(frames, target)
        if f is not None and all(f[2] != c[1][2] for c in chosen):
            chosen.append((target, f))
    if not chosen:
        return []
    data = [read_vtu(f[2]) for _, f in chosen]
    xs = np.concatenate([d["points"][:, 0] for d in data])
    ys = np.concatenate([d["points"][:, 1] for d in data])
    pad = 0.005
    xlim = (xs.min() - pad, xs.max() + pad)
    ylim = (min(0.0, ys.min()) - pad, ys.max() + pad)

    npanel = len(chosen)
    aspect = (ylim[1] - ylim[0]) / (xlim[1] - xlim[0])
    panel_w = 2.4
    fig, axes = plt.subplots(1, npanel, figsize=(panel_w * npanel + 0.5, 0.85 * panel_w * aspect + 1.9),
                             squeeze=False, constrained_layout=True)
    axes = axes[0]
    results, scatters = [], []
    lines_drawn = 0
    for ax, (target, (strain, time, path)), d in zip(axes, chosen, data):
        ax.set_xlim(*xlim)
        ax.set_ylim(*ylim)
        ax.set_aspect("equal")
        spec = d["body"] == 0
        gamma = d["max_shear_strain"]
        top = vmax if vmax is not None else float(np.percentile(gamma[spec], 99.5)) or 1.0
        # Particle spacing from the specimen's particle count and initial area (positions minus
        # displacements), for markers about one spacing across.
        p0 = d["points"] - d["displacement"]
        area0 = np.ptp(p0[spec, 0]) * np.ptp(p0[spec, 1])
        spacing = math.sqrt(area0 / max(spec.sum(), 1)) if area0 > 0 else 1e-3
        cap = ~spec
        if cap.any():
            sc_cap = ax.scatter(d["points"][cap, 0], d["points"][cap, 1], c="0.6", s=1.0, marker="s",
                                linewidths=0)
            scatters.append((ax, sc_cap, spacing))
        # Most strained particles drawn last, so that overlapping markers do not hide a band.
        idx = np.flatnonzero(spec)
        idx = idx[np.argsort(gamma[idx], kind="stable")]
        sc = ax.scatter(d["points"][idx, 0], d["points"][idx, 1], c=gamma[idx],
                        s=1.0, marker="s", linewidths=0, cmap="jet", vmin=0.0, vmax=top)
        scatters.append((ax, sc, spacing))
        bar = fig.colorbar(sc, ax=ax, orientation="horizontal", shrink=0.9, aspect=25, pad=0.02,
                           extend="max" if gamma[spec].max() > top else "neither")
        bar.ax.tick_params(labelsize=7)
        ax.set_xlabel("x (m)", fontsize=8)
        bands = specimen_bands(d)
        if draw_bands:
            lines_drawn += draw_band_lines(ax, bands)
        ax.set_title(f"{100 * strain:.0f} %\nbands: {describe_bands(bands)}", fontsize=8)
        ax.tick_params(labelsize=7)
        results.append((target, strain, bands))
    axes[0].set_ylabel("y (m)", fontsize=8)
    key = "maximum shear strain, each panel on its own scale (bar below it); cap in grey"
    if lines_drawn:
        # The key names only what is drawn.
        key += ";\nwhite lines: straight part of each arm of the clear bands (tools/bands.py)"
    fig.suptitle(f"{title}\n{key}", fontsize=9)
    # Marker sizes are in points: convert once the layout (and so each axis' scale) is final.
    fig.canvas.draw()
    for ax, sc, spacing in scatters:
        pts_per_m = ax.get_window_extent().width / fig.dpi * 72 / (xlim[1] - xlim[0])
        # 1.5 spacings: particles drift apart in a band and would leave white gaps.
        sc.set_sizes([(1.5 * spacing * pts_per_m) ** 2])
    fig.savefig(out, dpi=120)
    plt.close(fig)
    return results


def present_cases(root, wanted=None):
    names = wanted if wanted else CASES
    return [c for c in names if os.path.isdir(os.path.join(root, c))
            and (os.path.exists(os.path.join(root, c, "recorders.csv"))
                 or os.path.exists(os.path.join(root, c, "particles.pvd")))]


def main(argv=None):
    p = argparse.ArgumentParser(description="Plots the triaxial study's results.")
    p.add_argument("root", help="folder holding test1_fixed/, test1_free/, ...")
    p.add_argument("cases", nargs="*", help="cases to plot (default: every one present)")
    p.add_argument("--no-bands", action="store_true", help="do not draw the detected shear bands")
    p.add_argument("--vmax", type=float,
                   help="top of the shear-strain colour scale, the same in every panel "
                        "(default: each panel its own 99.5th percentile)")
    a = p.parse_intermixed_args(argv)  # options may come between the cases
    cases = present_cases(a.root, a.cases)
    if not cases:
        print(f"no cases under {a.root}", file=sys.stderr)
        return 1
    out = os.path.join(a.root, "stress_strain.png")
    plot_stress_strain(a.root, cases, out)
    print(f"wrote {out}")
    for case in cases:
        test = test_of(case)
        title = f"{case}: confining {CONFINING_KPA.get(test, 0):g} kPa, cap {cap_of(case)}"
        out = os.path.join(a.root, case, "shear_strain.png")
        shots = plot_snapshots(os.path.join(a.root, case), title, out, not a.no_bands, a.vmax)
        if shots:
            print(f"wrote {out} ({', '.join(f'{100 * s:.0f} %' for _, s, _ in shots)})")
        else:
            print(f"{case}: no frames near 2, 5, 10, 15 or 50 % strain")
    return 0


if __name__ == "__main__":
    sys.exit(main())
