"""Hypothesis strategies of malformed input as a new user would give it.

Each strategy starts from a valid file or option and applies a few mutations drawn from the
mistakes people make: spreadsheet exports (a byte-order mark, quoted cells, a decimal comma),
extreme or non-finite numbers, text where a number goes, duplicated or missing columns,
short rows, time going backwards, YAML 1.1 quirks (``3e-2``), tilted mounts, odd options.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from hypothesis import strategies as st

from zmpkit.io import FT_LOG_COLUMNS

EXTREME_NUMBERS = (
    "1.7e308",
    "-1.7e308",
    "1.79e308",
    "-1.79e308",
    "1e308",
    "1e-300",
    "-1e-300",
    "5e-324",
    "0",
    "-0.0",
    "1e999",
    "nan",
    "NaN",
    "inf",
    "-inf",
    "1e6",
    "-1e6",
    "3e-2",
)
ODD_CELLS = ("", " ", "abc", '"1.5"', "'2'", "1,5", " 2 ", "0x10", "1_000", "1e", "--1", "\x00")


def number_text() -> st.SearchStrategy[str]:
    """A number as a user's file may hold it: ordinary, extreme, non-finite or odd."""
    return st.one_of(
        st.floats(allow_nan=True, allow_infinity=True).map(repr),
        st.floats(-1e4, 1e4).map(lambda x: f"{x:.6g}"),
        st.sampled_from(EXTREME_NUMBERS),
        st.sampled_from(ODD_CELLS),
        st.text(max_size=8),
    )


def _valid_rows(n: int) -> list[list[str]]:
    """``n`` rows of a standing robot, 300 N on each foot, CoP near the ankles."""
    rows = []
    for k in range(n):
        right = [0.5, -0.2, -300.0 - k, 1.0, -2.0, 0.0]  # sensor z down: F_z < 0 (FEET rpy = pi)
        left = [-0.3, 0.1, -310.0 + k, -1.5, 2.5, 0.1]
        rows.append([repr(0.01 * k)] + [repr(v) for v in right + left])
    return rows


@dataclass(frozen=True)
class CsvCase:
    """A generated F-T log: its bytes and a note of the mutations applied."""

    data: bytes
    mutations: tuple[str, ...]


@st.composite
def ft_log_csv(draw: st.DrawFn) -> CsvCase:
    """An F-T log CSV with 0 to 3 mutations of its header, cells, rows and encoding."""
    header = list(FT_LOG_COLUMNS)
    rows = _valid_rows(draw(st.integers(1, 6)))
    notes: list[str] = []
    for _ in range(draw(st.integers(0, 3))):
        kind = draw(
            st.sampled_from(
                ("cell", "cell", "cell", "header", "row", "bom", "quote", "time", "empty")
            )
        )
        notes.append(kind)
        if not rows or not rows[0]:
            break
        if kind == "cell":
            r = draw(st.integers(0, len(rows) - 1))
            c = draw(st.integers(0, len(rows[r]) - 1)) if rows[r] else 0
            if rows[r]:
                rows[r][c] = draw(number_text())
        elif kind == "header":
            how = draw(st.sampled_from(("duplicate", "drop", "rename", "upper", "space")))
            c = draw(st.integers(0, len(header) - 1))
            if how == "duplicate":
                header.append(header[c])
                for row in rows:
                    row.append("0")
            elif how == "drop":
                del header[c]
                for row in rows:
                    del row[c : c + 1]
            elif how == "rename":
                header[c] = draw(st.text(max_size=6))
            elif how == "upper":
                header[c] = header[c].upper()
            else:
                header[c] = f" {header[c]} "
            notes[-1] = f"header {how}"
        elif kind == "row":
            r = draw(st.integers(0, len(rows) - 1))
            how = draw(st.sampled_from(("short", "long", "blank", "copy")))
            if how == "short":
                rows[r] = rows[r][: draw(st.integers(0, max(len(rows[r]) - 1, 0)))]
            elif how == "long":
                rows[r] = [*rows[r], "1.0"]
            elif how == "blank":
                rows.insert(r, [])
            else:
                rows.insert(r, list(rows[r]))
            notes[-1] = f"row {how}"
        elif kind == "quote":
            rows = [[f'"{cell}"' for cell in row] for row in rows]
        elif kind == "time":
            rows.reverse()
        elif kind == "empty":
            rows = []
    text = ",".join(header) + "\n" + "".join(",".join(row) + "\n" for row in rows)
    data = text.encode("utf-8", errors="surrogatepass")
    if "bom" in notes:
        data = b"\xef\xbb\xbf" + data
    return CsvCase(data, tuple(notes))


FEET_TEMPLATE = (
    "right: {{position: [{rx}, {ry}, 0.010], rpy: [{rr}, {rp}, 0.0], sole_height: {rh}}}\n"
    "left:  {{position: [0.0,  0.1285, 0.010], rpy: [3.14159265, 0.0, 0.0], "
    "sole_height: {lh}}}\n"
)


@st.composite
def feet_yaml(draw: st.DrawFn) -> str:
    """FEET.yaml, mostly valid, with odd numbers, tilted mounts or broken YAML."""
    good = {"rx": "0.0", "ry": "-0.1285", "rr": "3.14159265", "rp": "0.0"}
    good.update(rh="0.010", lh="0.010")
    for key in draw(st.lists(st.sampled_from(sorted(good)), max_size=2)):
        good[key] = draw(
            st.one_of(
                number_text(),
                st.floats(-math.pi, math.pi).map(repr),
                st.sampled_from(("3e-2", "1E-2", "1.5e+1", ".inf", "-.Inf", ".nan", "[]")),
            )
        )
    text = FEET_TEMPLATE.format(**good)
    if draw(st.booleans()) and draw(st.integers(0, 9)) == 0:
        text = draw(st.sampled_from(("", "- a\n- b\n", "right: [\n", "right: 1\nleft: 2\n")))
    return text


@st.composite
def column_map_yaml(draw: st.DrawFn) -> str | None:
    """None (no map), or a column map: identity, two roles on one header, unknown names."""
    how = draw(st.sampled_from((None, None, "identity", "shared", "unknown", "odd")))
    if how is None:
        return None
    if how == "identity":
        return "time: time\nright_fz: right_fz\n"
    if how == "shared":
        return "right_fz: left_fz\n"
    if how == "unknown":
        return "speed: time\n"
    return draw(st.sampled_from(("time: 3\n", "time: ''\n", "[a, b]\n", "time: [a]\n")))


def threshold_option() -> st.SearchStrategy[str | None]:
    """``--contact-threshold`` as typed: absent, sane, tiny, huge, negative or not a number."""
    return st.one_of(
        st.none(),
        st.sampled_from(("10", "1e-300", "5e-324", "0", "-5", "1e308", "nan", "inf", "abc")),
        st.floats(allow_nan=True, allow_infinity=True).map(repr),
    )
