"""The exceptions of vibrissa. Each message is the command line's one line, naming the
culprit (the parameter and its value, the file and line, or the solver and its residual)."""


class VibrissaError(Exception):
    """Base class of every error vibrissa raises."""


class InvalidInput(VibrissaError, ValueError):
    """A parameter, profile, scene file or log that the model refuses."""


class SolverError(VibrissaError, RuntimeError):
    """No solution meets the accuracy asked for (the message names the solver and its
    residual or error estimate)."""


class NoContact(SolverError):
    """The whisker never touches the obstacle during the sweep."""
