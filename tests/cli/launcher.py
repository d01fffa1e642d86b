#!/usr/bin/python3
"""The `velum` launcher (app/launcher.cpp): it executes velum-engine beside it with the same
arguments, with glibc's huge-page tunable set where the kernel honours the advice
(kept as the user gave it, left out under VELUM_HUGE_PAGES=0), and fails with a message naming
the engine, status 127, when there is none. A stand-in engine (a shell script) prints what it
was given.

usage: launcher.py VELUM WORK_DIR
"""
import os
import shutil
import subprocess
import sys

VELUM, WORK = sys.argv[1], sys.argv[2]
failures = []


def check(what, ok):
    print(("ok   " if ok else "FAIL ") + what)
    if not ok:
        failures.append(what)


shutil.rmtree(WORK, ignore_errors=True)
os.makedirs(WORK)
launcher = os.path.join(WORK, "velum")
shutil.copy(VELUM, launcher)

# No engine beside it.
r = subprocess.run([launcher, "--version"], capture_output=True, text=True)
check("without an engine: status 127", r.returncode == 127)
check("without an engine: the message names it",
      os.path.join(WORK, "velum-engine") in r.stderr and "install" in r.stderr)

engine = os.path.join(WORK, "velum-engine")
with open(engine, "w") as f:
    f.write('#!/bin/sh\nprintf "%s\\n" "$0" "tunables=$GLIBC_TUNABLES" "$@"\n')
os.chmod(engine, 0o755)

try:
    thp = open("/sys/kernel/mm/transparent_hugepage/enabled").read()
except OSError:
    thp = ""
honoured = "[madvise]" in thp or "[always]" in thp


def run(args, **env):
    e = {k: v for k, v in os.environ.items() if k not in ("GLIBC_TUNABLES", "VELUM_HUGE_PAGES")}
    e.update(env)
    r = subprocess.run([launcher] + args, capture_output=True, text=True, env=e)
    return r.returncode, r.stdout.splitlines()


status, out = run(["run", "a model.yaml", "-q"])
check("the engine ran: status 0", status == 0)
check("the engine beside the launcher, with the arguments as given",
      out[:1] == [engine] and out[2:] == ["run", "a model.yaml", "-q"])
want = "tunables=glibc.malloc.hugetlb=1" if honoured else "tunables="
check(f"the tunable ({thp.strip() or 'no THP'}): {want}", out[1:2] == [want])
status, out = run(["--version"], GLIBC_TUNABLES="glibc.malloc.arena_max=2")
check("the user's tunables kept",
      out[1:2] == ["tunables=glibc.malloc.arena_max=2" +
                   (":glibc.malloc.hugetlb=1" if honoured else "")])
status, out = run(["--version"], VELUM_HUGE_PAGES="0")
check("VELUM_HUGE_PAGES=0: no tunable", out[1:2] == ["tunables="])

print(f"{len(failures)} failed" if failures else "all passed")
sys.exit(1 if failures else 0)
