"""velum.run: a model solved in-process by the command line's own run function."""
from ._run import run_model
from .model import as_model
from .results import Results


def run(model, output=None, threads=0, quiet=False, progress=None):
    """Solves a model (a ``velum.Model``, a dict, or a model file path) in this process and
    writes the same files as ``velum run`` (history.csv, steps.csv, the ParaView frames,
    summary.json). Returns ``velum.Results``.

    output:   results directory; default the model's ``output.directory`` (relative to its
              base_dir), as ``velum run`` without -o
    threads:  OpenMP threads (0: OpenMP's default, as the command line)
    quiet:    no progress or statistics on stderr
    progress: called as ``progress(time, step, iterations)`` after every accepted step (step 0
              at the start); returning False stops the run, which then returns results with
              ``stopped`` set and ``status`` "failed". An exception from it stops the run and
              is raised once summary.json is written; so is Ctrl-C.

    Raises velum.InputError (bad model: every message, each naming the key),
    velum.SolveError (no convergence at the smallest step; ``.results`` holds what was written)
    and velum.OutputError (the results cannot be written). Model warnings become Python
    warnings (velum.VelumWarning).
    """
    # stacklevel 3: a warning points at the caller of run.
    return run_model(as_model(model), output, threads, quiet, progress, stacklevel=3)


def open_results(directory, model=None):
    """Results of an earlier run (by ``velum run`` or ``velum.run``) in ``directory``. With
    the model (a ``velum.Model``, a dict or a path), ``node_ids`` and ``blocks`` are set too."""
    node_ids, blocks = None, None
    if model is not None:
        stats = as_model(model).check()
        node_ids, blocks = stats["node_ids"], stats["blocks"]
    return Results(directory, node_ids, blocks)
