"""The exceptions of the velum module."""


class InputError(ValueError):
    """The model is not valid. ``messages`` lists every problem found, each naming the model
    (its file, or the name given to an in-memory model), the line when it came from a file,
    and the key: ``"c9.yaml: materials.canopy.E: expected a number"``."""

    def __init__(self, messages):
        if isinstance(messages, str):
            messages = [messages]
        self.messages = list(messages)
        super().__init__("\n".join(self.messages))


class SolveError(RuntimeError):
    """The solve failed (no convergence at the smallest step). ``results`` holds what was
    written up to the failure (history, frames, summary with ``status: failed``)."""

    def __init__(self, message, results):
        self.results = results
        super().__init__(message)


class OutputError(OSError):
    """The results directory or a file in it could not be written."""


class VelumWarning(UserWarning):
    """A model warning that is not fatal (as the command line's ``warning:`` lines)."""
