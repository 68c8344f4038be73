"""The error a bad record or parameter file raises: one line naming the file, the row (line
number in the file) and the column, and what was expected."""

from __future__ import annotations

__all__ = ["OptionError", "RecordError"]


class RecordError(ValueError):
    """A record or parameter file that cannot be used as it is.

    ``str(err)`` is one line: ``"<file>: line <row>, column '<col>': <what was expected>"``
    (row and column when known).  The command line prints it and exits with status 2.

    Examples
    --------
    >>> str(RecordError("run.csv", "expected a number; got 'abc'", row=12, column="t"))
    "run.csv: line 12, column 't': expected a number; got 'abc'"
    """

    def __init__(self, path: object, message: str, *, row: int | None = None,
                 column: str | None = None) -> None:
        self.path = str(path)
        self.row = row
        self.column = column
        self.detail = " ".join(str(message).split())  # always one line
        where = [self.path]
        loc = []
        if row is not None:
            loc.append(f"line {row}")
        if column is not None:
            loc.append(f"column {column!r}")
        text = f"{self.path}: " + (", ".join(loc) + ": " if loc else "") + self.detail
        del where
        super().__init__(text)


class OptionError(ValueError):
    """A bad command-line option (not a bad file): one line naming the option and what was
    expected; the command line prints it and exits with status 2.

    Examples
    --------
    >>> str(OptionError("--t0 must be a finite number of seconds; got nan"))
    '--t0 must be a finite number of seconds; got nan'
    """
