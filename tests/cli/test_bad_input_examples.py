"""Every bad input of issue 16, as a new user gave it, with the message it now gets.

Each ended badly before: a traceback, a non-finite number written with exit 0, a silent
misreading, a refusal without line or column, a 1611-character message, a robot leaning off
its feet, an empty output folder left behind.
"""

from __future__ import annotations

import csv
import tomllib
from pathlib import Path

import numpy as np
import pytest

from helpers.ft_data import FEET_YAML
from zmpkit.analysis.figure import new_figure, save_figure
from zmpkit.cli import main
from zmpkit.errors import FigureWarning, NonFiniteResultError
from zmpkit.io import FT_LOG_COLUMNS, check_zmp_finite, read_feet_yaml, read_ft_log_csv
from zmpkit.sensors import ZmpSeries

HEADER = ",".join(FT_LOG_COLUMNS)
STANDING = "0.5,-0.2,-300.0,1.0,-2.0,0.0,-0.3,0.1,-310.0,-1.5,2.5,0.1"  # both feet loaded


@pytest.fixture
def feet(tmp_path: Path) -> Path:
    path = tmp_path / "feet.yaml"
    path.write_text(FEET_YAML)
    return path


def _zmp(tmp_path: Path, feet: Path, text: str | bytes, *extra: str) -> tuple[int, str, Path]:
    log = tmp_path / "log.csv"
    if isinstance(text, bytes):
        log.write_bytes(text)
    else:
        log.write_text(text)
    out = tmp_path / "out"
    code = main(["zmp", str(log), "--feet", str(feet), *extra, "--out", str(out)])
    return code, str(log), out


def _one_line(capsys: pytest.CaptureFixture[str]) -> str:
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1, err
    assert "Traceback" not in err
    return err


def _zmp_rows(out: Path) -> list[dict[str, str]]:
    with (out / "zmp.csv").open() as f:
        return list(csv.DictReader(f))


# --- forces beyond any F-T sensor and a vanishing contact threshold ---------------------


@pytest.mark.parametrize("value", ["1.7e308", "-1.7e308"])
def test_extreme_cell_is_refused_not_plotted(
    tmp_path: Path, feet: Path, capsys: pytest.CaptureFixture[str], value: str
) -> None:
    cells = STANDING.split(",")
    cells[2] = value  # right_fz
    code, log, out = _zmp(tmp_path, feet, f"{HEADER}\n0.0,{STANDING}\n0.01,{','.join(cells)}\n")
    assert code == 2
    assert _one_line(capsys) == (
        f"zmpkit: error: {log}, column 'right_fz': {float(value):.4g} N at sample 2 "
        "(t = 0.01 s) is beyond the plausible ±100000 N of a foot F-T sensor"
    )
    assert not out.exists()


def test_overflowing_moment_row_is_refused_not_written_as_inf(
    tmp_path: Path, feet: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    row = "0.01,1.79e308,0,100,0,1.79e308,0,0,0,100,0,0,0"
    code, log, out = _zmp(tmp_path, feet, f"{HEADER}\n{row}\n")
    assert code == 2
    assert _one_line(capsys) == (
        f"zmpkit: error: {log}, column 'right_fx': 1.79e+308 N at sample 1 (t = 0.01 s) is "
        "beyond the plausible ±100000 N of a foot F-T sensor"
    )
    assert not out.exists()


def test_vanishing_contact_threshold_is_refused(
    tmp_path: Path, feet: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    text = f"{HEADER}\n0.0,0,0,-1e-300,1,1,0,0,0,0,0,0,0\n"
    code, _, out = _zmp(tmp_path, feet, text, "--contact-threshold", "1e-300")
    assert code == 2
    assert _one_line(capsys) == (
        "zmpkit: error: zmpkit zmp: Invalid value for '--contact-threshold': must lie in "
        "[0.01, 10000] N, got 1e-300 (see 'zmpkit zmp --help')"
    )
    assert not out.exists()


def test_non_finite_zmp_is_never_written_and_names_the_row() -> None:
    series = ZmpSeries(
        time=np.array([0.0, 0.01]),
        zmp=np.array([[0.01, 0.0], [-np.inf, 0.0]]),
        defined=np.array([True, True]),
        contact_right=np.array([True, True]),
        contact_left=np.array([False, False]),
        fz_right=np.array([300.0, 300.0]),
        fz_left=np.array([0.0, 0.0]),
    )
    with pytest.raises(NonFiniteResultError) as info:
        check_zmp_finite(series)
    assert str(info.value) == (
        "zmp.csv, row 3: the ZMP at t = 0.01 s is (-inf, 0.0) m, not finite; nothing written"
    )


def test_figure_that_cannot_be_drawn_is_a_warning_and_a_placeholder(tmp_path: Path) -> None:
    fig, ax = new_figure()
    ax.plot([0.0, 0.01], [0.0, 1.7e308])
    ax.plot([0.0, 0.01], [0.0, -1.7e308])
    with (
        np.errstate(over="ignore"),
        pytest.warns(FigureWarning, match=r"could not draw zmp.png \("),
    ):
        path = save_figure(fig, tmp_path / "zmp.png")
    assert path.stat().st_size > 1000  # the placeholder that says why


# --- the CSV reader ------------------------------------------------------------------


def test_duplicated_header_is_refused_naming_both_columns(
    tmp_path: Path, feet: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    code, log, _ = _zmp(tmp_path, feet, f"{HEADER},right_fx\n0.0,{STANDING},7\n")
    assert code == 2
    assert _one_line(capsys) == (
        f"zmpkit: error: {log}, line 1: the header names 'right_fx' twice (columns 2 and 14); "
        "each column needs its own name"
    )


def test_column_map_sending_two_roles_to_one_header_is_refused(
    tmp_path: Path, feet: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    columns = tmp_path / "columns.yaml"
    columns.write_text("right_fz: left_fz\n")
    code, _, _ = _zmp(tmp_path, feet, f"{HEADER}\n0.0,{STANDING}\n", "--columns", str(columns))
    assert code == 2
    assert _one_line(capsys) == (
        f"zmpkit: error: {columns}: ambiguous column map: both 'right_fz' and 'left_fz' read "
        "the header 'left_fz'; each column needs its own header"
    )


def test_byte_order_mark_is_read(tmp_path: Path, feet: Path) -> None:
    plain = tmp_path / "plain.csv"
    plain.write_text(f"{HEADER}\n0.0,{STANDING}\n")
    code, _, out = _zmp(tmp_path, feet, b"\xef\xbb\xbf" + plain.read_bytes())
    assert code == 0
    assert _zmp_rows(out)[0]["zmp_x"] != ""
    bom = read_ft_log_csv(tmp_path / "log.csv")
    assert np.array_equal(bom.right_wrench, read_ft_log_csv(plain).right_wrench)


def test_fully_quoted_csv_is_read_and_a_bad_quoted_cell_is_located(
    tmp_path: Path, feet: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    quoted = ",".join(f'"{c}"' for c in f"0.0,{STANDING}".split(","))
    header = ",".join(f'"{c}"' for c in FT_LOG_COLUMNS)
    code, _, out = _zmp(tmp_path, feet, f"{header}\n{quoted}\n")
    assert code == 0
    assert float(_zmp_rows(out)[0]["time"]) == 0.0
    code, log, _ = _zmp(tmp_path, feet, f"{header}\n{quoted}\n{quoted.replace('0.0', 'x', 1)}\n")
    assert code == 2
    assert _one_line(capsys).endswith(f"{log}, line 3, column 'time': expected a number, got 'x'")


def test_long_header_is_listed_briefly(
    tmp_path: Path, feet: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    header = ",".join(f"channel_{k:03d}_with_a_long_name" for k in range(60))
    code, log, _ = _zmp(tmp_path, feet, f"{header}\n" + ",".join(["0"] * 60) + "\n")
    assert code == 2
    err = _one_line(capsys)
    assert err == (
        f"zmpkit: error: {log}, line 1: missing column 'time'; the header has: "
        "channel_000_with_a_long_name, channel_001_with_a_long_name, "
        "channel_002_with_a_long_name, channel_003_with_a_long_name and 56 more"
    )
    assert len(err.replace(log, "LOG")) < 200


def test_yaml_exponent_without_dot_is_a_number(tmp_path: Path) -> None:
    path = tmp_path / "feet.yaml"
    path.write_text(FEET_YAML.replace("sole_height: 0.010}", "sole_height: 3e-2}", 1))
    assert read_feet_yaml(path)["right"].sole_height == pytest.approx(0.03)


# --- options with a physical meaning -----------------------------------------------------


def test_walking_backwards_is_refused(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["walk", "--speed", "-1", "--out", str(tmp_path / "out")]) == 2
    assert _one_line(capsys) == (
        "zmpkit: error: WalkConfig.speed_mps (forward) must lie in [0.0, 0.48] m/s, got -1.0 m/s"
    )
    assert not (tmp_path / "out").exists()


def test_targets_off_the_feet_are_refused_naming_the_reach(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    out = tmp_path / "out"
    assert main(["sim", "push", "--targets", "0:0.5:0.1", "--out", str(out)]) == 2
    assert _one_line(capsys) == (
        "zmpkit: error: ZMP target 0.2 m lies outside teo's support polygon in the sagittal "
        "plane; reachable targets lie in (-0.07, 0.175) m"
    )
    assert not out.exists()


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["sim", "push", "--hold", "0"], "Invalid value for '--hold': must lie in (0, 600] s"),
        (["sim", "push", "--workers", "0"], "Invalid value for '--workers': must lie in [1, 256]"),
        (["sim", "push", "--push-force", "nan"], "'--push-force': must lie in [-2000, 2000] N"),
        (["identify", "balance", "d", "--length", "-1"], "'--length': must lie in (0, 5] m"),
        (["identify", "sim", "--self-test", "--generations", "0"], "must lie in [1, 100000]"),
        (["identify", "sim", "--self-test", "--popsize", "2"], "must lie in [4, 65536]"),
        (["identify", "sim", "--self-test", "--restarts", "10"], "must lie in [0, 9]"),
        (
            ["identify", "sim", "--self-test", "--popsize", "4096", "--restarts", "5"],
            "with this popsize restarts must lie in [0, 4]",
        ),
        (["walk", "--step-duration", "0.05"], "step_duration_s must lie in [0.2, 2.0] s"),
        (["walk", "compensate", "--speed", "1"], "speed_mps must lie in (0, 0.48] m/s"),
        (["walk", "compensate", "--workers", "300"], "workers must lie in [1, 256]; got 300"),
        (["balance", "--fault", "glitch"], "'glitch' is not one of 'dropout', 'spike', 'nan'"),
        (["balance", "--fault", "nan"], "--fault injects faults into what the ZMP feedback"),
    ],
)
def test_option_out_of_range_names_the_valid_range(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], argv: list[str], message: str
) -> None:
    out = tmp_path / "out"
    assert main([*argv, "--out", str(out)]) == 2
    assert message in _one_line(capsys)
    assert not out.exists()


def test_identify_sim_with_a_missing_folder_creates_no_output(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    out = tmp_path / "out"
    assert main(["identify", "sim", str(tmp_path / "missing"), "--out", str(out)]) == 2
    assert _one_line(capsys) == (
        f"zmpkit: error: {tmp_path / 'missing'}: expected an experiment folder (does not exist)"
    )
    assert not out.exists()


def test_mujoco_lower_bound_is_the_one_the_simulator_needs() -> None:
    import mujoco

    pyproject = Path(__file__).parents[2] / "pyproject.toml"
    dependencies = tomllib.loads(pyproject.read_text())["project"]["dependencies"]
    assert "mujoco>=4.0" in dependencies  # dcmotor, PID actuators and mujoco.batch
    assert int(mujoco.__version__.split(".")[0]) >= 4
    assert hasattr(mujoco, "batch")
