"""YARP yarpdatadumper dumps: written here, read back exactly; every bad line named."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path
from typing import TypeVar

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from zmpkit.errors import InputFileError
from zmpkit.io import (
    LogUnits,
    read_ft_source,
    read_yarp_dump,
    read_yarp_ft,
    read_yarp_joints,
)

T0 = 1712345678.25


def _fmt(values: np.ndarray) -> str:
    return " ".join(repr(float(v)) for v in values)


def write_dump(
    folder: Path,
    rows: np.ndarray,
    stamps: np.ndarray,
    *,
    port: str | None = None,
    rx: np.ndarray | None = None,
    nested: bool = False,
) -> Path:
    """A yarpdatadumper folder: info.log (when ``port``) and data.log."""
    folder.mkdir(parents=True)
    if port is not None:
        kind = "tx+rx;" if rx is not None else "tx;"
        (folder / "info.log").write_text(
            f"Type: Bottle;\nStamp: {kind}\n[{T0 - 1:.6f}] {port} [connected]\n"
        )
    lines = []
    for k, (row, stamp) in enumerate(zip(rows, stamps, strict=True)):
        stamps_txt = f"{float(stamp)!r}" if rx is None else f"{float(stamp)!r} {float(rx[k])!r}"
        values = f"({_fmt(row[:3])}) ({_fmt(row[3:])})" if nested else _fmt(row)
        lines.append(f"{k} {stamps_txt} {values}")
    (folder / "data.log").write_text("\n".join(lines) + "\n")
    return folder


def _rows(n: int, sign: float = 1.0) -> np.ndarray:
    return sign * (np.arange(n * 6, dtype=float).reshape(n, 6) * 0.5 - 7.25)


def _stamps(n: int, offset: float = 0.0) -> np.ndarray:
    return T0 + offset + np.arange(n) * 0.01


def _teo(root: Path, n: int = 8, **kwargs: object) -> Path:
    write_dump(root / "jr3" / "ch0_o", _rows(n), _stamps(n), port="/jr3/ch0:o", **kwargs)
    write_dump(root / "jr3" / "ch1_o", _rows(n, -1.0), _stamps(n), port="/jr3/ch1:o", **kwargs)
    return root


def test_teo_layout_round_trip(tmp_path: Path) -> None:
    log = read_yarp_ft(_teo(tmp_path / "log"))
    np.testing.assert_array_equal(log.ft.time, _stamps(8) - T0)
    np.testing.assert_array_equal(log.ft.right_wrench, _rows(8))
    np.testing.assert_array_equal(log.ft.left_wrench, _rows(8, -1.0))
    assert log.time_origin_ns == round(T0 * 1e9)


def test_ports_found_by_folder_name_without_info_log(tmp_path: Path) -> None:
    write_dump(tmp_path / "jr3" / "ch1_o_00001", _rows(4, -1.0), _stamps(4))
    write_dump(tmp_path / "jr3" / "ch0_o", _rows(4), _stamps(4))
    ft = read_ft_source(tmp_path)
    np.testing.assert_array_equal(ft.left_wrench, _rows(4, -1.0))


def test_custom_ports_and_nested_bottles(tmp_path: Path) -> None:
    write_dump(tmp_path / "a", _rows(5), _stamps(5), port="/r:o", nested=True)
    write_dump(tmp_path / "b", _rows(5, 2.0), _stamps(5), port="/l:o", nested=True)
    ft = read_ft_source(tmp_path, right_topic="/r:o", left_topic="/l:o")
    np.testing.assert_array_equal(ft.right_wrench, _rows(5))
    np.testing.assert_array_equal(ft.left_wrench, _rows(5, 2.0))


def test_two_stamps_sender_by_default_receiver_on_request(tmp_path: Path) -> None:
    folder = write_dump(tmp_path / "d", _rows(3), _stamps(3), port="/p", rx=_stamps(3, 0.5))
    assert read_yarp_dump(folder).stamp.tolist() == _stamps(3).tolist()
    assert read_yarp_dump(folder, "receive").stamp.tolist() == _stamps(3, 0.5).tolist()
    assert read_yarp_dump(folder).stamp_kind == "tx+rx"


def test_legacy_single_file_with_both_feet(tmp_path: Path) -> None:
    both = np.hstack([_rows(4), _rows(4, 3.0)])
    body = [
        f"{k} {float(s)!r} {_fmt(r)}" for k, (s, r) in enumerate(zip(_stamps(4), both, strict=True))
    ]
    text = ["Type: Bottle;", "Source: /jr3/both:o [connected]", *body[:2], "", *body[2:]]
    (tmp_path / "data.log").write_text("\n".join(text) + "\n")
    dump = read_yarp_dump(tmp_path / "data.log")
    assert dump.port == "/jr3/both:o"
    ft = read_ft_source(tmp_path / "data.log")
    np.testing.assert_array_equal(ft.right_wrench, _rows(4))
    np.testing.assert_array_equal(ft.left_wrench, _rows(4, 3.0))


def test_units_convert_teo_moments_from_dnm(tmp_path: Path) -> None:
    units = tmp_path / "units.yaml"
    units.write_text(
        "right: {moment_unit: dN·m}\nleft: {moment_unit: dN·m, signs: [1,1,-1,1,1,1]}\n"
    )
    ft = read_ft_source(_teo(tmp_path / "log"), units=units)
    np.testing.assert_array_equal(ft.right_wrench[:, 3:], _rows(8)[:, 3:] * 0.1)
    np.testing.assert_array_equal(ft.left_wrench[:, 2], -_rows(8, -1.0)[:, 2])


def test_joint_encoders_in_degrees(tmp_path: Path) -> None:
    rows = np.array([[0.0, 90.0], [45.0, -180.0]])
    folder = write_dump(tmp_path / "enc", rows, _stamps(2), port="/teo/leftLeg/state:o")
    joints = LogUnits(joint_angle_unit="deg").apply_joints(read_yarp_joints(folder, ("a", "b")))
    np.testing.assert_allclose(joints.position, np.deg2rad(rows), rtol=1e-15)


@pytest.mark.parametrize(
    ("line", "message"),
    [
        ("2 1712345678.3 1 2 x 4 5 6", r"data.log, line 3: value 3: expected a number, got 'x'"),
        ("2 1712345678.3 1 2 nan 4 5 6", r"line 3: value 3: expected a finite number, got 'nan'"),
        ("2 1712345678.3 1 2 3", r"line 3: 3 values, but line 1 has 6; expected the same numb"),
        ("2 1712345678.26 1 2 3 4 5 6", r"line 3: stamps must be strictly increasing, but 1712"),
        ("2 1712345678.3 (1 2 3 4 5 6", r"line 3: unbalanced parentheses: 1 '\(' not closed"),
        ("2 1712345678.3 1 2 3) 4 5 6", r"line 3: unbalanced parentheses: '\)' without '\('"),
        ("two 1712345678.3 1 2 3 4 5 6", r"line 3: expected a packet number first, got 'two'"),
        ("2 t 1 2 3 4 5 6", r"line 3: stamp: expected a number, got 't'"),
        ("2", r"line 3: expected '<seq> <stamp> <values…>', got '2'"),
    ],
)
def test_bad_line_names_file_and_line(tmp_path: Path, line: str, message: str) -> None:
    folder = write_dump(tmp_path / "d", _rows(2), _stamps(2))
    with (folder / "data.log").open("a") as f:
        f.write(line + "\n")
    with pytest.raises(InputFileError, match=message):
        read_yarp_dump(folder)


def test_missing_port_lists_the_dumps(tmp_path: Path) -> None:
    write_dump(tmp_path / "jr3" / "ch0_o", _rows(2), _stamps(2), port="/jr3/ch0:o")
    write_dump(tmp_path / "other", _rows(2), _stamps(2))
    with pytest.raises(
        InputFileError,
        match=r"no dump of port '/jr3/ch1:o' found; dumps present: jr3/ch0_o \(/jr3/ch0:o\), "
        r"other \(port unknown\)",
    ):
        read_yarp_ft(tmp_path)


def test_wrong_number_of_values_per_foot(tmp_path: Path) -> None:
    _teo(tmp_path)
    write_dump(tmp_path / "x", _rows(2)[:, :5], _stamps(2), port="/jr3/ch1:o")
    with pytest.raises(InputFileError, match=r"2 dumps of port '/jr3/ch1:o' found"):
        read_yarp_ft(tmp_path)
    single = write_dump(tmp_path / "single", _rows(2), _stamps(2))
    with pytest.raises(
        InputFileError, match=r"single/data.log: expected 12 values per line \(the right wrench"
    ):
        read_yarp_ft(single)


def test_image_dump_is_refused(tmp_path: Path) -> None:
    folder = write_dump(tmp_path / "cam", _rows(2), _stamps(2))
    (folder / "info.log").write_text("Type: Image;\nStamp: tx;\n")
    with pytest.raises(
        InputFileError, match=r"info.log, line 1: dump type is 'Image;'; expected 'Bottle;'"
    ):
        read_yarp_dump(folder)


def test_empty_and_missing(tmp_path: Path) -> None:
    (tmp_path / "data.log").write_text("Type: Bottle;\n")
    with pytest.raises(InputFileError, match=r"data.log: no data lines; expected lines '<seq>"):
        read_yarp_dump(tmp_path)
    with pytest.raises(InputFileError, match=r"nope: holds no data.log|nope: not found"):
        read_yarp_ft(tmp_path / "nope")


R = TypeVar("R")


def _outcome(read: Callable[[Path], R], path: Path) -> tuple[R | None, InputFileError | None]:
    """The reader's result, or the InputFileError it raised (any other exception escapes)."""
    try:
        return read(path), None
    except InputFileError as exc:
        return None, exc


_GARBAGE_SETTINGS = settings(
    max_examples=150, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture]
)
_LINE = st.text(alphabet="0123456789 .-e()xn\t", max_size=40)


@_GARBAGE_SETTINGS
@given(data=st.binary(max_size=300))
def test_random_bytes_give_input_file_error_or_a_dump(tmp_path: Path, data: bytes) -> None:
    path = tmp_path / "data.log"
    path.write_bytes(data)
    dump, exc = _outcome(read_yarp_dump, path)
    if exc is not None:
        assert str(exc).startswith(str(path))
    else:
        assert np.all(np.isfinite(dump.values))
        assert np.all(np.diff(dump.stamp) > 0)


@_GARBAGE_SETTINGS
@given(lines=st.lists(_LINE, max_size=8))
def test_random_lines_give_input_file_error_or_a_log(tmp_path: Path, lines: list[str]) -> None:
    path = tmp_path / "data.log"
    path.write_text("\n".join(lines))
    log, exc = _outcome(read_yarp_ft, path)
    if exc is not None:
        assert str(exc).startswith(str(path))
    else:
        assert log.ft.right_wrench.shape == log.ft.left_wrench.shape == (log.ft.n_samples, 6)
