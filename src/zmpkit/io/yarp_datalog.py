"""YARP ``yarpdatadumper`` dumps: ``data.log`` (+ ``info.log``) of one port, as numbers.

A dump folder holds ``data.log`` with one line per received bottle::

    <seq> <stamp> [<stamp2>] <values…>        e.g.  17 1712345678.123456 1.5 (2 3) -0.25

and ``info.log`` with ``Type: Bottle;``, ``Stamp: tx;`` / ``rx;`` / ``tx+rx;`` and one
``[time] /source/port [connected]`` line per connection. With ``tx+rx`` each line carries two
stamps, the sender's then the receiver's. The legacy single-file form has no ``info.log``;
its ``data.log`` starts with ``Type: Bottle;`` and holds ``Source: /port [connected]`` lines
between the data, and one stamp per line. Nested bottles in parentheses are flattened in
order into the value columns, and their nesting is kept in :attr:`YarpDump.layout` (every
line must nest the same way); every value must be a finite number.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from zmpkit.errors import InputFileError, ParameterError

__all__ = ["YarpDump", "declared_port", "read_yarp_dump"]

_TOKEN = re.compile(r"\(|\)|[^\s()]+")
_ATOM = re.compile(r"[^\s()]+")

Layout = tuple["int | Layout", ...]
"""Nesting of a line's values: nested tuples whose leaves are value column indices."""
_CONNECTED = re.compile(r"^(?:\[[^\]]*\]|Source:)\s*(\S+)\s+\[connected\]\s*$")
_STAMP_KINDS = {"tx;": "tx", "rx;": "rx", "tx+rx;": "tx+rx"}


@dataclass(frozen=True)
class YarpDump:
    """The numeric content of one port's dump.

    Attributes:
        stamp: the chosen stamp of each line, strictly increasing [s] (YARP clock, usually
            Unix time), shape (N,).
        seq: the packet number of each line, shape (N,).
        values: the bottle of each line flattened, shape (N, K).
        port: the source port from ``info.log`` or a legacy ``Source:`` line, or "".
        stamp_kind: "tx", "rx" or "tx+rx" as ``info.log`` says; "" when it does not.
        source: the ``data.log`` file.
        layout: the nesting of every line's values, e.g. ``((0, 1, 2), (3, 4, 5))`` for
            ``(f_x f_y f_z) (τ_x τ_y τ_z)``; ``(0, 1, …, K−1)`` for flat lines.
        first_line: the line number of the first data line (1-based), for messages.
    """

    stamp: NDArray[np.float64]
    seq: NDArray[np.int64]
    values: NDArray[np.float64]
    port: str
    stamp_kind: str
    source: str
    layout: Layout = ()
    first_line: int = 1


@dataclass(frozen=True)
class _Info:
    port: str = ""
    stamp_kind: str = ""


def read_yarp_dump(path: str | Path, time_source: str = "header") -> YarpDump:
    """Read one ``yarpdatadumper`` dump.

    Args:
        path: the dump folder, or its ``data.log`` (also the legacy single file).
        time_source: with two stamps per line, "header" takes the sender's (tx) and
            "receive" the receiver's (rx); with one stamp, that one is used.

    Raises:
        InputFileError: missing file, not text, a line that is not ``<seq> <stamp> <values…>``,
            unbalanced parentheses, a non-numeric or non-finite value, lines of different
            lengths or nesting, stamps not strictly increasing — naming the file and line.
    """
    if time_source not in ("header", "receive"):
        raise ParameterError(f"time_source must be 'header' or 'receive', got {time_source!r}")
    path = Path(path)
    data_path = path / "data.log" if path.is_dir() else path
    info = (
        _read_info(data_path.parent / "info.log")
        if path.is_dir() or data_path.name == "data.log"
        else _Info()
    )
    lines = _read_lines(data_path)
    legacy = _legacy_info(lines)
    info = _Info(info.port or legacy.port, info.stamp_kind)
    if info.stamp_kind == "" and legacy.stamp_kind:
        info = _Info(info.port, legacy.stamp_kind)
    n_stamps = 2 if info.stamp_kind == "tx+rx" else 1
    pick = 1 if n_stamps == 2 and time_source == "receive" else 0
    seq, stamp, values, first = _parse_lines(data_path, lines, n_stamps, pick)
    layout = _layout(lines[first - 1], 1 + n_stamps)
    return YarpDump(stamp, seq, values, info.port, info.stamp_kind, str(data_path), layout, first)


def _read_lines(path: Path) -> list[str]:
    try:
        text = path.read_bytes().decode("utf-8")
    except FileNotFoundError:
        raise InputFileError(path, "file not found; expected a yarpdatadumper data.log") from None
    except IsADirectoryError:
        raise InputFileError(
            path, "is a folder without data.log; expected a yarpdatadumper dump"
        ) from None
    except (OSError, UnicodeDecodeError) as exc:
        raise InputFileError(path, f"cannot be read as UTF-8 text ({exc})") from None
    return text.splitlines()


def _read_info(path: Path) -> _Info:
    if not path.is_file():
        return _Info()
    lines = _read_lines(path)
    info = _legacy_info(lines)
    for no, line in enumerate(lines, start=1):
        if line.startswith("Type:") and "Bottle" not in line:
            raise InputFileError(
                path, f"dump type is {line[5:].strip()!r}; expected 'Bottle;' (numbers)", row=no
            )
    return info


def _legacy_info(lines: list[str]) -> _Info:
    port, kind = "", ""
    for line in lines:
        if line.startswith("Stamp:"):
            kind = _STAMP_KINDS.get(line[6:].strip(), "")
        elif not port and (m := _CONNECTED.match(line)):
            port = m.group(1)
    return _Info(port, kind)


def declared_port(folder: Path) -> str:
    """The source port a dump folder's ``info.log`` (or legacy ``data.log``) names, or ""."""
    for name in ("info.log", "data.log"):
        try:
            with (folder / name).open(encoding="utf-8", errors="replace") as f:
                head = [next(f, "") for _ in range(20)]
        except OSError:
            continue
        if port := _legacy_info(head).port:
            return port
    return ""


def _is_meta(line: str) -> bool:
    stripped = line.strip()
    return not stripped or stripped.startswith(("Type:", "Stamp:", "Source:"))


def _parse_lines(
    path: Path, lines: list[str], n_stamps: int, pick: int
) -> tuple[NDArray[np.int64], NDArray[np.float64], NDArray[np.float64], int]:
    seqs: list[int] = []
    stamps: list[float] = []
    rows: list[list[float]] = []
    first_line = 0
    first_shape = ""
    for no, line in enumerate(lines, start=1):
        if _is_meta(line):
            continue
        seq, line_stamps, values = _parse_line(path, no, line, n_stamps)
        if rows and len(values) != len(rows[0]):
            raise InputFileError(
                path,
                f"{len(values)} values, but line {first_line} has {len(rows[0])}; "
                "expected the same number on every line (truncated file?)",
                row=no,
            )
        shape = _shape(line)
        if rows and shape != first_shape:
            raise InputFileError(
                path,
                f"the bottle nests as {shape or 'a flat list'!r}, but line {first_line} as "
                f"{first_shape or 'a flat list'!r}; expected the same nesting on every line",
                row=no,
            )
        if stamps and line_stamps[pick] <= stamps[-1]:
            raise InputFileError(
                path,
                f"stamps must be strictly increasing, but {_stamp(line_stamps[pick])} s "
                f"follows {_stamp(stamps[-1])} s",
                row=no,
            )
        if not rows:
            first_line, first_shape = no, shape
        seqs.append(seq)
        stamps.append(line_stamps[pick])
        rows.append(values)
    if not rows:
        raise InputFileError(path, "no data lines; expected lines '<seq> <stamp> <values…>'")
    seq_array = np.array(seqs, dtype=np.int64)
    return seq_array, np.array(stamps), np.array(rows, dtype=np.float64), first_line


def _shape(line: str) -> str:
    """The nesting of a line with every number replaced by ``n``; "" for a flat line."""
    if "(" not in line and ")" not in line:
        return ""
    return "".join(_ATOM.sub("n", line).split())


def _layout(line: str, n_prefix: int) -> Layout:
    """The nesting of a (checked) line's values, leaves numbered from 0 in order.

    The first ``n_prefix`` numbers (packet number and stamps) are not values.
    """
    stack: list[list[int | Layout]] = [[]]
    k = 0
    for token in _TOKEN.findall(line):
        if token == "(":
            stack.append([])
        elif token == ")":
            inner = stack.pop()
            stack[-1].append(_freeze(inner))
        else:
            if k >= n_prefix:
                stack[-1].append(k - n_prefix)
            k += 1
    return _freeze(stack[0])


def _freeze(items: list[int | Layout]) -> Layout:
    return tuple(items)


def _parse_line(
    path: Path, no: int, line: str, n_stamps: int
) -> tuple[int, list[float], list[float]]:
    tokens = line.split() if "(" not in line and ")" not in line else _flatten(path, no, line)
    if len(tokens) < 2 + n_stamps:
        expected = (
            "<seq> <stamp> <stamp2> <values…>" if n_stamps == 2 else "<seq> <stamp> <values…>"
        )
        raise InputFileError(path, f"expected '{expected}', got {line.strip()[:60]!r}", row=no)
    try:
        seq = int(tokens[0])
    except ValueError:
        raise InputFileError(
            path, f"expected a packet number first, got {tokens[0][:30]!r}", row=no
        ) from None
    stamps = [_number(path, no, "stamp", t) for t in tokens[1 : 1 + n_stamps]]
    values = [_number(path, no, f"value {i}", t) for i, t in enumerate(tokens[1 + n_stamps :], 1)]
    return seq, stamps, values


def _number(path: Path, no: int, what: str, token: str) -> float:
    try:
        x = float(token)
    except ValueError:
        raise InputFileError(
            path, f"{what}: expected a number, got {token[:30]!r}", row=no
        ) from None
    if not math.isfinite(x):
        raise InputFileError(path, f"{what}: expected a finite number, got {token[:30]!r}", row=no)
    return x


def _stamp(seconds: float) -> str:
    """A stamp [s] for a message: microseconds shown, but never hundreds of digits."""
    return f"{seconds:.6f}" if abs(seconds) < 1e12 else f"{seconds:.6g}"


def _flatten(path: Path, no: int, line: str) -> list[str]:
    """Tokens of a line with nested bottles, parentheses removed after checking balance."""
    depth = 0
    tokens = []
    for token in _TOKEN.findall(line):
        if token == "(":
            depth += 1
        elif token == ")":
            depth -= 1
            if depth < 0:
                raise InputFileError(path, "unbalanced parentheses: ')' without '('", row=no)
        else:
            tokens.append(token)
    if depth:
        raise InputFileError(path, f"unbalanced parentheses: {depth} '(' not closed", row=no)
    return tokens
