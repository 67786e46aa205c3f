"""The fuzz harness: run the CLI on generated input, judge how it ended, count the cases.

A run of ``main(argv)`` ends well when

- it returns 0 and every CSV and JSON file it wrote holds only finite numbers, or
- it returns 2 (a user mistake) with one line on stderr per problem (one, or several
  ``zmpkit: error:`` lines for a file with several problems), each of at most
  :data:`MAX_MESSAGE_CHARS` characters (temporary paths shortened), no traceback text, and
  no output folder left behind.

Anything else (another exit code, an exception escaping ``main``, a traceback, a line that
continues another, a non-finite number written) ends badly; :func:`problems` names how.

:class:`Census` counts the cases of one fuzz test and the bad endings by cause. With the
environment variable ``ZMPKIT_FUZZ_CENSUS=1`` a fuzz test records every bad ending and goes
on instead of stopping (and shrinking) at the first, so a run measures how many of a fixed
set of generated inputs end badly; it still fails at the end if any did.
"""

from __future__ import annotations

import contextlib
import io
import json
import math
import os
import re
import warnings
from collections import Counter
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from pathlib import Path

from zmpkit.cli import main
from zmpkit.errors import ZmpkitError, problem_lines

MAX_MESSAGE_CHARS = 200
ERROR_PREFIX = "zmpkit: error: "
"""How each of several lines of a failing command starts (one per problem)."""
CENSUS_MODE = os.environ.get("ZMPKIT_FUZZ_CENSUS", "") == "1"
CENSUSES: list[Census] = []
"""Every census of this session, printed in the terminal summary (tests/conftest.py)."""


@dataclass
class Outcome:
    """How one run of ``main(argv)`` ended."""

    code: int | None
    stdout: str
    stderr: str
    exception: BaseException | None = None


def run_cli(argv: Sequence[str]) -> Outcome:
    """Run ``main(argv)``, capturing its output and any exception that escapes it."""
    out, err = io.StringIO(), io.StringIO()
    code: int | None = None
    exception: BaseException | None = None
    with (
        contextlib.redirect_stdout(out),
        contextlib.redirect_stderr(err),
        warnings.catch_warnings(),
    ):
        warnings.simplefilter("ignore")
        try:
            code = main(list(argv))
        except SystemExit as exc:
            code = exc.code if isinstance(exc.code, int) else 1
            exception = exc
        except Exception as exc:
            exception = exc
    return Outcome(code, out.getvalue(), err.getvalue(), exception)


_NUMBER = re.compile(r"^[+-]?(nan|inf|infinity)$", re.IGNORECASE)


def non_finite_cells(folder: Path) -> list[str]:
    """``file:line`` of every non-finite number in the CSV and JSON files under ``folder``."""
    found = []
    for path in sorted(folder.rglob("*")):
        if path.suffix == ".csv":
            for k, line in enumerate(path.read_text(encoding="utf-8").splitlines(), start=1):
                if any(_NUMBER.match(cell.strip()) for cell in line.split(",")):
                    found.append(f"{path.name}:{k}")
        elif path.suffix == ".json":
            text = path.read_text(encoding="utf-8")
            if re.search(r"\b(NaN|-?Infinity)\b", text):
                found.append(path.name)
            else:
                _check_json_numbers(json.loads(text), path.name, found)
    return found


def _check_json_numbers(value: object, where: str, found: list[str]) -> None:
    if isinstance(value, float) and not math.isfinite(value):
        found.append(where)
    elif isinstance(value, dict):
        for v in value.values():
            _check_json_numbers(v, where, found)
    elif isinstance(value, list):
        for v in value:
            _check_json_numbers(v, where, found)


def problems(outcome: Outcome, out_dir: Path | None, tmp_root: Path) -> list[str]:
    """Ways ``outcome`` ended badly (empty: it ended well); each starts with its cause."""
    found = []
    text = outcome.stdout + outcome.stderr
    if outcome.exception is not None and not isinstance(outcome.exception, SystemExit):
        found.append(f"exception {type(outcome.exception).__name__}: {outcome.exception}"[:300])
    if "Traceback (most recent call last)" in text:
        found.append("traceback text")
    if outcome.code not in (0, 2):
        found.append(f"exit code {outcome.code}")
    if outcome.code == 2:
        lines = [line for line in outcome.stderr.splitlines() if line.strip()]
        several = len(lines) > 1 and all(line.startswith(ERROR_PREFIX) for line in lines)
        if len(lines) != 1 and not several:
            found.append(f"{len(lines)} lines on stderr")
        for line in lines:
            message = line.strip().replace(str(tmp_root), "<tmp>")
            if len(message) > MAX_MESSAGE_CHARS:
                found.append(f"message of {len(message)} characters: {message[:80]}...")
        if out_dir is not None and out_dir.exists():
            found.append("output folder created by a failing command")
    if outcome.code == 0 and out_dir is not None and out_dir.exists():
        bad = non_finite_cells(out_dir)
        if bad:
            found.append(f"non-finite number written: {', '.join(bad[:3])}")
    return found


@dataclass
class Census:
    """Cases run by one fuzz test and their bad endings, by cause."""

    name: str
    cases: int = 0
    bad: int = 0
    causes: Counter[str] = field(default_factory=Counter)
    examples: dict[str, str] = field(default_factory=dict)

    def __post_init__(self) -> None:
        CENSUSES.append(self)

    def record(self, found: list[str], case: object) -> None:
        """Count one case; in census mode keep its problems, else fail on the first one."""
        self.cases += 1
        if not found:
            return
        self.bad += 1
        cause = found[0].split(":")[0]
        self.causes[cause] += 1
        self.examples.setdefault(cause, f"{case!r}"[:400])
        if not CENSUS_MODE:
            raise AssertionError(f"{self.name}: {'; '.join(found)}\ncase: {case!r}")

    def as_plain(self) -> dict[str, object]:
        """The census as plain values (what pytest-xdist sends from a worker)."""
        return {
            "name": self.name,
            "cases": self.cases,
            "bad": self.bad,
            "causes": dict(self.causes),
            "examples": dict(self.examples),
        }

    @classmethod
    def from_plain(cls, plain: dict) -> Census:
        """A census counted elsewhere (a pytest-xdist worker), registered here."""
        return cls(
            str(plain["name"]),
            int(plain["cases"]),
            int(plain["bad"]),
            Counter(plain["causes"]),
            dict(plain["examples"]),
        )

    def summary(self) -> str:
        """One line: cases, bad endings and their distinct causes."""
        causes = ", ".join(f"{c} ×{n}" for c, n in self.causes.most_common())
        return f"{self.name}: {self.cases} cases, {self.bad} ended badly" + (
            f" ({causes})" if causes else ""
        )


def reader_problems(read: Callable[[], object], tmp_root: Path) -> list[str]:
    """Ways a reader call ends badly.

    Any exception but a :class:`ZmpkitError`, or a problem of several lines or longer than
    :data:`MAX_MESSAGE_CHARS` (``tmp_root`` shortened to ``<tmp>``): a message, or each of
    the problems an :class:`~zmpkit.errors.InputFileProblemsError` carries.
    """
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        try:
            read()
        except ZmpkitError as exc:
            found = []
            for line in problem_lines(exc):
                message = line.strip().replace(str(tmp_root), "<tmp>")
                if "\n" in message:
                    found.append(f"multi-line message: {message[:120]}")
                elif len(message) > MAX_MESSAGE_CHARS:
                    found.append(f"message of {len(message)} characters: {message[:80]}...")
            return found
        except Exception as exc:
            return [f"exception {type(exc).__name__}: {exc}"[:300]]
    return []
