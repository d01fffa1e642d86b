#!/usr/bin/python3
"""SIGTERM inside a relaxation level on two processes (issue 47): the processes, signalled as a
scheduler signals them, stop together within the level, summary.json says "interrupted" and
mpirun reports 143. (It used to take effect after the whole level.)

usage: mpi_signals.py VELUM WORK_DIR
"""
import json
import os
import shutil
import signal
import subprocess
import sys
import time

import yaml

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "cli"))
from loop_cases import square  # noqa: E402  (the flat square under pressure)

VELUM, WORK = sys.argv[1], sys.argv[2]
shutil.rmtree(WORK, ignore_errors=True)
os.makedirs(WORK)
model = square(60, {"type": "relaxation", "time": {"end": 1, "step": 1},
                    "relaxation": {"newton_switch": 1e-6}, "linear_solver": "petsc"})
path = os.path.join(WORK, "model.yaml")
with open(path, "w") as f:
    f.write(yaml.safe_dump(model))
out = os.path.join(WORK, "out")
env = dict(os.environ, OMP_NUM_THREADS="1", OMPI_ALLOW_RUN_AS_ROOT="1",
           OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1", OMPI_MCA_rmaps_base_oversubscribe="1")
p = subprocess.Popen(["mpirun", "-np", "2", VELUM, "run", path, "-o", out, "--threads", "1"],
                     env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE)


def summary():
    try:
        return json.load(open(os.path.join(out, "summary.json")))
    except (OSError, ValueError):
        return {}


t0 = time.time()
while summary().get("status") != "running" and time.time() - t0 < 60:
    time.sleep(0.02)
time.sleep(0.5)
# The processes themselves, as a scheduler (scancel) signals them.
kids = subprocess.run(["pgrep", "-P", str(p.pid)], capture_output=True, text=True).stdout.split()
for k in kids:
    os.kill(int(k), signal.SIGTERM)
sent = time.time()
_, err = p.communicate(timeout=120)
took = time.time() - sent
s = summary()
problems = []
if p.returncode != 143:
    problems.append(f"mpirun exit {p.returncode}: {err.decode()[-400:]!r}")
if s.get("status") != "interrupted" or s.get("final_time", 1) >= 1:
    problems.append(f"summary {s.get('status')} at t = {s.get('final_time')}")
if took > 10:
    problems.append(f"ended {took:.1f} s after the signal")
print(f"ended {took:.2f} s after SIGTERM to {len(kids)} processes; status {s.get('status')}")
for pr in problems:
    print("FAIL:", pr)
sys.exit(1 if problems else 0)
