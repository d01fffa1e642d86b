#!/usr/bin/python3
"""Pictures of a Velum results folder without ParaView (`velum plot DIR`, docs/model-format.md).

Writes PNGs into OUT (default DIR/plots):
  shape_<field>_<frame>.png  the deformed shape coloured by a cell or point field of a frame;
                             cells where the field does not apply (NaN) are drawn grey;
  history.png                chosen history.csv columns against time, one panel each.
Runs with Debian's /usr/bin/python3 (matplotlib, meshio, numpy). Exit status 0; 1 with a
one-line message on bad input (no such folder, field, frame or column; a results file that is
damaged, empty, cut short or missing; an option out of range); 3 when the PNGs cannot be written.
Never a traceback.
"""
import argparse
import contextlib
import csv
import io
import os
import sys
import xml.etree.ElementTree as ET

# Plots compute on small arrays: numpy's OpenBLAS threads only spin (sched_yield) against the
# other plots and runs of `make demo`, and cost the plots a large share of their CPU time.
# A thread count the user set is kept; OPENBLAS_CORETYPE is never touched.
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

def missing_library(missing):
    print(f"velum plot: error: {missing.name} is missing (Debian: apt-get install "
          "python3-matplotlib python3-meshio)", file=sys.stderr)
    sys.exit(3)


try:
    import meshio
    import numpy as np
except ImportError as missing:
    missing_library(missing)

# matplotlib (0.27 s of a start's 0.5 s) is loaded at the first drawing, after every check of
# the input that comes before it: bad input is told without it.
matplotlib = plt = LineCollection = PolyCollection = Line3DCollection = Poly3DCollection = None


def load_matplotlib():
    global matplotlib, plt, LineCollection, PolyCollection, Line3DCollection, Poly3DCollection
    if plt is not None:
        return
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        from matplotlib.collections import LineCollection, PolyCollection
        from mpl_toolkits.mplot3d.art3d import Line3DCollection, Poly3DCollection
    except ImportError as missing:
        missing_library(missing)


# The boundary of each membrane cell, through its mid-side nodes (VTK/Gmsh order: corners,
# then mid-sides), so that curved quadratic elements are drawn curved.
OUTLINE = {"triangle": [0, 1, 2], "triangle6": [0, 3, 1, 4, 2, 5], "quad": [0, 1, 2, 3],
           "quad8": [0, 4, 1, 5, 2, 6, 3, 7], "quad9": [0, 4, 1, 5, 2, 6, 3, 7]}
VIEWS = {"xy": (0, 1), "xz": (0, 2), "yz": (1, 2)}
MAX_DEFAULT_COLUMNS = 8
DEFAULT_FIELDS = ["force_per_length_max", "true_stress_max", "force", "displacement"]


MAX_DPI = 1000  # a 7.5 x 6 inch figure at 1000 dpi is 45 megapixels


class BadInput(Exception):
    pass


class CannotWrite(Exception):
    pass


def finite_number(text):
    v = float(text)
    if not np.isfinite(v):
        raise argparse.ArgumentTypeError(f"{text}: expected a finite number")
    return v


def dpi_value(text):
    v = int(text)
    if not 1 <= v <= MAX_DPI:
        raise argparse.ArgumentTypeError(f"{text}: expected 1 to {MAX_DPI}")
    return v


class Parser(argparse.ArgumentParser):
    def error(self, message):  # one line, as every other error (exit 2: bad input)
        print(f"velum plot: error: {' '.join(message.split())} (velum plot --help)",
              file=sys.stderr)
        sys.exit(2)


def parse_args(argv):
    p = Parser(prog="velum plot", description=__doc__.split("\n")[0])
    p.add_argument("dir", metavar="DIR", help="results folder of `velum run`")
    p.add_argument("--field", help="cell or point field to colour by (default: "
                   "force_per_length_max, else true_stress_max, force, displacement); a vector "
                   "field is shown by its magnitude, or one component with NAME:x|y|z")
    p.add_argument("--nodal", action="store_true",
                   help="use the point (node-averaged) values of the field where a frame has both")
    p.add_argument("--frame", type=int, default=-1,
                   help="frame index, from 0; negative counts from the last (default -1)")
    p.add_argument("--scale", type=finite_number, default=1.0,
                   help="displacement magnification of the drawn shape (default 1)")
    p.add_argument("--view", choices=["iso", "xy", "xz", "yz"], default="iso",
                   help="3-D view or a projection onto a coordinate plane (default iso)")
    p.add_argument("--history", help="comma-separated history.csv columns (default: the "
                   "first 8; 'none' for no history figure)")
    p.add_argument("--no-shape", action="store_true", help="no deformed-shape figure")
    p.add_argument("-o", "--output", help="folder for the PNGs (default DIR/plots)")
    p.add_argument("--dpi", type=dpi_value, default=110,
                   help=f"resolution, 1 to {MAX_DPI} (default 110)")
    return p.parse_args(argv)


def frames_of(folder):
    pvd = os.path.join(folder, "results.pvd")
    if not os.path.exists(pvd):
        return []
    try:
        root = ET.parse(pvd).getroot()
        frames = [(float(d.get("timestep")), os.path.join(folder, d.get("file")))
                  for d in root.findall("./Collection/DataSet")]
    except (ET.ParseError, OSError, TypeError, ValueError) as e:
        raise BadInput(f"{pvd}: not a results index written by velum run ({one_line(e)})")
    return frames


def one_line(e):
    """An exception's message on one line (or its type's name when it has none)."""
    text = " ".join(str(e).split())
    return text if text else type(e).__name__


def read_frame_file(path):
    """read_frame, with any fault of the file (missing, empty, cut short, not VTK) bad input."""
    said = io.StringIO()  # meshio prints its own complaint and exits: keep it as the reason
    try:
        with contextlib.redirect_stderr(said), contextlib.redirect_stdout(said):
            mesh = read_frame(path)
    except (Exception, SystemExit) as e:  # meshio, ElementTree: many kinds on a damaged file
        why = one_line(said.getvalue()) if isinstance(e, SystemExit) else one_line(e)
        raise BadInput(f"{path}: cannot read the frame ({why or 'not a frame'})")
    if not len(mesh.points) or not np.all(np.isfinite(mesh.points)):
        raise BadInput(f"{path}: the frame has no points or points that are not finite")
    return mesh


def read_frame(path):
    """A frame as a meshio.Mesh; a run on several processes wrote it as a .pvtu naming one
    piece per process: put together in the one-process order by the pieces' node_index and
    cell_index arrays."""
    if not path.endswith(".pvtu"):
        return meshio.read(path)
    sources = [os.path.join(os.path.dirname(path), p.get("Source"))
               for p in ET.parse(path).getroot().iter("Piece")]
    pieces = [meshio.read(s) for s in sources]
    nodes = [p.point_data["node_index"] for p in pieces]
    n_points = 1 + max(int(n.max()) for n in nodes if n.size)
    points = np.zeros((n_points, 3))
    point_data = {name: np.zeros((n_points,) + np.shape(a)[1:], np.asarray(a).dtype)
                  for name, a in pieces[0].point_data.items() if name != "node_index"}
    cells = []  # (one-process index, type, nodes, {field: value})
    for p, at in zip(pieces, nodes):
        points[at] = p.points
        for name in point_data:
            point_data[name][at] = p.point_data[name]
        for b, block in enumerate(p.cells):
            index = p.cell_data["cell_index"][b]
            for k in range(len(block.data)):
                cells.append((int(index[k]), block.type, at[block.data[k]],
                              {n: v[b][k] for n, v in p.cell_data.items() if n != "cell_index"}))
    cells.sort(key=lambda c: c[0])
    blocks, cell_data = [], {n: [] for n in pieces[0].cell_data if n != "cell_index"}
    for _, kind, conn, values in cells:  # consecutive cells of one type: one block
        if not blocks or blocks[-1][0] != kind:
            blocks.append((kind, []))
            for n in cell_data:
                cell_data[n].append([])
        blocks[-1][1].append(conn)
        for n in cell_data:
            cell_data[n][-1].append(values[n])
    return meshio.Mesh(points, [(k, np.array(c)) for k, c in blocks], point_data=point_data,
                       cell_data={n: [np.array(v) for v in b] for n, b in cell_data.items()})


def field_values(mesh, name, nodal):
    """(values, where): values per cell (concatenated over blocks) or per point."""
    comp = None
    if ":" in name:
        name, c = name.rsplit(":", 1)
        if c not in ("x", "y", "z", "0", "1", "2"):
            raise BadInput(f"component '{c}' of field {name}: expected x, y or z")
        comp = "xyz".index(c) if c in "xyz" else int(c)
    in_cells, in_points = name in mesh.cell_data, name in mesh.point_data
    if not in_cells and not in_points:
        names = sorted(set(mesh.cell_data) | set(mesh.point_data))
        raise BadInput(f"no field '{name}' in the frame; fields: {', '.join(names)}")
    where = "point" if in_points and (nodal or not in_cells) else "cell"
    v = (np.asarray(mesh.point_data[name], dtype=float) if where == "point"
         else np.concatenate([np.asarray(b, dtype=float) for b in mesh.cell_data[name]]))
    if v.ndim == 2 and v.shape[1] > 1:
        if comp is not None:
            if comp >= v.shape[1]:
                raise BadInput(f"field {name} has {v.shape[1]} components")
            v = v[:, comp]
        else:
            v = np.linalg.norm(v, axis=1)
    elif comp is not None:
        raise BadInput(f"field {name} is a scalar: no component")
    return v.reshape(-1), where


def plot_shape(mesh, time, field, nodal, scale, view, path, dpi):
    U = mesh.point_data.get("displacement", np.zeros_like(mesh.points))
    x = mesh.points + scale * U
    values, where = field_values(mesh, field, nodal)
    polys, poly_vals, lines, line_vals = [], [], [], []
    k = 0
    for block in mesh.cells:
        for conn in block.data:
            if block.type in OUTLINE:
                outline = conn[OUTLINE[block.type]]
                polys.append(x[outline])
                poly_vals.append(values[outline].mean() if where == "point" else values[k])
            elif block.type in ("line", "line3"):
                ends = conn[[0, 2, 1]] if block.type == "line3" else conn[:2]
                lines.append(x[ends])
                lines_v = values[ends].mean() if where == "point" else values[k]
                line_vals.append(lines_v)
            k += 1
    shown = np.array([v for v in poly_vals + line_vals if np.isfinite(v)])
    lo, hi = (shown.min(), shown.max()) if shown.size else (0.0, 1.0)
    if hi <= lo:
        lo, hi = lo - 0.5 * max(abs(lo), 1e-30), hi + 0.5 * max(abs(hi), 1e-30)
    load_matplotlib()
    norm = matplotlib.colors.Normalize(lo, hi)
    cmap = matplotlib.colormaps["viridis"]

    def colours(vals):
        return [cmap(norm(v)) if np.isfinite(v) else (0.8, 0.8, 0.8, 1.0) for v in vals]

    fig = plt.figure(figsize=(7.5, 6))
    if view == "iso":
        ax = fig.add_subplot(projection="3d")
        if polys:
            ax.add_collection3d(Poly3DCollection(polys, facecolors=colours(poly_vals),
                                                 edgecolors=(0, 0, 0, 0.15), linewidths=0.2))
        if lines:
            ax.add_collection3d(Line3DCollection(lines, colors=colours(line_vals),
                                                 linewidths=1.2))
        # Equal scales on the three axes; a flat direction gets a little room (not a sliver).
        lo_x, hi_x = x.min(axis=0), x.max(axis=0)
        span = max((hi_x - lo_x).max(), 1e-30)
        half = np.maximum(0.5 * (hi_x - lo_x), 0.1 * span)
        mid = 0.5 * (lo_x + hi_x)
        for set_lim, m, h in zip((ax.set_xlim, ax.set_ylim, ax.set_zlim), mid, half):
            set_lim(m - h, m + h)
        ax.set_box_aspect(half)
        ax.set_xlabel("x"), ax.set_ylabel("y"), ax.set_zlabel("z")
    else:
        i, j = VIEWS[view]
        ax = fig.add_subplot()
        if polys:
            ax.add_collection(PolyCollection([p[:, [i, j]] for p in polys],
                                             facecolors=colours(poly_vals),
                                             edgecolors=(0, 0, 0, 0.15), linewidths=0.2))
        if lines:
            ax.add_collection(LineCollection([ln[:, [i, j]] for ln in lines],
                                             colors=colours(line_vals), linewidths=1.2))
        ax.autoscale_view()
        ax.set_aspect("equal")
        ax.set_xlabel("xyz"[i]), ax.set_ylabel("xyz"[j])
    sm = matplotlib.cm.ScalarMappable(norm=norm, cmap=cmap)
    fig.colorbar(sm, ax=ax, shrink=0.7,
                 label=f"{field} ({where} values, the model's units)")
    ax.set_title(f"t = {time:.6g}" + (f", displacements x {scale:g}" if scale != 1 else ""))
    fig.tight_layout()
    fig.savefig(path, dpi=dpi)
    plt.close(fig)


def read_history(folder):
    """history.csv as (header, rows of floats); every fault of the file is bad input that
    names the file and line."""
    name = os.path.join(folder, "history.csv")
    try:
        with open(name, newline="") as f:
            text = f.read()
    except (OSError, UnicodeDecodeError) as e:
        raise BadInput(f"{name}: cannot read it ({one_line(e)})")
    if "\0" in text:
        raise BadInput(f"{name}:{text[:text.index(chr(0))].count(chr(10)) + 1}: NUL bytes (the "
                       "file is damaged)")
    rows = [(i + 1, r) for i, r in enumerate(csv.reader(text.splitlines())) if r]
    if not rows:
        raise BadInput(f"{name}: empty (no header line)")
    head, data = rows[0][1], []
    for line, r in rows[1:]:
        if len(r) != len(head):
            raise BadInput(f"{name}:{line}: {len(r)} values, the header has {len(head)}")
        try:
            data.append([float(v) for v in r])
        except ValueError as e:
            raise BadInput(f"{name}:{line}: {one_line(e)}")
    return head, np.array(data, dtype=float).reshape(len(data), len(head))


def plot_history(folder, columns, path, dpi):
    head, data = read_history(folder)
    available = head[1:]
    if columns is None:
        columns = available[:MAX_DEFAULT_COLUMNS]
        if len(available) > MAX_DEFAULT_COLUMNS:
            print(f"velum plot: history.csv has {len(available)} columns: the first "
                  f"{MAX_DEFAULT_COLUMNS} drawn (--history to choose)", file=sys.stderr)
    for c in columns:
        if c not in available:
            raise BadInput(f"no column '{c}' in history.csv; columns: {', '.join(available)}")
    if not columns or data.size == 0:
        return False
    load_matplotlib()
    fig, axes = plt.subplots(len(columns), 1, sharex=True, squeeze=False,
                             figsize=(7, 1.2 + 1.8 * len(columns)))
    for ax, c in zip(axes[:, 0], columns):
        ax.plot(data[:, 0], data[:, head.index(c)], marker="." if len(data) < 40 else None)
        ax.set_ylabel(c)
        ax.grid(alpha=0.3)
    axes[-1, 0].set_xlabel("time")
    fig.suptitle(os.path.basename(os.path.normpath(folder)) + ": history")
    fig.tight_layout()
    save(fig, path, dpi)
    return True


def make_folder(out):
    try:
        os.makedirs(out, exist_ok=True)
    except OSError as e:
        raise CannotWrite(f"{out}: cannot make the folder for the PNGs ({one_line(e)})")
    if not os.access(out, os.W_OK | os.X_OK):
        raise CannotWrite(f"{out}: the folder for the PNGs is not writable")


def save(fig, path, dpi):
    """Writes the figure; a PNG that cannot be written is an I/O failure."""
    try:
        fig.savefig(path, dpi=dpi)
    except OSError as e:
        raise CannotWrite(f"{path}: cannot write it ({one_line(e)})")
    finally:
        plt.close(fig)


def main(argv):
    a = parse_args(argv)
    if not os.path.isdir(a.dir):
        raise BadInput(f"{a.dir}: no such results folder")
    out = a.output or os.path.join(a.dir, "plots")
    written = []
    frames = frames_of(a.dir)
    if not a.no_shape and (frames or a.field):
        if not frames:
            raise BadInput(f"{a.dir}: no frames (results.pvd; output.fields is off?)")
        if not -len(frames) <= a.frame < len(frames):
            raise BadInput(f"frame {a.frame}: the run wrote {len(frames)} frames (0 to "
                           f"{len(frames) - 1}, or negative from the last)")
        index = a.frame % len(frames)
        time, path = frames[index]
        mesh = read_frame_file(path)
        field = a.field or next((f for f in DEFAULT_FIELDS
                                 if f in mesh.cell_data or f in mesh.point_data), None)
        if field is None:
            raise BadInput(f"{path}: none of the fields {', '.join(DEFAULT_FIELDS)} (--field "
                           "to choose one)")
        make_folder(out)
        png = os.path.join(out, f"shape_{field.replace(':', '_')}_{index:05d}.png")
        plot_shape(mesh, time, field, a.nodal, a.scale, a.view, png, a.dpi)
        written.append(png)
    if a.history != "none" and os.path.exists(os.path.join(a.dir, "history.csv")):
        columns = None if a.history is None else [c.strip() for c in a.history.split(",")]
        make_folder(out)
        png = os.path.join(out, "history.png")
        if plot_history(a.dir, columns, png, a.dpi):
            written.append(png)
    if not written:
        raise BadInput(f"{a.dir}: nothing to plot (no frames, no history columns)")
    for w in written:
        print(w)
    return 0


if __name__ == "__main__":
    try:
        sys.exit(main(sys.argv[1:]))
    except BadInput as e:
        print(f"velum plot: error: {e}", file=sys.stderr)
        sys.exit(1)
    except CannotWrite as e:
        print(f"velum plot: error: {e}", file=sys.stderr)
        sys.exit(3)
    except MemoryError:
        print("velum plot: error: out of memory (a smaller --dpi?)", file=sys.stderr)
        sys.exit(1)
    except Exception as e:  # whatever a damaged folder leads to: one line, never a traceback
        print(f"velum plot: error: cannot draw the plots: {one_line(e)}", file=sys.stderr)
        sys.exit(1)
