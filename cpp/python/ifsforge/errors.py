"""The exceptions ifsforge raises. Each also derives from the built-in a caller would catch."""


class Error(Exception):
    """Base of every ifsforge error."""


class InputError(Error, ValueError):
    """Malformed input: a file, a parameter, a coefficient."""


class DivergentSystemError(InputError):
    """The system has no attractor."""


class MemoryBudgetError(Error, MemoryError):
    """The job would need more memory than the budget; nothing was allocated."""


class FileError(Error, OSError):
    """A path could not be read or written."""


class Cancelled(Error):
    """The progress callback asked to stop."""
