#!/usr/bin/env python3
"""Nothing lost (issue 13, items 1, 2, 4 and 13): outputs that would overwrite the input or each
other are refused before anything is written; a second run into a busy output directory stops at
once with exit 4 and the first run's process id, and the first run ends as if alone; frames of an
earlier run do not survive into a new one; global.csv is appended to, so memory and checkpoint
size do not grow with the number of rows; a restart into another directory (which it does not
create), or past its end time, is refused; a frame label that does not grow is warned of once; an
unknown command is named.

usage: output_safety_test.py TSUCHI_BINARY
"""
import os
import re
import shutil
import signal
import stat
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
cell_size = 0.05

[[materials]]
name = "soil"
model = "linear_elastic"
density = 1800.0
youngs_modulus = 2.0e6
poisson_ratio = 0.3

[[bodies]]
name = "column"
material = "soil"
min = [0.1, 0.0]
max = [0.3, 0.6]
velocity = [0.3, 0.0]

[boundary]
y_min = "fixed"

[time]
end = 100.0
max_steps = 3000

[output]
interval = 0.5
global_interval = 0.0
fields = ["displacement", "stress"]

[[recorders]]
name = "top_v"
min = [0.0, 0.55]
quantity = "velocity_y"
"""

failures = []


def check(cond, msg):
    if not cond:
        failures.append(msg)
        print("FAIL:", msg)


def run(binary, *args, wait=True, cwd=None):
    p = subprocess.Popen([binary, "run", "-q", *args], stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                         cwd=cwd)
    if not wait:
        return p
    out, _ = p.communicate(timeout=120)
    return p.returncode, out


def files(d):
    return {n: open(os.path.join(d, n), "rb").read() for n in sorted(os.listdir(d))
            if os.path.isfile(os.path.join(d, n))}


def rss_kb(pid):
    try:
        for line in open(f"/proc/{pid}/status"):
            if line.startswith("VmRSS:"):
                return int(line.split()[1])
    except OSError:
        pass
    return None


def main():
    binary = os.path.abspath(sys.argv[1])
    sanitized = b"__asan_init" in open(binary, "rb").read()
    tmp = tempfile.mkdtemp(prefix="tsuchi_output_safety_")
    try:
        inp = os.path.join(tmp, "m.toml")
        open(inp, "w").write(INPUT)

        # 1. A checkpoint path that is the input file or another output is refused before anything
        #    is written, naming the key; a nested folder is created before step 1; an unwritable one
        #    stops the run before step 1 with exit 4.
        out = os.path.join(tmp, "o1")
        for value, text in [("particles.pvd", "one of the run's output files"),
                            ("global.csv", "one of the run's output files"),
                            ("particles_000003.vtu", "one of the run's output files"),
                            (".", "that is the output directory"),
                            (inp, "is the input file")]:
            code, msg = run(binary, inp, "-o", out, "--set", f'checkpoint.file="{value}"')
            check(code == 2, f"checkpoint.file = {value!r}: exit {code}, expected 2: {msg}")
            check("key 'checkpoint.file'" in msg and text in msg and "(command-line override)" in msg,
                  f"checkpoint.file = {value!r}: message {msg!r}")
            check(not os.path.exists(out), f"checkpoint.file = {value!r}: the refused run wrote {out}")
            c = subprocess.run([binary, "check", inp, "--set", f'checkpoint.file="{value}"', "--set",
                                f'output.directory="{out}"'], stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
            check(c.returncode == 2 and text in c.stdout, f"check, checkpoint.file = {value!r}: exit {c.returncode}: {c.stdout}")
        check(open(inp).read() == INPUT, "the input file was changed")
        code, msg = run(binary, inp, "-o", out, "--set", 'checkpoint.file="sub/dir/x"', "--set", "time.max_steps=20",
                        "--set", "checkpoint.every_steps=10")
        check(code == 0 and os.path.isfile(os.path.join(out, "sub", "dir", "x")),
              f"checkpoint.file = 'sub/dir/x': exit {code}, the checkpoint is not there: {msg}")
        shutil.rmtree(out)
        code, msg = run(binary, inp, "-o", out, "--set", 'checkpoint.file="/dev/null/x"')
        check(code == 4 and "/dev/null" in msg and "checkpoint" in msg,
              f"an unwritable checkpoint folder: exit {code}, expected 4 at once: {msg}")
        check(not os.path.exists(os.path.join(out, "particles_000001.vtu")),
              "an unwritable checkpoint folder was found only after steps were taken")

        # 2. Two runs into one directory: the second stops within a second with exit 4 and the
        #    first's process id; the first ends byte-identical to a run alone.
        solo = os.path.join(tmp, "solo")
        long = ["--set", "time.max_steps=12000", "--set", "output.global_interval=0.01"]  # about a second
        code, msg = run(binary, inp, "-o", solo, *long)
        check(code == 0, f"solo run: exit {code}: {msg}")
        shared = os.path.join(tmp, "shared")
        first = run(binary, inp, "-o", shared, *long, wait=False)
        lock = os.path.join(shared, ".tsuchi.lock")
        deadline = time.time() + 10
        while not (os.path.exists(lock) and open(lock).read().strip()) and time.time() < deadline:
            time.sleep(0.005)
        check(first.poll() is None, "the first run ended before the second started: make it longer")
        t0 = time.time()
        code, msg = run(binary, inp, "-o", shared, *long)
        took = time.time() - t0
        out1, _ = first.communicate(timeout=120)
        print(f"second run into a busy directory: exit {code} after {took:.3f} s")
        check(code == 4 and took < 1.0 and f"process id {first.pid}" in msg,
              f"the second run: exit {code} after {took:.2f} s: {msg}")
        check(first.returncode == 0, f"the first run: exit {first.returncode}: {out1}")
        a, b = files(solo), files(shared)
        check(sorted(a) == sorted(b), f"files differ: {sorted(a)} vs {sorted(b)}")
        check(all(a[n] == b.get(n) for n in a), "the first run's output differs from the solo run")
        check(not os.path.exists(lock), "the lock file outlives the run")

        # A lock left by a dead process is taken over.
        open(lock, "w").write("999999999\n")
        code, msg = run(binary, inp, "-o", shared, "--set", "time.max_steps=10")
        check(code == 0, f"a stale lock stopped the run: exit {code}: {msg}")

        # Frames of an earlier run are removed: 7 frames, then a run of 3 frames leaves 3.
        d = os.path.join(tmp, "rerun")
        run(binary, inp, "-o", d)
        before = sorted(n for n in os.listdir(d) if n.endswith(".vtu"))
        code, msg = run(binary, inp, "-o", d, "--set", "time.max_steps=250", "--set", "output.interval=1.0",
                        "--set", "output.frames=true")
        after = sorted(n for n in os.listdir(d) if n.endswith(".vtu"))
        listed = [e.get("file") for e in ET.parse(os.path.join(d, "particles.pvd")).getroot().iter("DataSet")]
        check(len(before) > len(after) and after == listed,
              f"stale frames: {len(before)} frames, then {after} on disk and {listed} in the .pvd")
        code, msg = run(binary, inp, "-o", d, "--set", "time.max_steps=250", "--set", "output.frames=false",
                        "--set", "recorders.0.name=\"w\"")
        check(not [n for n in os.listdir(d) if n.endswith(".vtu") or n.endswith(".pvd")],
              f"a run without frames left the earlier run's frames: {sorted(os.listdir(d))}")

        # 4. global.csv is appended to: a checkpoint after 20,000 rows is as large as one after
        #    2,000, and the resident memory does not grow with the rows.
        sizes = []
        for steps in (2000, 20000):
            d = os.path.join(tmp, f"rows{steps}")
            p = run(binary, inp, "-o", d, "--set", f"time.max_steps={steps}", "--set", "checkpoint.every_steps=1000",
                    "--set", "output.frames=false", wait=False)
            samples = []
            while p.poll() is None:
                r = rss_kb(p.pid)
                rows = 0
                try:
                    rows = os.path.getsize(os.path.join(d, "global.csv")) // 150
                except OSError:
                    pass
                if r and rows >= 1000:
                    samples.append(r)
                time.sleep(0.02)
            out, _ = p.communicate()
            check(p.returncode == 0, f"{steps} steps: exit {p.returncode}: {out}")
            sizes.append(os.path.getsize(os.path.join(d, "checkpoint.tsuchi")))
            rows = open(os.path.join(d, "global.csv")).read().count("\n")
            check(rows == steps + 2, f"{steps} steps: global.csv has {rows} lines, expected {steps + 2}")
            if steps == 20000 and sanitized:
                print("sanitized binary: resident memory not compared (AddressSanitizer keeps freed memory)")
            elif steps == 20000 and len(samples) >= 3:
                print(f"resident memory: {samples[0]} kB after ~1000 rows, {samples[-1]} kB at the end")
                check(samples[-1] <= 1.1 * samples[0], f"resident memory grew from {samples[0]} to {samples[-1]} kB")
        print(f"checkpoint sizes after 2,000 and 20,000 rows: {sizes}")
        check(sizes[0] == sizes[1], f"the checkpoint grows with the rows: {sizes}")

        # Issue 41, defect 0. Every file the input reads is guarded, and only regular files are
        # replaced. (a) A checkpoint that would overwrite a function's CSV or a body's particle file.
        rec = os.path.join(tmp, "record.csv")
        open(rec, "w").write("time,g\n0.0,1.0\n1000.0,1.0\n")
        fn_input = inp + ".fn.toml"
        open(fn_input, "w").write(INPUT.replace("[model]", '[[functions]]\nname = "ramp"\nfile = "record.csv"\n\n[model]')
                                  .replace("gravity = [0.0, -9.81]", 'gravity = [0.0, -9.81]\ngravity_function = "ramp"'))
        out = os.path.join(tmp, "o41")
        code, msg = run(binary, fn_input, "-o", out, "--set", "time.max_steps=5")
        check(code == 0, f"the input with a record function does not run: exit {code}: {msg}")
        shutil.rmtree(out, ignore_errors=True)
        code, msg = run(binary, fn_input, "-o", out, "--set", f'checkpoint.file="{rec}"')
        check(code == 2 and "key 'checkpoint.file'" in msg and "functions.0" in msg,
              f"checkpoint.file = the function's CSV: exit {code}: {msg}")
        check(open(rec).read() == "time,g\n0.0,1.0\n1000.0,1.0\n", "the function's CSV was changed")
        check(not os.path.exists(out), "the refused run wrote its output directory")
        # (b) A checkpoint or an element test's CSV that names a named pipe (as a device would):
        #     the rename would have replaced it by a regular file.
        fifo = os.path.join(tmp, "pipe")
        os.mkfifo(fifo)
        code, msg = run(binary, inp, "-o", out, "--set", f'checkpoint.file="{fifo}"')
        check(code == 2 and "key 'checkpoint.file'" in msg and "named pipe" in msg,
              f"checkpoint.file = a named pipe: exit {code}: {msg}")
        element = os.path.join(tmp, "element.toml")
        open(element, "w").write('[[materials]]\nname = "soil"\nmodel = "linear_elastic"\ndensity = 2000.0\n'
                                 'youngs_modulus = 1.0e7\npoisson_ratio = 0.3\n\n[test]\ntype = "triaxial_compression"\n'
                                 'confining_pressure = 1.0e5\naxial_strain = 0.01\nincrements = 10\n')
        e = subprocess.run([binary, "element", element, "-q", "-o", fifo], stdout=subprocess.PIPE,
                           stderr=subprocess.STDOUT, text=True, timeout=60)
        check(e.returncode == 4 and "named pipe" in e.stdout, f"element -o a named pipe: exit {e.returncode}: {e.stdout}")
        check(stat.S_ISFIFO(os.stat(fifo).st_mode), "the named pipe was replaced")
        # (c) A body read from a frame of an earlier run into the same directory: the start-up
        #     clean-up of that run's frames would delete the body's own input.
        old = os.path.join(tmp, "old")
        code, msg = run(binary, inp, "-o", old, "--set", "time.max_steps=20", "--set", "output.interval=1.0e-3",
                        "--set", 'output.fields=["volume", "stress", "velocity"]')
        frame = sorted(n for n in os.listdir(old) if n.endswith(".vtu"))[-1]
        reuse = inp + ".reuse.toml"
        open(reuse, "w").write(INPUT.replace('min = [0.1, 0.0]\nmax = [0.3, 0.6]', f'particles = "old/{frame}"'))
        code, msg = run(binary, reuse, "-o", old, "--set", "time.max_steps=20")
        check(code == 2 and "key 'bodies.0.particles'" in msg and "output" in msg,
              f"a body read from a frame in the output directory: exit {code}: {msg}")
        check(os.path.isfile(os.path.join(old, frame)), "the body's particle file was deleted")
        code, msg = run(binary, reuse, "-o", os.path.join(tmp, "new"), "--set", "time.max_steps=20")
        check(code == 0, f"the same body into another directory: exit {code}: {msg}")
        # (d) An empty -o (an unset shell variable) is refused, not taken as output.directory.
        for sub in (["run", inp], ["fos", inp], ["element", element]):
            r = subprocess.run([binary, *sub, "-o", ""], stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                               text=True, cwd=tmp, timeout=60)
            check(r.returncode == 1 and "empty" in r.stdout, f"{sub[0]} -o '': exit {r.returncode}: {r.stdout}")
        r = subprocess.run([binary, "run", inp, "--restart", ""], stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                           text=True, cwd=tmp, timeout=60)
        check(r.returncode == 1 and "empty" in r.stdout, f"run --restart '': exit {r.returncode}: {r.stdout}")

        # 13. A restart into another directory, or whose end time has passed, is refused.
        d = os.path.join(tmp, "split")
        run(binary, inp, "-o", d, "--set", "time.max_steps=100", "--set", "checkpoint.every_steps=100")
        ck = os.path.join(d, "checkpoint.tsuchi")
        other = os.path.join(tmp, "elsewhere")
        code, msg = run(binary, inp, "-o", other, "--restart", ck)
        check(code == 2 and "restart into the output directory of the checkpointed run" in msg,
              f"a restart into another directory: exit {code}: {msg}")
        check(not os.path.exists(other), "a refused restart created its output directory")
        snapshot = files(d)
        code, msg = run(binary, inp, "-o", d, "--restart", ck, "--set", "time.end=0.01")
        check(code == 2 and "past time.end = 0.01 s" in msg, f"a restart past its end: exit {code}: {msg}")
        check(files(d) == snapshot, "a refused restart changed the output directory")

        # 14. Frames labelled by a recorder that does not grow (the column's top falls: velocity_y
        #     goes negative): said once, with the frame and both labels; the frames are written.
        fl = os.path.join(tmp, "falling_label")
        code, msg = run(binary, inp, "-o", fl, "--set", 'output.frame_label="top_v"', "--set", "time.max_steps=400",
                        "--set", "output.interval=0.002")
        check(code == 0 and msg.count("(output.frame_label), not above") == 1 and 'recorder "top_v"' in msg,
              f"a frame label that falls: exit {code}, expected one warning: {msg}")
        grows = os.path.join(tmp, "time_label")
        code, msg = run(binary, inp, "-o", grows, "--set", "time.max_steps=400", "--set", "output.interval=0.002")
        check(code == 0 and "frame_label" not in msg, f"frames labelled by time: exit {code}: {msg}")

        # 15. A command that does not exist is named, with the commands there are (not CLI11's
        #     "A subcommand is required").
        for args, text in [(["frobnicate", inp], "unknown command 'frobnicate'"), (["--bogus"], "unknown option '--bogus'"),
                           ([], "expected a command")]:
            r = subprocess.run([binary, *args], stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, timeout=60)
            check(r.returncode == 1 and text in r.stdout and "run, check, fos, element" in r.stdout,
                  f"tsuchi {' '.join(args)}: exit {r.returncode}: {r.stdout}")
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    if failures:
        print(f"{len(failures)} failures")
        sys.exit(1)
    print("ok")


if __name__ == "__main__":
    main()
