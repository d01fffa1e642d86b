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

# Damaged folders and options out of range (issue 47): a one-line message, exit 1 (3 when the
# PNGs cannot be written), never a traceback.
def damaged(name, damage):
    d = os.path.join(WORK, "damaged", name)
    shutil.copytree(run, d)
    shutil.rmtree(os.path.join(d, "plots"), ignore_errors=True)
    damage(d)
    return d


def rewrite(rel, text=None, cut=None, mode="w"):
    def damage(d):
        path = os.path.join(d, rel)
        if cut is not None:
            data = open(path, "rb").read()
            open(path, "wb").write(data[:int(len(data) * cut)])
        else:
            open(path, mode).write(text)
    return damage


def remove(rel):
    return lambda d: os.remove(os.path.join(d, rel))


frame = "frames/frame_00010.vtu"
pvtu = ('<?xml version="1.0"?>\n<VTKFile type="PUnstructuredGrid" version="1.0">'
        '<PUnstructuredGrid GhostLevel="0"><PPoints><PDataArray type="Float64" '
        'NumberOfComponents="3"/></PPoints><Piece Source="frame_00010/piece_0.vtu"/>'
        '<Piece Source="frame_00010/piece_1.vtu"/></PUnstructuredGrid></VTKFile>\n')


def two_pieces(d):  # a run on two processes whose pieces are missing
    open(os.path.join(d, "frames", "frame_00010.pvtu"), "w").write(pvtu)
    pvd = open(os.path.join(d, "results.pvd")).read()
    open(os.path.join(d, "results.pvd"), "w").write(pvd.replace(frame, "frames/frame_00010.pvtu"))


def nan_points(d):
    path = os.path.join(d, frame)
    import meshio
    m = meshio.read(path)
    m.points[0, 0] = float("nan")
    meshio.write(path, m)


history_only = ["--no-shape"]
shape_only = ["--history", "none"]
cases = [
    ("garbage pvd", rewrite("results.pvd", "\x01\x02 not xml"), shape_only, 1),
    ("empty pvd", rewrite("results.pvd", ""), shape_only, 1),
    ("truncated pvd", rewrite("results.pvd", cut=0.5), shape_only, 1),
    ("pvd bad time", lambda d: rewrite("results.pvd", open(os.path.join(
        d, "results.pvd")).read().replace('timestep="', 'timestep="x'))(d), shape_only, 1),
    ("garbage frame", rewrite(frame, "garbage\n"), shape_only, 1),
    ("empty frame", rewrite(frame, ""), shape_only, 1),
    ("truncated frame", rewrite(frame, cut=0.6), shape_only, 1),
    ("missing frame", remove(frame), shape_only, 1),
    ("missing pieces", two_pieces, shape_only, 1),
    ("nan points", nan_points, shape_only, 1),
    ("ragged history", rewrite("history.csv", "time,a,b\n0,1,2\n1,2\n"), history_only, 1),
    ("nul history", rewrite("history.csv", "time,a\n0,1\n\0\0\0\n"), history_only, 1),
    ("empty history", rewrite("history.csv", ""), history_only, 1),
    ("text history", rewrite("history.csv", "time,a\n0,one\n"), history_only, 1),
    ("binary history", rewrite("history.csv", b"\xff\xfe\x00x", mode="wb"), history_only, 1),
    ("scale nan", lambda d: None, ["--scale", "nan"], 1),
    ("scale inf", lambda d: None, ["--scale", "-inf"], 1),
    ("dpi 0", lambda d: None, ["--dpi", "0"], 1),
    ("dpi negative", lambda d: None, ["--dpi", "-5"], 1),
    ("dpi huge", lambda d: None, ["--dpi", "1000000000"], 1),
    ("output is a file", lambda d: open(os.path.join(d, "plots"), "w").write("x"), [], 3),
    ("output under a file", lambda d: open(os.path.join(d, "f"), "w").write("x"),
     ["-o", "f/plots"], 3),
]
if os.geteuid() != 0:  # root writes into a read-only folder
    cases.append(("read-only output", lambda d: os.makedirs(os.path.join(d, "plots"), 0o500),
                  [], 3))
for name, damage, args, code in cases:
    d = damaged(name.replace(" ", "_"), damage)
    args = [a if a != "f/plots" else os.path.join(d, "f", "plots") for a in args]
    p = plot(d, *args)
    lines = p.stderr.strip().splitlines()
    assert p.returncode == code, (name, p.returncode, p.stderr)
    assert len(lines) == 1 and lines[0].startswith("velum plot: error: "), (name, p.stderr)
    assert "Traceback" not in p.stderr, (name, p.stderr)
print(f"velum plot: pictures, bad input and {len(cases)} damaged folders or options as expected")
