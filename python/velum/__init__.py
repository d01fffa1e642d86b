"""Velum from Python: load, edit, build and run models in-process; results as numpy arrays.

    import velum
    m = velum.load("model.yaml")              # dict-like: m["materials"]["skin"]["E"] = 2e9
    r = velum.run(m, output="out", threads=1)  # the command line's run, in this process
    r.status, r.summary                        # as summary.json
    r.history["time"], r.history["w"]          # numpy arrays, one per history.csv column
    r.node_ids, r.frame(-1).displacement       # (N,) ids, (N, 3) displacement, last frame

Errors: velum.InputError (names the key), velum.SolveError (``.results``: what was written),
velum.OutputError. Guide: docs/python.md.
"""
from ._velum import __version__
from .errors import InputError, OutputError, SolveError, VelumWarning
from .mesh import mesh, mesh_from_meshio
from .model import Model, check, load
from .results import Frame, Results
from .runner import open_results, run

__all__ = ["Frame", "InputError", "Model", "OutputError", "Results", "SolveError",
           "VelumWarning", "check", "load", "mesh", "mesh_from_meshio", "open_results", "run",
           "__version__"]
