#!/usr/bin/python3
"""Transfer function of the shaken column (examples/shaking_column) against uniform undamped soil
on rigid rock, |H(f)| = 1 / |cos(2 pi f H / Vs)| (Kramer 1996, Geotechnical Earthquake
Engineering, section 7.2.1).

Usage:
    /usr/bin/python3 examples/shaking_column/study.py RESULTS_DIR [--csv transfer.csv] [--plot transfer.png]

Reads RESULTS_DIR/recorders.csv (time, top_velocity) of a run of column.toml and takes the base
velocity from the input's pulse, v_b(t) = (1 - cos(20 pi t)) / (20 pi) for t < 0.1 s, else 0.
Prints the measured first resonance against Vs / (4 H) = 2.5 Hz; with --csv, writes both
transfer functions (f, measured, theory); with --plot, draws them (needs matplotlib).
"""
import argparse
import cmath
import csv
import math
import os

H, VS = 10.0, 100.0


def base_velocity(t):
    return (1.0 - math.cos(20.0 * math.pi * t)) / (20.0 * math.pi) if t < 0.1 else 0.0


def spectrum(t, x, f):
    return sum(xk * cmath.exp(-2j * math.pi * f * tk) for tk, xk in zip(t, x))


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("results")
    ap.add_argument("--csv", help="write f, measured and theoretical |H| to this CSV file")
    ap.add_argument("--plot", help="draw the transfer functions into this image (matplotlib)")
    a = ap.parse_args()
    t, top = [], []
    with open(os.path.join(a.results, "recorders.csv")) as f:
        for row in csv.DictReader(f):
            if row["top_velocity"] in ("", "nan"):
                continue
            t.append(float(row["time"]))
            top.append(float(row["top_velocity"]))
    base = [base_velocity(tk) for tk in t]
    freqs = [0.5 + 0.005 * k for k in range(1900)]  # 0.5 - 10 Hz
    ratio = [abs(spectrum(t, top, f)) / max(abs(spectrum(t, base, f)), 1e-300) for f in freqs]
    # The first resonance: the peak below 2 f1 (between the first and second modes).
    f1 = VS / (4.0 * H)
    first = max((r, f) for r, f in zip(ratio, freqs) if f < 2.0 * f1)[1]
    print(f"first resonance {first:.3f} Hz, Vs / 4H = {f1:.3f} Hz ({100.0 * (first / f1 - 1.0):+.2f} %)")
    theory = [min(1.0 / max(abs(math.cos(2.0 * math.pi * f * H / VS)), 1e-9), 1e3) for f in freqs]
    if a.csv:
        with open(a.csv, "w") as f:
            f.write("frequency_Hz,measured,theory\n")
            for fr, r, th in zip(freqs, ratio, theory):
                f.write(f"{fr:.3f},{r:.6g},{th:.6g}\n")
    if a.plot:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        plt.semilogy(freqs, theory, "k-", label="uniform undamped soil on rigid rock (Kramer 1996)")
        plt.semilogy(freqs, ratio, "r-", label="tsuchi, |V_top / V_base|")
        plt.xlabel("frequency (Hz)")
        plt.ylabel("|H(f)|")
        plt.ylim(0.3, 1e3)
        plt.legend()
        plt.savefig(a.plot, dpi=120)


if __name__ == "__main__":
    main()
