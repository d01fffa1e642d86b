"""The in-process run behind ``velum.run`` and ``Model.run``: below both the model and the
runner, so that neither imports the other."""
import os
import warnings

from . import _velum
from .errors import InputError, OutputError, SolveError, VelumWarning
from .results import Results


def run_model(model, output, threads, quiet, progress, stacklevel):
    """Solves ``model`` (a ``velum.Model``) as ``velum.run`` documents; ``stacklevel`` is that
    of the model's warnings, counted from this function."""
    out = _velum.run(model._data, model.name, str(model.base_dir),
                     None if output is None else os.fspath(output), int(threads), bool(quiet),
                     progress)
    for w in out["warnings"]:
        warnings.warn(w, VelumWarning, stacklevel=stacklevel)
    status = out["status"]
    if status == _velum.EXIT_BAD_INPUT:
        raise InputError(out["errors"])
    if status == _velum.EXIT_IO:
        raise OutputError("\n".join(out["errors"]))
    results = Results(out["directory"], out["node_ids"], out["blocks"], out["stopped"],
                      out["warnings"])
    if status != _velum.EXIT_OK and not out["stopped"]:  # failed (or any status to come)
        raise SolveError("\n".join(out["errors"]), results)
    return results
