"""The package's exceptions: one definition each, importable from every layer.

* :class:`ParameterError` - invalid input. Its message is one line naming the field, the value
  and what is allowed; the command line prints it and exits with status 2, writing nothing.
* :class:`EquilibriumError` - no balance position could be found for a parameter set; the
  command line prints it in one line and exits with status 3.
* :class:`IncompleteError` - a computation stopped before it finished (e.g. a campaign whose dask
  scheduler went away); what it wrote is kept for a resume. The command line prints it in one
  line and exits with status 3.
"""

from __future__ import annotations


class ParameterError(ValueError):
    """Invalid input: the message is one line naming the field, the value and what is allowed."""


class EquilibriumError(RuntimeError):
    """The balance position could not be found; ``.result`` holds the solver's result.

    Parameters
    ----------
    message : str
        One line: why, and what was tried.
    result : object, optional
        The raw solver result (``scipy.optimize.OptimizeResult``), for diagnosis.
    """

    def __init__(self, message: str, result=None):
        super().__init__(message)
        self.result = result


class IncompleteError(RuntimeError):
    """A computation stopped before it finished; its output so far is kept (exit status 3).

    The message is one line: what stopped, and how to go on (e.g. run the same command again).
    """
