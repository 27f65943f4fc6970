#!/usr/bin/python3
"""Runs one bad input file through `tsuchi run` and checks that it is refused as its header says.

Usage: run_case.py TSUCHI CASE.toml

The expectation is written in comment lines at the top of CASE.toml, or, for a file that cannot
carry a comment (an empty or binary file), in CASE.expect beside it; both are read when present:

    # expect-exit: 2              exit code (default 2, an input error)
    # expect: bodies.0.material   a text the program's output must contain (one or more lines)
    # no-output-override          run without `-o`, so that output.directory of the file is used
    # args: --set time.end=-1     extra arguments after the file (split as a shell would)

The program runs in a fresh empty directory as `tsuchi run CASE -q -o DIR/out`. Besides the exit
code and the texts, the output must hold no raw control character (only line breaks and tabs), the output of an input error (exit 2) must name the case file, and the
directory must still be empty afterwards: a refused input writes nothing, not even the output
directory. On failure the whole program output is printed.
"""
import os
import shlex
import subprocess
import sys
import tempfile


def read_expectation(case):
    lines = []
    with open(case, "rb") as f:
        for raw in f.read().decode("utf-8", errors="replace").splitlines():
            if not raw.startswith("#"):
                break
            lines.append(raw)
    sidecar = os.path.splitext(case)[0] + ".expect"
    if os.path.exists(sidecar):
        with open(sidecar, encoding="utf-8") as f:
            lines += [l for l in f.read().splitlines() if l.startswith("#")]
    exp = {"exit": 2, "texts": [], "override": True, "args": []}
    for line in lines:
        body = line[1:].strip()
        key, _, value = body.partition(":")
        key, value = key.strip(), value.strip()
        if key == "expect-exit":
            exp["exit"] = int(value)
        elif key == "expect":
            exp["texts"].append(value)
        elif key == "args":
            exp["args"] += shlex.split(value)
        elif body == "no-output-override":
            exp["override"] = False
    return exp


def main():
    if len(sys.argv) != 3:
        print(__doc__, file=sys.stderr)
        return 2
    tsuchi, case = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])
    exp = read_expectation(case)
    problems = []
    if not exp["texts"]:
        problems.append("the case states no '# expect:' text")
    with tempfile.TemporaryDirectory(prefix="tsuchi_bad_input_") as tmp:
        cmd = [tsuchi, "run", case, "-q"]
        if exp["override"]:
            cmd += ["-o", os.path.join(tmp, "out")]
        cmd += exp["args"]
        env = dict(os.environ, OMP_NUM_THREADS=os.environ.get("OMP_NUM_THREADS", "1"))
        try:
            r = subprocess.run(cmd, cwd=tmp, env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                               timeout=120)
            output = r.stdout.decode("utf-8", errors="replace")
            code = r.returncode
        except subprocess.TimeoutExpired as e:
            output = (e.stdout or b"").decode("utf-8", errors="replace")
            code = None
            problems.append("the program did not end within 120 s")
        if code is not None and code != exp["exit"]:
            problems.append(f"exit code {code}, expected {exp['exit']}")
        # An input error names the input file; an output error names the path it could not write.
        name = [os.path.basename(case)] if exp["exit"] == 2 else []
        for text in name + exp["texts"]:
            if text not in output:
                problems.append(f"the output does not contain {text!r}")
        # No message passes a file's control characters to the terminal (issue 41): ESC, BEL, NUL...
        raw = sorted({f"0x{ord(ch):02x}" for ch in output if (ord(ch) < 0x20 and ch not in "\n\t") or ord(ch) == 0x7f})
        if raw:
            problems.append("the output holds raw control characters " + ", ".join(raw))
        left = sorted(os.path.relpath(os.path.join(d, n), tmp)
                      for d, dirs, files in os.walk(tmp) for n in dirs + files)
        if left:
            problems.append("the refused run left files behind: " + ", ".join(left))
    if problems:
        print(f"FAIL {os.path.basename(case)}")
        print("command: " + " ".join(shlex.quote(c) for c in cmd))
        for p in problems:
            print("  - " + p)
        print("---- program output ----")
        print(output, end="" if output.endswith("\n") else "\n")
        print("------------------------")
        return 1
    print(f"ok {os.path.basename(case)} (exit {code})")
    return 0


if __name__ == "__main__":
    sys.exit(main())
