#!/usr/bin/python3
"""`velum plot` (issue 20): PNGs of the deformed shape and of history columns from a results
folder, its options and its bad input.

usage: plot_cases.py VELUM MODEL.yaml WORK_DIR
"""
import os
import shutil
import struct
import subprocess
import sys

VELUM, MODEL, WORK = sys.argv[1:4]
shutil.rmtree(WORK, ignore_errors=True)
run = os.path.join(WORK, "run")
p = subprocess.run([VELUM, "run", MODEL, "-o", run, "--threads", "1", "--quiet"],
                   capture_output=True, text=True)
assert p.returncode == 0, f"velum run failed ({p.returncode}):\n{p.stderr}"


def plot(*args):
    return subprocess.run([VELUM, "plot", *args], capture_output=True, text=True, timeout=300)


def png_size(path):
    """Width and height of a PNG (its IHDR chunk)."""
    with open(path, "rb") as f:
        head = f.read(24)
    assert head[:8] == b"\x89PNG\r\n\x1a\n", f"{path} is not a PNG"
    return struct.unpack(">II", head[16:24])


# Defaults: the last frame coloured by the force per length, and every history column.
p = plot(run)
assert p.returncode == 0, p.stderr
written = p.stdout.split()
assert len(written) == 2, p.stdout
shape = os.path.join(run, "plots", "shape_force_per_length_max_00010.png")
history = os.path.join(run, "plots", "history.png")
assert written == [shape, history], written
for png in written:
    w, h = png_size(png)
    assert w > 300 and h > 300, (png, w, h)
    assert os.path.getsize(png) > 10_000, png  # a picture, not an empty canvas

# A chosen field (point values, a vector component), frame, view, scale, columns and folder.
out = os.path.join(WORK, "chosen")
p = plot(run, "--field", "displacement:z", "--frame", "3", "--view", "xz", "--scale", "5",
         "--history", "centre_uz,rim_Rz", "-o", out)
assert p.returncode == 0, p.stderr
assert p.stdout.split() == [os.path.join(out, "shape_displacement_z_00003.png"),
                            os.path.join(out, "history.png")], p.stdout
p = plot(run, "--field", "true_stress_max", "--nodal", "--history", "none", "-o", out)
assert p.returncode == 0 and p.stdout.split() == [
    os.path.join(out, "shape_true_stress_max_00010.png")], (p.stdout, p.stderr)

# Help names the options; bad input: exit 1 and a message naming what is wrong.
p = plot("--help")
assert p.returncode == 0 and "--field" in p.stdout and "--history" in p.stdout, p
for args, phrase in [([os.path.join(WORK, "nowhere")], "no such results folder"),
                     ([run, "--field", "stres_11"], "no field 'stres_11'"),
                     ([run, "--frame", "11"], "frame 11: the run wrote 11 frames"),
                     ([run, "--history", "centre_uz,nope"], "no column 'nope'"),
                     ([run, "--view", "top"], "invalid choice")]:
    p = plot(*args)
    assert p.returncode == 1, (args, p.returncode, p.stderr)
    assert phrase in p.stderr, (args, p.stderr)
print("velum plot: pictures and bad input as expected")
