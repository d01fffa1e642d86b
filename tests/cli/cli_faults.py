#!/usr/bin/python3
"""Faults around a run (issue 14, item 3): SIGINT and SIGTERM finish the current step and leave
summary.json "interrupted" (exit 130 / 143); a closed, full or broken stdout/stderr never stops a
run; summary.json says "running" from the start; a second run into a folder in use is refused
(exit 3) and a killed run does not leave it locked; a rerun killed early never leaves the previous
run's "converged" beside its own partial history; out of memory while reading is exit 1.

usage: cli_faults.py VELUM WORK_DIR [CASE_NAME_SUBSTRING]
"""
import json
import os
import resource
import shutil
import signal
import subprocess
import sys
import time

import yaml

VELUM, WORK = sys.argv[1], sys.argv[2]
ONLY = sys.argv[3] if len(sys.argv) > 3 else ""
ASAN = b"__asan_init" in open(VELUM, "rb").read()


def model(end=0.02, interval=0.01):
    m = {
        "mesh": {
            "nodes": [[1, 0, 0, 0], [2, 1, 0, 0], [3, 2, 0, 0], [4, 0, 1, 0], [5, 1, 1, 0],
                      [6, 2, 1, 0]],
            "elements": [{"set": "sheet", "type": "quad4",
                          "connectivity": [[1, 2, 5, 4], [2, 3, 6, 5]]}],
            "node_sets": {"left": [1, 4], "right": [3, 6]},
        },
        "materials": {"iso": {"type": "isotropic", "E": 1000.0, "nu": 0.3, "density": 1.0}},
        "sections": [{"elements": "sheet", "material": "iso", "thickness": 0.1}],
        "boundary": [{"nodes": "left", "fix": ["x", "y", "z"]}],
        "loads": [{"type": "edge", "nodes": "right", "force_per_length": [1.0, 0, 0]}],
        "analysis": {"type": "dynamic", "time": {"end": end, "step": 0.005}},
        "output": {"interval": interval, "history": [
            {"name": "ux", "quantity": "displacement", "node": 6, "component": "x"}]},
    }
    return yaml.safe_dump(m)


def case_dir(name, text):
    d = os.path.join(WORK, name)
    shutil.rmtree(d, ignore_errors=True)
    os.makedirs(d)
    with open(os.path.join(d, "model.yaml"), "w") as f:
        f.write(text)
    return d


def cmd(d, out="out"):
    return [VELUM, "run", os.path.join(d, "model.yaml"), "--threads", "1", "-o",
            os.path.join(d, out)]


def summary(d, out="out"):
    try:
        return json.load(open(os.path.join(d, out, "summary.json")))
    except (OSError, ValueError) as e:
        return {"status": f"unreadable: {e}"}


def history_rows(d, out="out"):
    with open(os.path.join(d, out, "history.csv")) as f:
        rows = [r.rstrip("\n").split(",") for r in f]
    return rows


def wait_for_steps(d, rows=3, out="out", timeout=60, pid=None):
    """Waits until the run (process `pid`, when given: summary.json names it once the run has
    started) has written `rows` history rows (header included)."""
    t0 = time.time()
    if pid is not None:
        while summary(d, out).get("pid") != pid and time.time() - t0 < timeout:
            time.sleep(0.01)
        time.sleep(0.2)  # the previous run's history is truncated right after
    while time.time() - t0 < timeout:
        try:
            if len(history_rows(d, out)) >= rows:
                return True
        except OSError:
            pass
        time.sleep(0.02)
    return False


def check(cond, what, problems):
    if not cond:
        problems.append(what)


def interrupted_by(sig, status):
    def run(name):
        d = case_dir(name, model(end=1000.0, interval=0.5))
        p = subprocess.Popen(cmd(d), stdout=subprocess.PIPE, stderr=subprocess.PIPE)
        problems = []
        check(wait_for_steps(d, pid=p.pid), "the run wrote no history", problems)
        check(summary(d).get("status") == "running", f"summary.json while running: {summary(d)}",
              problems)
        p.send_signal(sig)
        out, err = p.communicate(timeout=60)
        check(p.returncode == status, f"exit status {p.returncode}, expected {status}", problems)
        s = summary(d)
        check(s.get("status") == "interrupted", f"summary.json status {s.get('status')}", problems)
        name_ = "SIGINT" if sig == signal.SIGINT else "SIGTERM"
        check(name_ in s.get("reason", ""), f"summary.json reason {s.get('reason')}", problems)
        check(name_ in err.decode(), "the console does not say why it stopped", problems)
        rows = history_rows(d)
        check(all(len(r) == 2 for r in rows), "history.csv is ragged", problems)
        check(float(rows[-1][0]) <= s.get("final_time", -1) + 1e-12,
              "history.csv goes past final_time", problems)
        check(s.get("final_time", 0) < 1000.0, "the run was not stopped early", problems)
        return problems
    return run


def runs_with_streams(make_streams):
    def run(name):
        d = case_dir(name, model())
        stdout, stderr, preexec, cleanup = make_streams()
        p = subprocess.run(cmd(d), stdout=stdout, stderr=stderr, preexec_fn=preexec, timeout=120)
        cleanup()
        problems = []
        check(p.returncode == 0, f"exit status {p.returncode}, expected 0", problems)
        check(summary(d).get("status") == "converged", f"summary.json {summary(d)}", problems)
        check(len(history_rows(d)) == 4, "history.csv lacks rows", problems)
        check(os.path.exists(os.path.join(d, "out", "results.pvd")), "no results.pvd", problems)
        return problems
    return run


def closed_streams():
    def preexec():
        os.close(1)
        os.close(2)
    return None, None, preexec, lambda: None


def full_streams():
    full = open("/dev/full", "w")
    return full, full, None, full.close


def broken_pipes():
    r, w = os.pipe()
    os.close(r)  # nobody reads: every write fails with EPIPE (SIGPIPE ignored)
    return w, w, None, lambda: os.close(w)


def closed_stdin_and_stdout():
    def preexec():
        os.close(0)
        os.close(1)
    return None, subprocess.DEVNULL, preexec, lambda: None


def second_run_refused(name):
    d = case_dir(name, model(end=1000.0, interval=0.5))
    problems = []
    first = subprocess.Popen(cmd(d), stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    check(wait_for_steps(d, pid=first.pid), "the first run wrote no history", problems)
    rows_before = len(history_rows(d))
    second = subprocess.run(cmd(d), capture_output=True, text=True, timeout=60)
    check(second.returncode == 3, f"second run: exit {second.returncode}, expected 3", problems)
    check("another velum run" in second.stderr and ".velum.lock" in second.stderr,
          f"second run's message: {second.stderr!r}", problems)
    check(len(history_rows(d)) >= rows_before, "the second run truncated the history", problems)
    check(summary(d).get("status") == "running", "the second run touched summary.json", problems)
    first.kill()  # SIGKILL: no clean-up at all
    first.wait()
    third = subprocess.Popen(cmd(d), stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    check(wait_for_steps(d, pid=third.pid), "a killed run left the folder locked", problems)
    third.send_signal(signal.SIGTERM)
    third.wait(timeout=60)
    check(third.returncode == 143, f"exit {third.returncode} after SIGTERM", problems)
    return problems


def rerun_after_kill(name):
    d = case_dir(name, model(end=1000.0, interval=0.5))
    problems = []
    third = subprocess.Popen(cmd(d), stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    check(wait_for_steps(d, pid=third.pid), "no history", problems)
    third.send_signal(signal.SIGTERM)
    _, err = third.communicate(timeout=60)
    check(third.returncode == 143, f"exit {third.returncode} after SIGTERM", problems)
    first = subprocess.Popen(cmd(d), stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    check(wait_for_steps(d, pid=first.pid), "no history after a SIGTERMed run", problems)
    first.kill()
    first.wait()
    again = subprocess.Popen(cmd(d), stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    check(wait_for_steps(d, pid=again.pid), "a SIGKILLed run left the folder locked", problems)
    again.send_signal(signal.SIGINT)
    again.communicate(timeout=60)
    check(again.returncode == 130, f"exit {again.returncode} after SIGINT", problems)
    return problems


def rerun_killed_early(name):
    d = case_dir(name, model())
    problems = []
    p = subprocess.run(cmd(d), capture_output=True, timeout=120)
    check(p.returncode == 0 and summary(d).get("status") == "converged", "first run", problems)
    check(len(os.listdir(os.path.join(d, "out", "frames"))) == 3, "first run's frames", problems)
    with open(os.path.join(d, "model.yaml"), "w") as f:
        f.write(model(end=1000.0, interval=0.5))
    p = subprocess.Popen(cmd(d), stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    # As soon as summary.json stops saying "converged", the old run's results are gone.
    t0 = time.time()
    while summary(d).get("status") == "converged" and time.time() - t0 < 60:
        time.sleep(0.001)
    p.kill()
    p.wait()
    s = summary(d)
    check(s.get("status") == "running", f"summary.json after a killed rerun: {s}", problems)
    rows = history_rows(d) if os.path.exists(os.path.join(d, "out", "history.csv")) else []
    check(all(len(r) == 2 for r in rows), "history.csv is ragged", problems)
    return problems


def out_of_memory(name):
    if ASAN:
        return []  # an address-space limit and AddressSanitizer's shadow memory do not mix
    nodes = [[i + 1, float(i % 1000), float(i // 1000), 0.0] for i in range(400_000)]
    text = yaml.safe_dump({"mesh": {"nodes": nodes}}, default_flow_style=True)
    d = case_dir(name, text)
    limit = 400 << 20

    def preexec():
        resource.setrlimit(resource.RLIMIT_AS, (limit, limit))
    p = subprocess.run(cmd(d), capture_output=True, text=True, preexec_fn=preexec, timeout=120)
    problems = []
    check(p.returncode == 1, f"exit {p.returncode}, expected 1: {p.stderr[-500:]!r}", problems)
    check("out of memory" in p.stderr and "model.yaml" in p.stderr,
          f"message: {p.stderr[-500:]!r}", problems)
    return problems


CASES = [
    ("sigint_finishes_step", interrupted_by(signal.SIGINT, 130)),
    ("sigterm_finishes_step", interrupted_by(signal.SIGTERM, 143)),
    ("stdout_stderr_closed", runs_with_streams(closed_streams)),
    ("stdin_stdout_closed", runs_with_streams(closed_stdin_and_stdout)),
    ("stdout_stderr_full", runs_with_streams(full_streams)),
    ("stdout_stderr_broken_pipe", runs_with_streams(broken_pipes)),
    ("second_run_refused", second_run_refused),
    ("rerun_after_kill", rerun_after_kill),
    ("rerun_killed_early", rerun_killed_early),
    ("out_of_memory_reading", out_of_memory),
]


def main():
    failed = 0
    cases = [c for c in CASES if not ONLY or ONLY in c[0]]
    for name, run in cases:
        try:
            problems = run(name)
        except Exception as e:  # a timeout or a missing file is a failure too
            problems = [f"{type(e).__name__}: {e}"]
        if problems:
            failed += 1
            print(f"FAIL {name}: {'; '.join(problems)}")
        else:
            print(f"ok   {name}")
    print(f"{len(cases) - failed}/{len(cases)} fault cases passed")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
