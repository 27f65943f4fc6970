"""What the Python tests of the triaxial case share: the paths, the tsuchi binary named on the
command line, the plane-strain Mohr-Coulomb peak, and a run of an example into a temporary folder."""
import math
import os
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.normpath(os.path.join(HERE, ".."))
sys.path.insert(0, os.path.join(REPO, "tools"))


def tsuchi_from_argv():
    """The first argument (taken out of sys.argv, which unittest reads), or the default build."""
    return sys.argv.pop(1) if len(sys.argv) > 1 else os.path.join(REPO, "build", "app", "tsuchi")


def mohr_coulomb_peak(p_kpa, c_kpa=8.5, phi_deg=30.5):
    """q = p (N - 1) + 2 c sqrt(N), N = (1 + sin phi) / (1 - sin phi): kPa, the paper's soil."""
    s = math.sin(math.radians(phi_deg))
    n = (1 + s) / (1 - s)
    return p_kpa * (n - 1) + 2 * c_kpa * math.sqrt(n)


def run_example(tsuchi, example, prefix, overrides=()):
    """Runs examples/triaxial/EXAMPLE.toml quietly with the --set overrides into a new temporary
    folder; returns the folder and the completed process."""
    out = tempfile.mkdtemp(prefix=prefix)
    cmd = [tsuchi, "run", os.path.join(REPO, "examples", "triaxial", f"{example}.toml"), "-q", "--output", out]
    for o in overrides:
        cmd += ["--set", o]
    return out, subprocess.run(cmd, capture_output=True, text=True)
