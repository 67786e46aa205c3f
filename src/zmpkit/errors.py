"""The zmpkit exception tree.

Every error a user can cause derives from :class:`ZmpkitError`. Messages say what was
expected, what came, and (where there is a closed set) what is valid, so the CLI can print
them as one line and exit with code 2 instead of a traceback. A check that finds several
problems in a file raises them together (:class:`InputFileProblemsError`): one line each.
"""

from __future__ import annotations

from collections.abc import Iterable

__all__ = [
    "FigureWarning",
    "InputFileError",
    "InputFileProblemsError",
    "ModelError",
    "NonFiniteResultError",
    "ParameterError",
    "SimulationDivergedError",
    "VideoWarning",
    "ZmpkitError",
    "ZmpkitWarning",
    "problem_lines",
]


class ZmpkitError(Exception):
    """Base class of every error zmpkit raises on purpose."""


class ParameterError(ZmpkitError, ValueError):
    """A parameter is out of its valid range, non-finite or of the wrong shape."""


class ModelError(ZmpkitError, ValueError):
    """A model cannot do what was asked, e.g. an unstable DLIPM where a stable one is needed."""


class NonFiniteResultError(ZmpkitError, ValueError):
    """A computed result is not finite; raised before it is written, naming the row.

    Args:
        what: the result, e.g. ``"zmp.csv"``.
        row: 1-based row of the result (the header is row 1 in a CSV).
        message: what was not finite.
    """

    def __init__(self, what: str, row: int, message: str) -> None:
        self.what = what
        self.row = row
        self.detail = message
        super().__init__(f"{what}, row {row}: {message}; nothing written")

    def __reduce__(self) -> tuple[object, ...]:
        """Pickle support (errors cross process pools): rebuild from the constructor args."""
        return (NonFiniteResultError, (self.what, self.row, self.detail))


class ZmpkitWarning(UserWarning):
    """Base class of the warnings zmpkit issues: the run goes on, something is missing."""


class FigureWarning(ZmpkitWarning):
    """A figure could not be drawn; the data it would show were written all the same."""


class VideoWarning(ZmpkitWarning):
    """A video could not be written as MP4: a GIF, a keyframe strip or nothing was written.

    The data the video would show were written all the same; the warning says why.
    """


class InputFileError(ZmpkitError, ValueError):
    """A file the user gave cannot be read as expected.

    Args:
        path: the file.
        message: what was wrong and what was expected.
        row: 1-based line number in the file, when the problem is on one line.
        column: the column or field name, when the problem is in one column.
        key: the key of a YAML file the problem is at, dotted (``feet.right``); the message
            reads ``PATH: KEY: MESSAGE``.
    """

    def __init__(
        self,
        path: object,
        message: str,
        *,
        row: int | None = None,
        column: str | None = None,
        key: str | None = None,
    ) -> None:
        self.path = str(path)
        self.row = row
        self.column = column
        self.key = key
        self.detail = message
        where = self.path
        if row is not None:
            where += f", line {row}"
        if column is not None:
            where += f", column '{column}'"
        if key is not None:
            where += f": {key}"
        super().__init__(f"{where}: {message}")

    def __reduce__(self) -> tuple[object, ...]:
        """Pickle support (errors cross process pools): rebuild from the constructor args."""
        return (_input_file_error, (self.path, self.detail, self.row, self.column, self.key))


def _input_file_error(
    path: str, message: str, row: int | None, column: str | None, key: str | None = None
) -> InputFileError:
    return InputFileError(path, message, row=row, column=column, key=key)


class InputFileProblemsError(InputFileError):
    """Every problem found in checking an input file (a robot file and the files it names).

    Each problem is an :class:`InputFileError` of one line; the message is their lines, one
    per problem, and the CLI prints each as its own ``zmpkit: error:`` line. ``path``,
    ``row``, ``column``, ``key`` and ``detail`` are the first problem's.

    Args:
        problems: the problems, at least one; groups among them are flattened.
    """

    def __init__(self, problems: Iterable[InputFileError]) -> None:
        self.problems: tuple[InputFileError, ...] = tuple(_flatten(problems))
        if not self.problems:
            raise ValueError("InputFileProblemsError needs at least one problem")
        first = self.problems[0]
        self.path, self.row, self.column = first.path, first.row, first.column
        self.key, self.detail = first.key, first.detail
        Exception.__init__(self, "\n".join(str(p) for p in self.problems))

    def __reduce__(self) -> tuple[object, ...]:
        """Pickle support (errors cross process pools): rebuild from the problems."""
        return (InputFileProblemsError, (self.problems,))


def _flatten(problems: Iterable[InputFileError]) -> Iterable[InputFileError]:
    for problem in problems:
        if isinstance(problem, InputFileProblemsError):
            yield from problem.problems
        else:
            yield problem


def problem_lines(error: ZmpkitError) -> tuple[str, ...]:
    """The lines a user reads for ``error``: one per problem of a group, else its message."""
    if isinstance(error, InputFileProblemsError):
        return tuple(str(p) for p in error.problems)
    return (str(error),)


class SimulationDivergedError(ZmpkitError, RuntimeError):
    """A simulation left its valid state; says when and where.

    Args:
        time_s: simulated time of the divergence [s].
        where: the joint or quantity that diverged.
        message: what was seen.
    """

    def __init__(self, time_s: float, where: str, message: str) -> None:
        self.time_s = time_s
        self.where = where
        self.detail = message
        super().__init__(f"simulation diverged at t = {time_s:.4f} s in {where}: {message}")

    def __reduce__(self) -> tuple[object, ...]:
        """Pickle support (errors cross process pools): rebuild from the constructor args."""
        return (SimulationDivergedError, (self.time_s, self.where, self.detail))
