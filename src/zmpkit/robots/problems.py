"""The problems of a robot file, collected: every check runs, one error carries them all.

A check of a robot file (its layout, the model's names, the package folders, the truth)
adds each problem it finds to a :class:`Problems` list and goes on; at the end
:meth:`Problems.raise_any` raises one :class:`~zmpkit.errors.InputFileProblemsError` with
every problem, which the CLI prints one ``zmpkit: error:`` line each. A problem that makes
the later checks meaningless (no model file: no body names to check) is the caller's to stop
at.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable
from typing import ParamSpec, TypeVar

from zmpkit.errors import InputFileError, InputFileProblemsError

__all__ = ["Problems"]

T = TypeVar("T")
P = ParamSpec("P")


class Problems:
    """The problems found so far by one check (a working list, not a value object).

    Args:
        found: problems found before (groups are flattened when raised).
    """

    def __init__(self, found: Iterable[InputFileError] = ()) -> None:
        self._found: list[InputFileError] = list(found)

    def __bool__(self) -> bool:
        return bool(self._found)

    @property
    def found(self) -> tuple[InputFileError, ...]:
        """The problems found, in the order found (groups flattened)."""
        return tuple(
            single
            for problem in self._found
            for single in (
                problem.problems if isinstance(problem, InputFileProblemsError) else (problem,)
            )
        )

    def add(self, problem: InputFileError) -> None:
        """Record ``problem`` (a one-line error, or a group of them)."""
        self._found.append(problem)

    def extend(self, problems: Iterable[InputFileError]) -> None:
        """Record every one of ``problems``."""
        self._found.extend(problems)

    def attempt(self, check: Callable[P, T], *args: P.args, **kwargs: P.kwargs) -> T | None:
        """``check(*args, **kwargs)``, or None with the problem it raised recorded."""
        try:
            return check(*args, **kwargs)
        except InputFileError as exc:
            self.add(exc)
            return None

    def raise_any(self) -> None:
        """Raise every problem found as one error; nothing if none was.

        Raises:
            InputFileProblemsError: carrying the problems, one line each.
        """
        if self._found:
            raise InputFileProblemsError(self._found) from None
