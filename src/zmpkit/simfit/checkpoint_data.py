"""The numbers of a checkpoint: its ``.npz`` arrays, and the random generators' states.

:func:`npz_bytes` writes the arrays uncompressed, numbers only; :func:`read_arrays` reads
them back without running code or unpacking anything: the file's SHA-256 must be the one
the checkpoint's JSON records, every member a plain ``.npy`` stored uncompressed (a
compressed member could unpack to any size), loaded with ``allow_pickle=False``.
:class:`ArrayFile` then hands each array out once, checked for dtype and shape, and refuses
arrays nobody took. A ``numpy.random.RandomState`` (MT19937) state is 624 words, a position
and a cached Gaussian (:func:`generator_data`, :func:`generator_state`).
"""

from __future__ import annotations

import hashlib
import io
import reprlib
import zipfile
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from zmpkit.errors import InputFileError

__all__ = [
    "ArrayFile",
    "damaged",
    "echo",
    "generator_data",
    "generator_state",
    "npz_bytes",
    "one_line",
    "read_arrays",
]

_MT_WORDS = 624
_ECHO = 60


def echo(value: object, limit: int = _ECHO) -> str:
    """A short ``repr`` of a value read from a file, safe for any nesting, for a message."""
    echoer = reprlib.Repr()
    echoer.maxlevel, echoer.maxlist, echoer.maxdict, echoer.maxstring = 2, 3, 3, 40
    text = echoer.repr(value)
    return text if len(text) <= limit else text[: limit - 3] + "..."


def damaged(path: object, message: str, key: str | None = None) -> InputFileError:
    """The error of a checkpoint file that is not as zmpkit wrote it: one line."""
    return InputFileError(path, f"{message} (damaged)", key=key)


def one_line(exc: BaseException) -> str:
    """An exception's text on one short line, for a message about a damaged file."""
    return " ".join(str(exc).split())[:80] or type(exc).__name__


class ArrayFile:
    """The arrays of a checkpoint's ``.npz``, taken by name; each must be taken once.

    Args:
        path: the file, for messages.
        arrays: its arrays by name.
    """

    def __init__(self, path: Path, arrays: dict[str, NDArray[Any]]) -> None:
        self.path = path
        self._left = dict(arrays)

    def error(self, name: str, message: str) -> InputFileError:
        """A one-line error about array ``name`` of this file."""
        return damaged(self.path, message, key=name)

    def ndim(self, name: object) -> int:
        """Dimensions of array ``name`` not yet taken; -1 if there is none."""
        array = self._left.get(name) if isinstance(name, str) else None
        return -1 if array is None else array.ndim

    def take(self, name: object, shape: tuple[int, ...], dtype: Any = np.float64) -> NDArray[Any]:
        """The array ``name``, checked for ``shape`` (-1: any length) and ``dtype``."""
        if not isinstance(name, str) or name not in self._left:
            raise damaged(self.path, f"lacks the array {echo(name)}")
        array = self._left.pop(name)
        dtype = np.dtype(dtype)
        if array.dtype != dtype:
            raise self.error(name, f"holds {array.dtype} numbers; expected {dtype}")
        fits = all(s in (-1, a) for s, a in zip(shape, array.shape, strict=False))
        if array.ndim != len(shape) or not fits:
            want = "×".join("k" if s < 0 else str(s) for s in shape) or "a single number"
            raise self.error(name, f"has shape {array.shape}; expected {want}")
        return array

    def finish(self) -> None:
        """Refuse arrays nobody took (a checkpoint holds nothing it does not use)."""
        if self._left:
            name = sorted(self._left)[0][:_ECHO]
            raise damaged(self.path, f"holds an unknown array {name!r}")


def npz_bytes(arrays: dict[str, NDArray[Any]]) -> bytes:
    """The arrays as an uncompressed ``.npz`` (as ``numpy.savez``), never pickled."""
    buffer = io.BytesIO()
    with zipfile.ZipFile(buffer, "w", zipfile.ZIP_STORED) as archive:
        for name, array in arrays.items():
            with archive.open(f"{name}.npy", "w") as member:
                np.lib.format.write_array(member, np.asanyarray(array), allow_pickle=False)
    return buffer.getvalue()


def read_arrays(path: Path, meta: object, where: Path) -> ArrayFile:
    """The arrays of ``path``, which the JSON ``where`` describes by ``meta``.

    Args:
        path: the ``.npz``.
        meta: the JSON's ``arrays``: ``file`` (the ``.npz``'s name), ``sha256``, ``names``.
        where: the JSON file, for messages.

    Raises:
        InputFileError: if the file is missing, another than the JSON's, or not a plain
            ``.npz`` of the names it lists.
    """
    if not isinstance(meta, dict) or set(meta) != {"file", "sha256", "names"}:
        raise damaged(where, "expected keys file, sha256 and names", key="arrays")
    if meta["file"] != path.name or not isinstance(meta["names"], list):
        raise damaged(where, f"expected file {path.name!r} and a list", key="arrays")
    try:
        data = path.read_bytes()
    except OSError as exc:
        raise InputFileError(path, f"cannot read the checkpoint's arrays: {exc.strerror}") from None
    if hashlib.sha256(data).hexdigest() != meta["sha256"]:
        raise InputFileError(
            path, f"does not match {where.name} (SHA-256 differs): damaged or partly copied"
        )
    arrays = _parse_npz(path, data)
    if sorted(arrays) != sorted(str(n) for n in meta["names"]):
        raise damaged(path, f"holds other arrays than {where.name} names")
    return ArrayFile(path, arrays)


def _parse_npz(path: Path, data: bytes) -> dict[str, NDArray[Any]]:
    """Every array of the ``.npz`` bytes; nothing unpickled, nothing decompressed."""
    try:
        with zipfile.ZipFile(io.BytesIO(data)) as archive:
            packed = [i.filename for i in archive.infolist() if i.compress_type]
        if packed:
            raise damaged(path, f"member {packed[0][:_ECHO]!r} is compressed")
        with np.load(io.BytesIO(data), allow_pickle=False) as npz:
            return {name: npz[name] for name in npz.files}
    except InputFileError:
        raise
    except Exception as exc:  # any failure of zipfile or numpy on these bytes: damaged
        raise damaged(path, f"not a NumPy .npz ({one_line(exc)})") from None


def generator_data(state: tuple[Any, ...], name: str) -> tuple[dict[str, int], dict[str, Any]]:
    """A ``RandomState``'s state (``get_state()``) as (JSON document, arrays ``name.*``)."""
    _, key, pos, has_gauss, cached = state
    arrays = {
        f"{name}.key": np.asarray(key, dtype=np.uint32),
        f"{name}.cached_gaussian": np.asarray(np.float64(cached)),
    }
    return {"pos": int(pos), "has_gauss": int(has_gauss)}, arrays


def generator_state(doc: object, arrays: ArrayFile, name: str, where: Path) -> tuple[Any, ...]:
    """The ``RandomState`` state :func:`generator_data` wrote, checked (for ``set_state``).

    Raises:
        InputFileError: on a position outside the 624 words, a flag not 0 or 1, a
            non-finite cached Gaussian, or all-zero words (a generator that never leaves 0).
    """
    key_name = f"random.{name.rsplit('.', 1)[-1]}"
    if not isinstance(doc, dict) or set(doc) != {"pos", "has_gauss"}:
        raise damaged(where, "expected keys pos and has_gauss", key=key_name)
    pos, has_gauss = doc["pos"], doc["has_gauss"]
    if not all(type(v) is int for v in (pos, has_gauss)) or not (
        0 <= pos <= _MT_WORDS and has_gauss in (0, 1)
    ):
        raise damaged(where, f"expected pos in [0, {_MT_WORDS}] and has_gauss 0 or 1", key=key_name)
    key = arrays.take(f"{name}.key", (_MT_WORDS,), np.uint32)
    cached = float(arrays.take(f"{name}.cached_gaussian", ()))
    if not np.isfinite(cached):
        raise arrays.error(f"{name}.cached_gaussian", "expected a finite number")
    if not np.any(key[1:]) and not key[0] & 0x80000000:
        raise arrays.error(f"{name}.key", "is all zeros: not a Mersenne Twister state")
    return ("MT19937", key.copy(), pos, has_gauss, cached)
