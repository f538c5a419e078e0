"""The exceptions tensorglyph raises. Every message is the command line's one line, naming the
file (or the argument) and the place."""


class Error(ValueError):
    """Bad data, a bad option or a renderer that failed: the command line's one-line message."""


class FileError(Error, OSError):
    """A file that cannot be read or written (also an ``OSError``)."""


class FileNotFound(FileError, FileNotFoundError):
    """A file that is not there (also a ``FileNotFoundError``)."""
