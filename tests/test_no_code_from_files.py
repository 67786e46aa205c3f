"""Nothing in zmpkit reads a file in a way that can run code (issue 32).

A fit folder, a dataset or a robot file may come from anyone, so ``src/`` holds no
unpickling (``pickle.load``/``loads``/``Unpickler``, nor the libraries built on it), no
``allow_pickle=True``, and YAML goes only through :class:`~zmpkit.io.yaml_file.Yaml12Loader`,
a ``yaml.SafeLoader``; ``exec`` appears once, on source built from float ``repr``s. Pickling
our own objects for our own process pools (``pickle.dumps`` by ``concurrent.futures``) is
not reading a user's file and stays allowed.
"""

from __future__ import annotations

import re
from pathlib import Path

import pytest
import yaml

from zmpkit.io.yaml_file import Yaml12Loader

SRC = Path(__file__).resolve().parents[1] / "src" / "zmpkit"
FORBIDDEN = {
    "unpickling": (
        r"\b(c?pickle|dill|cloudpickle|joblib|shelve|marshal)\.(load|loads|Unpickler|open)\b"
    ),
    "pickle through pandas or torch": r"\b(read_pickle|torch\.load)\b",
    "allow_pickle=True": r"allow_pickle\s*=\s*True",
    "an unsafe YAML loader": r"\b(unsafe_load|full_load|FullLoader|UnsafeLoader)\b|yaml\.Loader\b",
    "yaml.load without the safe loader": r"yaml\.load(_all)?\((?![^)]*Loader=Yaml12Loader)",
}  # fmt: skip
EXEC_ALLOWED = {"sensors/fast.py"}  # the ZMP's generated arithmetic: float reprs only


def _sources() -> list[tuple[str, str]]:
    return [(p.relative_to(SRC).as_posix(), p.read_text()) for p in sorted(SRC.rglob("*.py"))]


def test_the_sources_are_found() -> None:
    names = [name for name, _ in _sources()]
    assert "simfit/checkpoint.py" in names
    assert len(names) > 100


@pytest.mark.parametrize("what", sorted(FORBIDDEN))
def test_no_source_reads_a_file_in_a_way_that_can_run_code(what: str) -> None:
    pattern = re.compile(FORBIDDEN[what])
    found = [
        f"{name}:{k}: {line.strip()}"
        for name, text in _sources()
        for k, line in enumerate(text.splitlines(), start=1)
        if pattern.search(line)
    ]
    assert found == [], what


def test_exec_and_eval_only_on_generated_numbers() -> None:
    call = re.compile(r"(?<![\w.])(exec|eval)\(")
    found = {name for name, text in _sources() if call.search(text)}
    assert found <= EXEC_ALLOWED


def test_the_yaml_loader_is_the_safe_one() -> None:
    assert issubclass(Yaml12Loader, yaml.SafeLoader)
    with pytest.raises(yaml.constructor.ConstructorError):
        yaml.load("!!python/object/apply:os.system ['true']", Loader=Yaml12Loader)


def test_the_patterns_catch_what_they_forbid() -> None:
    """Each pattern matches the line it is there for (so an empty finding means something)."""
    lines = {
        "unpickling": "state = pickle.loads(path.read_bytes())",
        "pickle through pandas or torch": "frame = pd.read_pickle(path)",
        "allow_pickle=True": "np.load(path, allow_pickle = True)",
        "an unsafe YAML loader": "yaml.load(text, Loader=yaml.FullLoader)",
        "yaml.load without the safe loader": "doc = yaml.load(text)",
    }
    for what, line in lines.items():
        assert re.search(FORBIDDEN[what], line), what
    assert not re.search(
        FORBIDDEN["yaml.load without the safe loader"], "yaml.load(t, Loader=Yaml12Loader)"
    )
    assert not re.search(FORBIDDEN["unpickling"], "pickle.dumps(problem)")
