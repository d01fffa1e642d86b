#!/usr/bin/env python3
"""A run on two processes stopped at a checkpoint and continued with --restart (issue 18).

Usage: mpi_restart.py VELUM OUTDIR

The dynamic model of mpi_cases.py (a quarter membrane on two symmetry planes, a payload with
drag on three cables; the partition's boundary through a cable and the planes) on two
processes: once through to its end, once to half its end (an output time; checkpoints every 3
steps and at the end) and then continued from that folder with `--restart` on two processes.
The continued history must be the uninterrupted two-process run's and the one-process run's
within 1e-8 of each column's largest value, and its frames, the ones written before the stop
and after the restart, valid pieces (per frame a .pvtu naming two pieces that hold every cell
once and every node) with the one-process frame's values (mpi_cases.frame_errors).
"""
import os
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import mpi_cases  # noqa: E402


def main():
    velum, out = sys.argv[1], sys.argv[2]
    env = mpi_cases.fresh(out)
    text = mpi_cases.model("dynamic", "petsc").replace("output:\n",
                                                      "output:\n  checkpoint: {steps: 3}\n", 1)
    if "end: 0.04," not in text:
        sys.exit("FAIL: the dynamic model's end time is not 0.04")
    full, half = os.path.join(out, "full.yaml"), os.path.join(out, "half.yaml")
    with open(full, "w") as f:
        f.write(text)
    with open(half, "w") as f:
        f.write(text.replace("end: 0.04,", "end: 0.02,", 1))
    one, whole, cont = (os.path.join(out, d) for d in ("one", "whole", "restarted"))
    mpirun = ["mpirun", "-np", "2", "--oversubscribe", "--bind-to", "none", velum, "run"]
    mpi_cases.run([velum, "run", full, "-o", one, "-q", "--threads", "1"], env)
    mpi_cases.run(mpirun + [full, "-o", whole, "-q", "--threads", "1"], env)
    mpi_cases.run(mpirun + [half, "-o", cont, "-q", "--threads", "1"], env)
    stopped = mpi_cases.history(os.path.join(cont, "history.csv"))
    mpi_cases.run(mpirun + [full, "--restart", cont, "-q", "--threads", "1"], env)
    errors = []
    got = mpi_cases.history(os.path.join(cont, "history.csv"))
    ref = mpi_cases.history(os.path.join(whole, "history.csv"))
    if not len(stopped[1]) < len(got[1]):
        errors.append(f"the restart added no rows ({len(stopped[1])} before, {len(got[1])} after)")
    if abs(got[1][-1][0] - 0.04) > 1e-12:
        errors.append(f"the restarted run ends at t = {got[1][-1][0]}, not 0.04")
    errors += mpi_cases.compare(ref, got, "restarted vs uninterrupted, 2 processes")
    errors += mpi_cases.compare(mpi_cases.history(os.path.join(one, "history.csv")), got,
                                "restarted on 2 processes vs one process")
    errors += mpi_cases.frame_errors(one, cont, 2)
    # A one-process checkpoint restarted on two processes would name frames (.pvtu) that do not
    # exist: refused, exit 1, nothing changed (issue 47).
    before = open(os.path.join(one, "history.csv"), "rb").read()
    p = subprocess.run(mpirun + [full, "--restart", one, "-q", "--threads", "1"], env=env,
                       capture_output=True, text=True, timeout=300)
    if p.returncode != 1 or "written by a run on 1 process, this one has 2" not in p.stderr:
        errors.append(f"one-process checkpoint on 2 processes: exit {p.returncode}: {p.stderr}")
    if open(os.path.join(one, "history.csv"), "rb").read() != before:
        errors.append("one-process checkpoint on 2 processes: history.csv changed")
    if errors:
        sys.exit("FAIL:\n" + "\n".join(errors))
    print(f"ok: restart on 2 processes: {len(got[1])} history rows ({len(stopped[1])} before the "
          f"stop) agree with the uninterrupted run within 1e-8; "
          f"{len(mpi_cases.series(cont))} frames of valid pieces")


if __name__ == "__main__":
    main()
