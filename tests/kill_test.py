#!/usr/bin/env python3
"""Kills at random moments (issue 6): a run killed with SIGKILL at any moment leaves only complete
files (every .vtu parses with all its data, the .pvd lists only such frames, every CSV row is whole);
restarted from its latest checkpoint after each kill, it ends bitwise identical to a run never
interrupted. SIGTERM saves the state, exits with 128 + 15, and the restart also ends identical;
so does SIGTERM sent twice 10 ms apart (issue 13; TSUCHI_TWICE_REPEATS times, default 4).

usage: kill_test.py TSUCHI_BINARY
"""
import os
import random
import re
import resource
import shutil
import signal
import struct
import subprocess
import sys
import tempfile
import time
import xml.etree.ElementTree as ET

INPUT = """
[model]
dimension = 2
gravity = [0.0, -9.81]

[grid]
extent = [0.4, 1.0]
cell_size = 0.01

[[materials]]
name = "soil"
model = "mohr_coulomb"
density = 1800.0
youngs_modulus = 2.0e6
poisson_ratio = 0.3
cohesion = 1.0e3
friction_angle = 30.0

[[bodies]]
name = "column"
material = "soil"
min = [0.1, 0.0]
max = [0.3, 0.6]
velocity = [0.3, 0.0]

[boundary]
y_min = "fixed"
x_min = "roller"
x_max = "roller"

[time]
end = 10.0
courant = 0.4
max_steps = 700

[output]
interval = 2.0e-3

[checkpoint]
every_steps = 50
every_minutes = 0.002   # also every 0.12 s of wall time: at steps that differ from run to run

[[recorders]]
name = "top_v"
min = [0.0, 0.55]
quantity = "displacement_y"
"""

failures = []


def check(cond, msg):
    if not cond:
        failures.append(msg)
        print("FAIL:", msg)


def vtu_complete(path):
    """The XML header parses, every appended block lies inside the file, and the file ends whole."""
    data = open(path, "rb").read()
    mark = b'<AppendedData encoding="raw">'
    at = data.find(mark)
    if at < 0 or not data.endswith(b"\n  </AppendedData>\n</VTKFile>\n"):
        return False
    header = data[:at].decode() + "</VTKFile>"
    try:
        root = ET.fromstring(header.replace("<AppendedData", ""))
    except ET.ParseError:
        return False
    start = data.index(b"_", at + len(mark)) + 1
    end_of_blob = len(data) - len(b"\n  </AppendedData>\n</VTKFile>\n")
    n = int(root.find(".//Piece").get("NumberOfPoints"))
    for arr in root.iter("DataArray"):
        if arr.get("format") != "appended":  # the body names, ascii in the header
            continue
        off = start + int(arr.get("offset"))
        if off + 8 > end_of_blob:
            return False
        (size,) = struct.unpack("<Q", data[off:off + 8])
        comps = int(arr.get("NumberOfComponents"))
        width = {"Float64": 8, "Int64": 8, "UInt8": 1, "Int32": 4}[arr.get("type")]
        if size != n * comps * width or off + 8 + size > end_of_blob:
            return False
    return True


def check_directory(d, when):
    """Only complete files under their final names."""
    for name in sorted(os.listdir(d)):
        path = os.path.join(d, name)
        if name.startswith("."):
            continue  # a temporary file of the killed writer, hidden and cleaned up by the next run
        if name.endswith(".vtu"):
            check(vtu_complete(path), f"{when}: {name} is incomplete")
        elif name.endswith(".csv"):
            text = open(path).read()
            rows = text.split("\n")
            check(text.endswith("\n"), f"{when}: {name} does not end with a newline")
            widths = {len(r.split(",")) for r in rows[:-1]}
            check(len(widths) == 1, f"{when}: {name} has rows of different widths {widths}")
    pvd = os.path.join(d, "particles.pvd")
    if os.path.exists(pvd):
        try:
            frames = [e.get("file") for e in ET.parse(pvd).getroot().iter("DataSet")]
        except ET.ParseError:
            check(False, f"{when}: particles.pvd does not parse")
            return
        for f in frames:
            p = os.path.join(d, f)
            check(os.path.exists(p) and vtu_complete(p), f"{when}: particles.pvd lists {f}, which is not complete")


def run(binary, inp, out, *extra, **kw):
    return subprocess.Popen([binary, "run", "-q", inp, "-o", out, *extra], stdout=subprocess.PIPE,
                            stderr=subprocess.STDOUT, text=True, **kw)


def same_files(a, b, when):
    names = sorted(n for n in os.listdir(a) if not n.startswith("."))
    check(names == sorted(n for n in os.listdir(b) if not n.startswith(".")), f"{when}: different files")
    for n in names:
        pa, pb = os.path.join(a, n), os.path.join(b, n)
        if os.path.exists(pb):
            check(open(pa, "rb").read() == open(pb, "rb").read(), f"{when}: {n} differs from the uninterrupted run")


def main():
    binary = os.path.abspath(sys.argv[1])
    tmp = tempfile.mkdtemp(prefix="tsuchi_kill_")
    try:
        inp = os.path.join(tmp, "column.toml")
        open(inp, "w").write(INPUT)
        ref = os.path.join(tmp, "ref")
        t0 = time.time()
        p = run(binary, inp, ref)
        out, _ = p.communicate()
        duration = time.time() - t0
        check(p.returncode == 0, f"reference run failed: {out}")
        print(f"uninterrupted run: {duration:.2f} s, {len(os.listdir(ref))} files")

        # SIGKILL at random moments; each time the run goes on from its latest checkpoint.
        rng = random.Random(2026)
        d = os.path.join(tmp, "killed")
        ck = os.path.join(d, "checkpoint.tsuchi")
        kills = 0
        for attempt in range(40):
            extra = ["--restart", ck] if os.path.exists(ck) else []
            p = run(binary, inp, d, *extra)
            time.sleep(rng.uniform(0.05, 0.2 * duration))
            if p.poll() is not None:  # finished before the kill
                out, _ = p.communicate()
                check(p.returncode == 0, f"run {attempt} failed: {out}")
                break
            p.send_signal(signal.SIGKILL)
            p.wait()
            kills += 1
            check_directory(d, f"after kill {kills}")
        else:
            check(False, "the killed run never finished")
        step = re.findall(r"\n[^,\n]*,(\d+),", open(os.path.join(d, "global.csv")).read())
        print(f"{kills} kills; the run finished at step {step[-1] if step else '?'}")
        check(kills >= 5, f"only {kills} kills landed: the run is too short for the test")
        check(not [n for n in os.listdir(d) if ".tmp." in n], "temporary files remain after the final run")
        same_files(ref, d, "after the kills")

        # SIGTERM saves the state; the restart ends where the uninterrupted run does.
        d = os.path.join(tmp, "terminated")
        p = run(binary, inp, d)
        time.sleep(0.4 * duration)
        p.send_signal(signal.SIGTERM)
        out, _ = p.communicate()
        check(p.returncode == 128 + signal.SIGTERM, f"SIGTERM gave exit code {p.returncode}: {out}")
        check(f"continue with tsuchi run {inp} -o {d} --restart {os.path.join(d, 'checkpoint.tsuchi')}" in out,
              f"the message does not say how to continue: {out}")
        check_directory(d, "after SIGTERM")
        p = run(binary, inp, d, "--restart", os.path.join(d, "checkpoint.tsuchi"))
        out, _ = p.communicate()
        check(p.returncode == 0, f"restart after SIGTERM failed: {out}")
        same_files(ref, d, "after SIGTERM")

        # SIGHUP (a closed terminal or SSH session) is a SIGTERM: state saved, exit 129, lock
        # released, and the restart ends identical (issue 41, defect 0). It used to end the run at
        # once with no checkpoint and a stale lock.
        d = os.path.join(tmp, "hung_up")
        p = run(binary, inp, d)
        time.sleep(0.4 * duration)
        p.send_signal(signal.SIGHUP)
        out, _ = p.communicate()
        check(p.returncode == 128 + signal.SIGHUP, f"SIGHUP gave exit code {p.returncode}: {out}")
        check(os.path.isfile(os.path.join(d, "checkpoint.tsuchi")), f"SIGHUP left no checkpoint: {out}")
        check(not os.path.exists(os.path.join(d, ".tsuchi.lock")), "SIGHUP left the lock behind")
        check_directory(d, "after SIGHUP")
        p = run(binary, inp, d, "--restart", os.path.join(d, "checkpoint.tsuchi"))
        out, _ = p.communicate()
        check(p.returncode == 0, f"restart after SIGHUP failed: {out}")
        same_files(ref, d, "after SIGHUP")

        # A closed pipe (`tsuchi run ... | head -1`): the reader goes after the first line; the run
        # writes on to the end with exit 0 and the same files, instead of dying by SIGPIPE.
        d = os.path.join(tmp, "piped")
        p = subprocess.Popen([binary, "run", inp, "-o", d], stdout=subprocess.PIPE, stderr=subprocess.PIPE)
        p.stdout.readline()
        p.stdout.close()
        p.stderr.close()
        p.wait(timeout=120)
        check(p.returncode == 0, f"a run whose output pipe was closed: exit code {p.returncode}")
        same_files(ref, d, "after the output pipe was closed")

        # SIGTERM twice, 10 ms apart (as `timeout` and batch schedulers do), at random moments: the
        # second signal must not cut the save short. Every time the exit code is 143, a complete
        # checkpoint is left, and the restart ends byte-identical to the uninterrupted run.
        d = os.path.join(tmp, "twice")
        ck = os.path.join(d, "checkpoint.tsuchi")
        repeats, interrupted = int(os.environ.get("TSUCHI_TWICE_REPEATS", "4")), 0
        for attempt in range(repeats):
            shutil.rmtree(d, ignore_errors=True)
            p = run(binary, inp, d)
            time.sleep(rng.uniform(0.05, 0.8 * duration))
            p.send_signal(signal.SIGTERM)
            time.sleep(0.01)
            p.send_signal(signal.SIGTERM)
            out, _ = p.communicate()
            if p.returncode == 0:
                continue  # ended before the signals
            interrupted += 1
            check(p.returncode == 128 + signal.SIGTERM, f"SIGTERM twice: exit code {p.returncode}: {out}")
            check(f"continue with tsuchi run {inp} -o {d} --restart {ck}" in out,
                  f"SIGTERM twice: the message does not say how to continue: {out}")
            check_directory(d, f"after SIGTERM twice ({attempt})")
            p = run(binary, inp, d, "--restart", ck)
            out, _ = p.communicate()
            check(p.returncode == 0, f"restart after SIGTERM twice failed: {out}")
            same_files(ref, d, f"after SIGTERM twice ({attempt})")
        print(f"SIGTERM twice: {interrupted} of {repeats} runs interrupted, each saved and restarted bitwise")
        check(interrupted >= repeats // 2, f"only {interrupted} of {repeats} runs were still running at the signals")

        # A full disk, played by a file-size limit that the frames fit under and the checkpoint does not.
        d = os.path.join(tmp, "full")
        limit = 150 * 4800
        p = run(binary, inp, d, "--set", 'output.fields=["displacement"]', "--set", "checkpoint.every_minutes=0",
                preexec_fn=lambda: resource.setrlimit(resource.RLIMIT_FSIZE, (limit, limit)))
        out, _ = p.communicate()
        check(p.returncode == 4, f"a full disk gave exit code {p.returncode}: {out}")
        check(re.search(r"step 50 \(t = [^)]*\): cannot write .*checkpoint.tsuchi \(\d+ bytes\): File too large", out)
              is not None, f"the message does not say what and where: {out}")
        check_directory(d, "after the write failure")
        check(os.path.exists(os.path.join(d, "particles_000001.vtu")), "the frames before the failure are gone")
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    if failures:
        print(f"{len(failures)} failures")
        sys.exit(1)
    print("ok")


if __name__ == "__main__":
    main()
