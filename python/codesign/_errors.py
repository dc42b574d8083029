"""The exceptions of codesign: every failure is a :class:`codesign.Error`."""


class Error(Exception):
    """Any failure of codesign; its message is the command line's."""


class InputError(Error, ValueError):
    """A task, file or argument that is not valid; the message names the file, field or keyword."""


class SolverError(Error, RuntimeError):
    """IPOPT, a worker process or a file write failed while the work ran."""
