"""`velum` starts without PETSc's libraries and hands the runs that need them to `velum-mpi`
beside it (docs/parallel.md, "Two executables"): velum links no libpetsc and no libmpi; a
model with `linear_solver: petsc` run by velum is solved through PETSc all the same, with the
run's first lines printed once and the same answers as velum-mpi run directly."""
import csv
import os
import subprocess
import sys

VELUM, MODEL, WORK = sys.argv[1:4]
WITH_PETSC = os.path.join(os.path.dirname(VELUM), "velum-mpi")
failures = []


def check(ok, what):
    print(("ok:   " if ok else "FAIL: ") + what)
    if not ok:
        failures.append(what)


if not os.path.exists(WITH_PETSC):
    print("no velum-mpi in this build (no PETSc): nothing to check")
    sys.exit(0)

linked = subprocess.run(["ldd", VELUM], capture_output=True, text=True).stdout
check("libpetsc" not in linked and "libmpi" not in linked, "velum links neither libpetsc nor libmpi")
check("libpetsc" in subprocess.run(["ldd", WITH_PETSC], capture_output=True, text=True).stdout,
      "velum-mpi links libpetsc")

os.makedirs(WORK, exist_ok=True)
text = open(MODEL).read().replace("analysis:\n", "analysis:\n  linear_solver: petsc\n", 1)
text = text.replace("end: 0.1,", "end: 0.01,")
path = os.path.join(WORK, "petsc.yaml")
with open(path, "w") as f:
    f.write(text)
runs = {}
for name, exe in (("velum", VELUM), ("velum-mpi", WITH_PETSC)):
    out = os.path.join(WORK, name)
    p = subprocess.run([exe, "run", path, "-o", out, "--threads", "1"], capture_output=True,
                       text=True, timeout=120, cwd=os.path.dirname(MODEL))
    check(p.returncode == 0, f"{name}: exit {p.returncode} {p.stderr.strip()[-300:]}")
    check(p.stderr.count(" run: ") == 1, f"{name}: the run's first line printed once")
    summary = open(os.path.join(out, "summary.json")).read() if p.returncode == 0 else ""
    check('"petsc' in summary, f"{name}: solved through PETSc (summary.json's linear_solver)")
    runs[name] = open(os.path.join(out, "history.csv")).read() if p.returncode == 0 else None
check(runs["velum"] is not None and runs["velum"] == runs["velum-mpi"],
      "velum and velum-mpi write the same history, byte for byte")
sys.exit(1 if failures else 0)
