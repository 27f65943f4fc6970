#!/usr/bin/env python3
"""Limits a batch job meets (issue 41, defect 10): a model larger than the process's address-space
limit (`ulimit -v`) is refused before it allocates, naming that limit (it ran to "internal error:
std::bad_alloc"); a thread count above the CPUs the process may use is held to them with a warning
(--threads 1024 died in libgomp or ran 1000x slower); a run whose thread waits for its CPU, shared
with another busy process, says so once and suggests fewer threads; the frames' size is said in the
summary, and warned of when it exceeds the space free where they go.

usage: machine_limits_test.py TSUCHI_BINARY
"""
import os
import re
import signal
import subprocess
import sys
import tempfile
import time

MODEL = """
[model]
dimension = 2
gravity = [0.0, -9.81]

[grid]
extent = [{size}, {size}]
cell_size = 0.05

[[materials]]
name = "soil"
model = "linear_elastic"
density = 2000.0
youngs_modulus = 1.0e7
poisson_ratio = 0.3

[[bodies]]
name = "block"
material = "soil"
min = [0.0, 0.0]
max = [{size}, {half}]
particles_per_cell = 2

[boundary]
y_min = "fixed"
x_min = "roller"
x_max = "roller"

[time]
end = {end}
courant = 0.5

[output]
interval = 0.0
global_interval = 0.0
"""

failures = []


def check(cond, what, output=""):
    if not cond:
        failures.append(what + ("\n--- output:\n" + output if output else ""))


def shell(cmd, cwd):
    r = subprocess.run(["/bin/sh", "-c", cmd], cwd=cwd, capture_output=True, text=True, timeout=120)
    return r.returncode, r.stdout + r.stderr


def main():
    tsuchi = os.path.abspath(sys.argv[1])
    with tempfile.TemporaryDirectory(prefix="tsuchi_limits_") as tmp:
        # 1. 8e6 particles (an estimate of 3.4 GB) under a 1.5 GB address-space limit: an input
        #    error naming the limit, and nothing written.
        #    AddressSanitizer maps about 15 TB of shadow memory before main and aborts under any
        #    `ulimit -v`, so a sanitized build (scripts/sanitize.sh) leaves this case out.
        with open(os.path.join(tmp, "big.toml"), "w") as f:
            f.write(MODEL.format(size=100.0, half=50.0, end=0.01))
        if os.environ.get("TSUCHI_SANITIZED") == "1":
            print("skipped under the sanitizers: a model above ulimit -v")
        else:
            code, out = shell(f"ulimit -v 1500000 && '{tsuchi}' run -q big.toml -o out", tmp)
            check(code == 2, f"a model above ulimit -v: exit {code}, expected 2", out)
            check("more than the" in out and "address-space limit of this process (ulimit -v = 1.54 GB" in out,
                  "the message names the address-space limit", out)
            check(not os.path.exists(os.path.join(tmp, "out")), "a refused model wrote its output directory")

        # 2. --threads above the usable CPUs: held to them, with a warning; the run goes on.
        cpus = len(os.sched_getaffinity(0))
        with open(os.path.join(tmp, "small.toml"), "w") as f:
            f.write(MODEL.format(size=0.4, half=0.2, end=0.001))
        env = dict(os.environ)
        env.pop("OMP_NUM_THREADS", None)
        r = subprocess.run([tsuchi, "run", "small.toml", "-o", "out2", "--threads", "1024"], cwd=tmp,
                           capture_output=True, text=True, timeout=120, env=env)
        out = r.stdout + r.stderr
        check(r.returncode == 0, f"--threads 1024: exit {r.returncode}", out)
        check(f"--threads 1024 asks for more threads than the {cpus} CPUs" in out, "--threads 1024 warned of", out)
        m = re.search(r"^threads\s+(\d+)$", r.stdout, re.M)
        check(m is not None and int(m.group(1)) == cpus, f"the summary's thread count is the {cpus} CPUs", out)
        env["OMP_NUM_THREADS"] = "5000"
        r = subprocess.run([tsuchi, "check", "small.toml"], cwd=tmp, capture_output=True, text=True, timeout=120,
                           env=env)
        out = r.stdout + r.stderr
        check(r.returncode == 0 and "OMP_NUM_THREADS=5000 asks for more threads" in out,
              "OMP_NUM_THREADS=5000 held to the CPUs with a warning", out)

        # 3. One thread on CPU 0 beside a busy loop on CPU 0: it waits for its CPU about half the
        #    time, and says so once (judged over 3 s windows after the first).
        env = dict(os.environ, OMP_NUM_THREADS="1")
        busy = subprocess.Popen(["taskset", "-c", "0", "/bin/sh", "-c", "while :; do :; done"])
        try:
            run = subprocess.Popen(["taskset", "-c", "0", tsuchi, "run", "-q", "small.toml", "-o", "out3",
                                    "--set", "time.end=1000", "--set", "time.max_steps=100000000"],
                                   cwd=tmp, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, env=env)
            time.sleep(10.0)  # windows end at 3, 6 and 9 s; the first only sets the base
            run.send_signal(signal.SIGTERM)  # a checkpoint, then exit 143
            out = run.communicate(timeout=60)[0]
        finally:
            busy.kill()
            busy.wait()
        waits = re.findall(r"warning: this run's 1 thread waited for a CPU (\d+) % of the time", out)
        check(len(waits) == 1, f"the busy machine warned of once, got {len(waits)}", out)
        check(all(30 <= int(w) <= 70 for w in waits), "the wait is about half the time (30..70 %)", out)

        # 4. Frames that would fill the disk: 2e6 particles of ~257 B in 90,001 frames, ~46 TB, said
        #    against the space free where they go; the run is not refused (a recorder may stop it).
        with open(os.path.join(tmp, "frames.toml"), "w") as f:
            f.write(MODEL.format(size=10.0, half=5.0, end=9.0).replace("cell_size = 0.05", "cell_size = 0.01")
                    .replace("interval = 0.0\n", "interval = 1e-4\n", 1) + "\n")
        code, out = shell(f"'{tsuchi}' check frames.toml --set time.max_steps=100000", tmp)
        check(code == 0, f"check of a model whose frames fill the disk: exit {code}, expected 0", out)
        m = re.search(r"warning: the frames would take about ([\d.]+) TB, more than the ([\d.]+ [kMGT]?B) free", out)
        check(m is not None and 40.0 < float(m.group(1)) < 60.0, "the frames' size (~46 TB) against the free space", out)

        # 5. The frame size said in the summary is that of the frames written, within 2 %.
        code, out = shell(f"'{tsuchi}' run small.toml -o out5 --set output.interval=0.0005", tmp)
        m = re.search(r"frames of about ([\d.]+) kB", out)
        written = os.path.getsize(os.path.join(tmp, "out5", "particles_000001.vtu"))
        check(code == 0 and m is not None and abs(float(m.group(1)) * 1e3 / written - 1.0) < 0.02,
              f"the frame size said ({m.group(1) if m else '?'} kB) is the written one ({written} B)", out)

    for f in failures:
        print("FAIL:", f)
    print(f"{'FAILED' if failures else 'passed'}: machine limits")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
