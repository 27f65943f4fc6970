#!/usr/bin/env python3
"""`tsuchi` started by mpirun (issue 42, first step): a build with MPI starts MPI only when a
launcher started the process, so a plain run is as before; under `mpirun -np 2` the step does not
yet divide the model, and the program says so once (from the first process), exits 1 on every
process, and writes nothing. `mpirun -np 1` runs as one process, with the same bits as a plain run.

usage: mpi_launch_test.py TSUCHI_BINARY MPIEXEC
"""
import filecmp
import os
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
MODEL = os.path.join(HERE, "..", "examples", "column_self_weight", "column.toml")
ENV = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1", OMP_NUM_THREADS="1")


def main():
    tsuchi, mpiexec = os.path.abspath(sys.argv[1]), sys.argv[2]
    failures = []
    with tempfile.TemporaryDirectory(prefix="tsuchi_mpi_") as tmp:
        out = os.path.join(tmp, "two")
        r = subprocess.run([mpiexec, "--oversubscribe", "-np", "2", tsuchi, "run", MODEL, "-q", "-o", out],
                           capture_output=True, text=True, timeout=120, env=ENV)
        said = r.stdout + r.stderr
        print(said.strip())
        if r.returncode != 1:
            failures.append(f"mpirun -np 2: exit {r.returncode}, expected 1")
        if said.count("not built yet") != 1 or "2 processes" not in said:
            failures.append("mpirun -np 2: expected the message once, naming 2 processes")
        if os.path.exists(out):
            failures.append("mpirun -np 2 created the output directory")

        # One process under the launcher: the same files, byte for byte, as the plain run.
        plain, one = os.path.join(tmp, "plain"), os.path.join(tmp, "one")
        common = ["run", MODEL, "-q", "--set", "time.end=0.05"]
        subprocess.run([tsuchi, *common, "-o", plain], check=True, capture_output=True, timeout=120, env=ENV)
        r = subprocess.run([mpiexec, "-np", "1", tsuchi, *common, "-o", one], capture_output=True, text=True,
                           timeout=120, env=ENV)
        if r.returncode != 0:
            failures.append(f"mpirun -np 1: exit {r.returncode}: {(r.stdout + r.stderr).strip()}")
        else:
            for name in ("global.csv", "particles.pvd", "particles_000001.vtu"):
                if not filecmp.cmp(os.path.join(plain, name), os.path.join(one, name), shallow=False):
                    failures.append(f"mpirun -np 1: {name} differs from the plain run's")
    for f in failures:
        print("FAIL:", f)
    print("passed" if not failures else "FAILED")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
