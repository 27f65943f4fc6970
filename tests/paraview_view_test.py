#!/usr/bin/env python3
"""What a ParaView user opens (issue 41): every frame carries its fields' units and the sign
convention as field data ('units', 'conventions'), with the units of the model's dimension; a run
writes particles_view.py beside particles.pvd, a Python state naming no absolute path (a restart
or a copied directory gives the same file). Where ParaView's pvpython is installed (with xvfb-run
for a display), the script is run: it must open the last frame, as Point Gaussian discs scaled by
'radius', coloured by max_shear_strain over the range of every frame, not of the first.

usage: paraview_view_test.py TSUCHI_BINARY
"""
import os
import re
import shutil
import subprocess
import sys
import tempfile

INPUT = """
[model]
dimension = 2
gravity = [0.0, -9.81]

[grid]
extent = [0.2, 0.6]
cell_size = 0.05

[[materials]]
name = "soil"
model = "linear_elastic"
density = 2000.0
youngs_modulus = 1.0e6
poisson_ratio = 0.3

[[bodies]]
name = "column"
material = "soil"
min = [0.0, 0.0]
max = [0.2, 0.5]

[boundary]
x_min = "roller"
x_max = "roller"
y_min = "fixed"

[time]
end = 0.2
courant = 0.5

[output]
interval = 0.05
"""

failures = []


def check(cond, what, detail=""):
    if not cond:
        failures.append(what + ("\n--- " + detail if detail else ""))


def strings(vtu, name):
    """The strings of a FieldData String array (character codes, each string ended by 0)."""
    m = re.search(r'Name="%s" NumberOfTuples="(\d+)" format="ascii">\s*([\d ]*)\s*</DataArray>' % name, vtu)
    if not m:
        return None
    out, cur = [], []
    for code in m.group(2).split():
        if code == "0":
            out.append(bytes(cur).decode())
            cur = []
        else:
            cur.append(int(code))
    return out if len(out) == int(m.group(1)) else None


def main():
    tsuchi = os.path.abspath(sys.argv[1])
    with tempfile.TemporaryDirectory(prefix="tsuchi_paraview_") as tmp:
        with open(os.path.join(tmp, "column.toml"), "w") as f:
            f.write(INPUT)
        r = subprocess.run([tsuchi, "run", "-q", "column.toml", "-o", "out"], cwd=tmp, capture_output=True,
                           text=True, timeout=120)
        check(r.returncode == 0, f"the run: exit {r.returncode}", r.stdout + r.stderr)
        out = os.path.join(tmp, "out")
        with open(os.path.join(out, "particles_000004.vtu"), "rb") as f:
            vtu = f.read().split(b"<AppendedData")[0].decode()
        units = strings(vtu, "units")
        check(units is not None, "the frame has a 'units' field data array", vtu[:2000])
        units = units or []
        check("stress [Pa]: Cauchy stress, tension positive" in units, "stress in Pa, tension positive", str(units))
        check("volume [m^2]: volume" in units, "a 2D volume in m^2", str(units))
        check("velocity [m/s]: velocity" in units, "velocity in m/s", str(units))
        point_data = vtu[vtu.index("<PointData"):vtu.index("</PointData>")]
        names = re.findall(r'<DataArray type="\w+" Name="(\w+)" NumberOfComponents', point_data)
        check(len(units) == len(names) and all(u.startswith(n + " [") for u, n in zip(units, names)),
              "one unit per point field, in their order", f"{names} / {units}")
        conv = strings(vtu, "conventions") or []
        check(any("compression is negative" in c and "-10000 Pa" in c for c in conv), "the sign convention stated",
              str(conv))
        check(strings(vtu, "body_names") == ["column"], "the body names kept", vtu[:1500])

        view = os.path.join(out, "particles_view.py")
        check(os.path.exists(view), "particles_view.py written beside particles.pvd", str(os.listdir(out)))
        if not os.path.exists(view):
            return report()
        with open(view) as f:
            script = f.read()
        check(tmp not in script, "the script names no absolute path of the run")
        compiled = subprocess.run([sys.executable, "-m", "py_compile", view], capture_output=True, text=True)
        check(compiled.returncode == 0, "the script is valid Python", compiled.stderr)

        pvpython, xvfb = shutil.which("pvpython"), shutil.which("xvfb-run")
        if not (pvpython and xvfb):
            print("note: pvpython or xvfb-run not installed: the script was not run in ParaView")
            return report()
        probe = os.path.join(tmp, "probe.py")
        with open(probe, "w") as f:
            f.write(
                "import os\n"
                "path = %r\n"
                "exec(compile(open(path).read(), path, 'exec'), {'__file__': path, '__name__': '__main__'})\n"
                "from paraview.simple import *\n"
                "view = GetActiveView()\n"
                "d = GetDisplayProperties(FindSource('particles.pvd'), view)\n"
                "lut = GetColorTransferFunction('max_shear_strain')\n"
                "print('STATE', GetAnimationScene().AnimationTime, lut.RGBPoints[0], lut.RGBPoints[-4],\n"
                "      d.Representation, list(d.SetScaleArray))\n" % view)
        # From another directory: the script finds its frames by its own place, not the working one.
        # Twice at most: on a loaded machine the virtual X server may not be up in xvfb-run's time.
        for attempt in range(2):
            r = subprocess.run([xvfb, "-a", pvpython, probe], cwd=tmp, capture_output=True, text=True, timeout=300)
            m = re.search(r"STATE (\S+) (\S+) (\S+) (.+)", r.stdout)
            if m:
                break
            print(f"note: attempt {attempt + 1}: pvpython exit {r.returncode}: {r.stderr[-500:]}")
        check(m is not None, f"pvpython ran the script (exit {r.returncode})", r.stdout[-2000:] + r.stderr[-2000:])
        if m:
            time, lo, hi, rest = float(m.group(1)), float(m.group(2)), float(m.group(3)), m.group(4)
            check(abs(time - 0.2) < 1e-9, f"opens at the last frame (t = {time})")
            check("Point Gaussian" in rest and "radius" in rest, "Point Gaussian scaled by radius", rest)
            # max_shear_strain is 0 in the first frame: its range there is 0 to 0 (ParaView showed
            # 0 to 1.2e-38); over every frame it is the settled column's.
            check(lo == 0.0 and hi > 1e-4, f"the colour range of every frame ({lo} to {hi})")
    return report()


def report():
    for f in failures:
        print("FAIL:", f)
    print(f"{'FAILED' if failures else 'passed'}: ParaView view")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
