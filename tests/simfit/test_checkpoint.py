"""The fit's checkpoint as data (format 2): a round trip keeps everything, a resume at any
generation ends as the uninterrupted fit, damage, older formats and other fits are refused
in one line, and nothing in a checkpoint folder is ever unpickled."""

from __future__ import annotations

import json
import pickle
import shutil
import zipfile
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from helpers.checkpoints import (
    npz_of,
    read_pair,
    rewrite,
    sphere_problem,
    trap_npz,
    trap_payload,
    write_fit,
)
from helpers.fuzz import run_cli
from zmpkit.errors import InputFileError, ParameterError
from zmpkit.simfit.checkpoint import (
    ARRAYS_FILE,
    CHECKPOINT_FILE,
    CHECKPOINT_FORMAT,
    OLD_CHECKPOINT_FILE,
    check_fingerprint,
    load_checkpoint,
    save_checkpoint,
)
from zmpkit.simfit.cma_state import strategy_data
from zmpkit.simfit.optimizer import CmaOptions, FitInterruptedError, fingerprint, run_cma

OPTIONS = {"generations": 4, "popsize": 6, "restarts": 1, "seed": 3}


@pytest.fixture(scope="module")
def fit_folder(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A finished sphere fit of two runs (its checkpoint: generation 8, run 1)."""
    folder = tmp_path_factory.mktemp("sphere_fit")
    write_fit(folder, **OPTIONS)
    return folder


@pytest.fixture
def folder(fit_folder: Path, tmp_path: Path) -> Path:
    """A copy of the fit's folder to damage."""
    return Path(shutil.copytree(fit_folder, tmp_path / "fit"))


def _same_strategy(a: Any, b: Any) -> None:
    doc_a, arrays_a = strategy_data(a)
    doc_b, arrays_b = strategy_data(b)
    assert doc_a == doc_b
    assert arrays_a.keys() == arrays_b.keys()
    for name, array in arrays_a.items():
        assert array.dtype == arrays_b[name].dtype
        assert np.array_equal(array, arrays_b[name], equal_nan=True), name


def test_a_round_trip_keeps_every_field(fit_folder: Path, tmp_path: Path) -> None:
    first = load_checkpoint(fit_folder)
    assert (first.generation, first.restart, first.run_start) == (8, 1, 4)
    save_checkpoint(first, tmp_path)
    again = load_checkpoint(tmp_path)
    for name in ("fingerprint", "generation", "history", "restart", "run_start"):
        assert getattr(again, name) == getattr(first, name), name
    assert again.best_unit == first.best_unit
    assert again.best_cost == first.best_cost
    assert again.best_restart == first.best_restart
    assert again.best_run_std == first.best_run_std
    for a, b in (
        (first.rng_state, again.rng_state),
        (first.draws.get_state(), again.draws.get_state()),
    ):
        assert a[0] == b[0]
        assert np.array_equal(a[1], b[1])
        assert a[2:] == b[2:]
    _same_strategy(first.strategy, again.strategy)


def test_the_checkpoint_is_json_and_plain_arrays(fit_folder: Path) -> None:
    doc = json.loads((fit_folder / CHECKPOINT_FILE).read_text(), parse_constant=_refuse_constant)
    assert doc["format"] == CHECKPOINT_FORMAT
    assert doc["fingerprint"]["seed"] == OPTIONS["seed"]
    with zipfile.ZipFile(fit_folder / ARRAYS_FILE) as archive:
        members = archive.infolist()
    assert all(m.compress_type == zipfile.ZIP_STORED for m in members)
    assert sorted(m.filename.removesuffix(".npy") for m in members) == doc["arrays"]["names"]
    _, arrays = read_pair(fit_folder)  # allow_pickle=False: no object array in there
    assert {a.dtype.kind for a in arrays.values()} <= set("biuf")
    assert sorted(p.name for p in fit_folder.iterdir()) == [
        "checkpoint.json",
        "checkpoint.npz",
        "history.json",
    ]  # no temporary file left behind, no pickle


def _refuse_constant(name: str) -> float:
    raise AssertionError(f"non-standard JSON constant {name} in the checkpoint")


class _StopAt:
    """A progress callback that presses Ctrl-C after the ``k``-th generation."""

    def __init__(self, k: int) -> None:
        self.k = k

    def __call__(self, progress: Any) -> None:
        if progress.generation == self.k:
            raise KeyboardInterrupt


@pytest.mark.slow
def test_a_fit_resumed_after_any_generation_ends_as_the_uninterrupted_one(tmp_path: Path) -> None:
    """Population 4: cma's selective mirrors carry directions from one generation to the
    next; two restarts: a resume before, at and after each switch of run."""
    from helpers.checkpoints import SphereEvaluator

    options = CmaOptions(generations=3, popsize=4, restarts=2, seed=5)
    problem = sphere_problem(2)
    whole = run_cma(problem, SphereEvaluator(), options, tmp_path / "whole")
    expected = [(r.restart, r.popsize, r.best_cost, r.median_cost, r.sigma) for r in whole.history]
    assert len(expected) == 9
    for k in range(1, len(expected)):
        cut = tmp_path / f"cut{k}"
        with pytest.raises(FitInterruptedError):
            run_cma(problem, SphereEvaluator(), options, cut, progress=_StopAt(k))
        resumed = run_cma(problem, SphereEvaluator(), options, cut, resume=cut)
        got = [(r.restart, r.popsize, r.best_cost, r.median_cost, r.sigma) for r in resumed.history]
        assert got == expected, k
        assert np.array_equal(resumed.best_values, whole.best_values)
        assert np.array_equal(resumed.unit_std, whole.unit_std)


def _set(path: str, value: Any) -> Callable[[dict, dict], Any]:
    def mutate(doc: dict, arrays: dict) -> None:
        *parents, last = path.split("/")
        target: Any = doc
        for p in parents:
            target = target[int(p)] if isinstance(target, list) else target[p]
        if value is KeyError:
            del target[last]
        else:
            target[int(last) if isinstance(target, list) else last] = value

    return mutate


def _array(name: str, change: Callable[[np.ndarray], np.ndarray | None]) -> Callable:
    def mutate(doc: dict, arrays: dict) -> None:
        if change is KeyError:
            del arrays[name]
            return
        array = arrays[name].copy()
        new = change(array)
        arrays[name] = array if new is None else new

    return mutate


def _poke(index: tuple, value: float) -> Callable[[np.ndarray], None]:
    def change(array: np.ndarray) -> None:
        array[index] = value

    return change


DAMAGE = [
    (
        "NaN in the covariance",
        _array("strategy.sm.C", _poke((0, 0), np.nan)),
        r"checkpoint\.npz: strategy\.sm\.C: holds NaN or infinity; expected finite numbers",
    ),
    (
        "infinity in the mean",
        _array("strategy.mean", _poke((1,), np.inf)),
        r"strategy\.mean: holds NaN or infinity",
    ),
    (
        "NaN in a cost history",
        _array("strategy.fit.hist", _poke((0,), np.nan)),
        r"strategy\.fit\.hist: holds NaN or a negative cost",
    ),
    (
        "NaN in the random state",
        _array("random.global.cached_gaussian", lambda a: np.array(np.nan)),
        r"random\.global\.cached_gaussian: expected a finite number",
    ),
    (
        "a covariance of the wrong shape",
        _array("strategy.sm.C", lambda a: a[:, :2].copy()),
        r"strategy\.sm\.C: has shape \(3, 2\); expected 3×3",
    ),
    (
        "a mean of integers",
        _array("strategy.mean", lambda a: a.astype(np.int64)),
        r"strategy\.mean: holds int64 numbers; expected float64",
    ),
    (
        "a negative step size",
        _array("strategy.sigma", lambda a: -a),
        r"strategy\.sigma: expected positive numbers",
    ),
    (
        "an asymmetric covariance",
        _array("strategy.sm.C", _poke((0, 1), 5.0)),
        r"expected a symmetric covariance matrix",
    ),
    (
        "an all-zero generator",
        _array("random.draws.key", lambda a: np.zeros_like(a)),
        r"random\.draws\.key: is all zeros",
    ),
    ("an array missing", _array("strategy.pc", KeyError), r"lacks the array 'strategy\.pc'"),
    (
        "an unknown array",
        lambda doc, arrays: arrays.update(extra=np.zeros(3)),
        r"holds an unknown array 'extra'",
    ),
    ("a key missing", _set("history", KeyError), r"checkpoint\.json: lacks the key 'history'"),
    ("an unknown key", _set("pickle", 1), r"unknown key 'pickle'"),
    ("a count as text", _set("generation", "8"), r"generation: expected an integer >= 0"),
    (
        "a state entry missing",
        _set("strategy/state/countiter", KeyError),
        r"lacks the entry 'countiter'",
    ),
    (
        "an unknown state entry",
        _set("strategy/state/opts", {"array": "x", "type": "list"}),
        r"unknown entry 'opts'",
    ),
    ("a count negative", _set("strategy/state/countevals", -4), r"countevals: expected an integer"),
    (
        "a flag as a number",
        _set("strategy/state/adapt_sigma.is_initialized", 1),
        r"is_initialized: expected true or false",
    ),
    (
        "a type unknown",
        _set("strategy/state/mean/type", "object"),
        r"state\.mean: type 'object'; expected ndarray",
    ),
    (
        "an array where cma appends to a list",
        _set("strategy/state/fit.hist/type", "ndarray"),
        r"state\.fit\.hist: type 'ndarray'; expected list \(damaged\)",
    ),
    (
        "NaN in the history",
        _set("history/0/sigma", float("nan")),
        r"history\[0\]\.sigma: expected a positive step size",
    ),
    (
        "a history record short",
        _set("history/2/wall_s", KeyError),
        r"history\[2\]: lacks the field 'wall_s' \(damaged\)",
    ),
    (
        "another format",
        _set("format", "zmpkit-simfit-checkpoint/1"),
        r"of another zmpkit version \(format 'zmpkit-simfit-checkpoint/1'\)",
    ),
    ("not a checkpoint", _set("format", ["x"]), r"not a zmpkit fit checkpoint"),
    ("another cma", _set("cma", "0.0.1"), r"written with cma '0\.0\.1' \(this Python has cma"),
    ("arrays elsewhere", _set("arrays/file", "../../secret.npz"), r"arrays: expected file"),
]


@pytest.mark.parametrize(("mutate", "pattern"), [d[1:] for d in DAMAGE], ids=[d[0] for d in DAMAGE])
def test_a_damaged_checkpoint_is_refused_in_one_line(
    folder: Path, mutate: Callable, pattern: str
) -> None:
    doc, arrays = read_pair(folder)
    mutate(doc, arrays)
    rewrite(folder, doc, npz_of(arrays))
    with pytest.raises(InputFileError, match=pattern) as caught:
        load_checkpoint(folder)
    assert "\n" not in str(caught.value)
    assert len(str(caught.value).replace(str(folder), "<tmp>")) <= 200


def test_a_checkpoint_damaged_on_disk_is_refused(folder: Path) -> None:
    doc, arrays = read_pair(folder)
    rewrite(folder, doc, npz_of({**arrays, "strategy.mean": arrays["strategy.mean"] + 0.1}),
            rehash=False)  # fmt: skip
    with pytest.raises(InputFileError, match=r"checkpoint\.npz: does not match checkpoint\.json"):
        load_checkpoint(folder)
    npz = npz_of(arrays)
    rewrite(folder, doc, npz[: len(npz) // 2])  # truncated, its own hash recorded
    pattern = r"checkpoint\.npz: not a NumPy \.npz \(.*\) \(damaged\)"
    with pytest.raises(InputFileError, match=pattern):
        load_checkpoint(folder)
    text = (folder / CHECKPOINT_FILE).read_text()
    (folder / CHECKPOINT_FILE).write_text(text[: len(text) // 3])
    with pytest.raises(InputFileError, match=r"checkpoint\.json: not JSON \(.*\) \(damaged\)"):
        load_checkpoint(folder)
    (folder / CHECKPOINT_FILE).unlink()
    with pytest.raises(InputFileError, match=r"checkpoint\.json: no checkpoint here"):
        load_checkpoint(folder)


def test_a_compressed_member_is_not_unpacked(folder: Path) -> None:
    doc, arrays = read_pair(folder)
    packed = folder / "packed.npz"
    np.savez_compressed(packed, **arrays)
    rewrite(folder, doc, packed.read_bytes())
    with pytest.raises(InputFileError, match=r"member '.*\.npy' is compressed"):
        load_checkpoint(folder)


def test_the_trap_payload_is_live(tmp_path: Path) -> None:
    """The payload the next tests plant does run code when unpickled (so they mean it)."""
    marker = tmp_path / "ran"
    pickle.loads(trap_payload(marker))  # the test's own payload, on purpose
    assert marker.exists()


def _plant(folder: Path, where: str, marker: Path) -> None:
    doc, arrays = read_pair(folder)
    if where == "checkpoint.pkl alone":
        for name in (CHECKPOINT_FILE, ARRAYS_FILE):
            (folder / name).unlink()
        (folder / OLD_CHECKPOINT_FILE).write_bytes(trap_payload(marker))
    elif where == "checkpoint.pkl beside a damaged checkpoint.json":
        (folder / OLD_CHECKPOINT_FILE).write_bytes(trap_payload(marker))
        (folder / CHECKPOINT_FILE).write_text("{")
    elif where == "checkpoint.json":
        (folder / CHECKPOINT_FILE).write_bytes(trap_payload(marker))
    elif where == "checkpoint.npz":
        rewrite(folder, doc, trap_payload(marker))
    elif where == "checkpoint.npz, unhashed":
        rewrite(folder, doc, trap_payload(marker), rehash=False)
    elif where == "an object array for the mean":
        rewrite(folder, doc, trap_npz(arrays, "strategy.mean", marker))
    else:  # an extra object array
        rewrite(folder, doc, trap_npz(arrays, "strategy.payload", marker))


PLACES = [
    "checkpoint.pkl alone",
    "checkpoint.pkl beside a damaged checkpoint.json",
    "checkpoint.json",
    "checkpoint.npz",
    "checkpoint.npz, unhashed",
    "an object array for the mean",
    "an extra object array",
]


@pytest.mark.parametrize("where", PLACES)
def test_a_pickle_payload_in_a_checkpoint_never_runs(
    folder: Path, tmp_path: Path, where: str
) -> None:
    marker = tmp_path / "pwned"
    _plant(folder, where, marker)
    argv = ["identify", "sim", str(tmp_path / "data"), "--resume", str(folder)]
    outcome = run_cli([*argv, "--out", str(tmp_path / "out")])
    assert not marker.exists(), "the checkpoint's pickle ran"
    lines = outcome.stderr.strip().splitlines()
    assert outcome.code == 2, outcome
    assert len(lines) == 1, lines
    assert lines[0].startswith("zmpkit: error: ")
    assert "Traceback" not in outcome.stderr
    assert not (tmp_path / "out").exists()
    if where == "checkpoint.pkl alone":
        assert "an older zmpkit (a pickle, which can run code when opened)" in lines[0]
        assert "no longer opens it" in lines[0]


def test_another_fit_is_refused_naming_what_differs(fit_folder: Path, tmp_path: Path) -> None:
    saved = load_checkpoint(fit_folder).fingerprint
    options = CmaOptions(**OPTIONS)
    check_fingerprint(saved, fingerprint(sphere_problem(3), options), fit_folder)  # tuples too
    other = fingerprint(sphere_problem(4), CmaOptions(**{**OPTIONS, "seed": 4}))
    pattern = r"another fit \(different parameters; seed: 3 there, 4 now\)"
    with pytest.raises(ParameterError, match=pattern):
        check_fingerprint(saved, other, fit_folder)
    folder = Path(shutil.copytree(fit_folder, tmp_path / "fit"))
    with pytest.raises(ParameterError, match=r"another fit \(seed: 3 there, 9 now\)"):
        write_fit(tmp_path / "out", resume=folder, **{**OPTIONS, "seed": 9})


def test_a_robot_file_typed_relative_still_resumes(
    monkeypatch: pytest.MonkeyPatch, tmp_path: Path
) -> None:
    """A checkpoint that recorded ``robot.yaml`` as typed resumes with the file's source."""
    monkeypatch.chdir(tmp_path)
    source = str(tmp_path / "robot.yaml")  # a robot file's Robot.source: its absolute path
    check_fingerprint({"robot": "robot.yaml", "seed": 1}, {"robot": source, "seed": 1}, tmp_path)
    with pytest.raises(ParameterError, match=r"another fit \(different robot\)"):
        check_fingerprint({"robot": "other.yaml"}, {"robot": source}, tmp_path)
    with pytest.raises(ParameterError, match=r"robot: 'robot\.yaml' there, 'nao' now"):
        check_fingerprint({"robot": "robot.yaml"}, {"robot": "nao"}, tmp_path)


def test_identify_sim_refuses_a_damaged_resume_before_writing(folder: Path, tmp_path: Path) -> None:
    doc, arrays = read_pair(folder)
    arrays["strategy.sm.D"][0] = np.nan
    rewrite(folder, doc, npz_of(arrays))
    argv = ["identify", "sim", "--self-test", "--quick", "--resume", str(folder)]
    outcome = run_cli([*argv, "--out", str(tmp_path / "out")])
    assert outcome.code == 2
    assert outcome.stderr.strip().endswith(
        "checkpoint.npz: strategy.sm.D: holds NaN or infinity; expected finite numbers (damaged)"
    )
    assert not (tmp_path / "out").exists()  # nothing recorded, nothing written


def test_a_record_as_plain_values_is_what_asdict_gives() -> None:
    from dataclasses import asdict

    from zmpkit.simfit.checkpoint_history import GenerationRecord

    record = GenerationRecord(3, 18, 0.5, 0.25, 0.75, 0.1, {"a": 1.0, "b": 2.5}, 0.01, 1, 12)
    plain = record.as_plain()
    assert plain == asdict(record)
    assert plain["best_values"] is not record.best_values  # a copy, as asdict makes
