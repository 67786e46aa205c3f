"""Fuzzing the ROS 2 bag reader: valid bags (sqlite3, MCAP) with their files corrupted.

Each case takes a small valid bag of two F-T topics and breaks it the way bags break on disk:
truncated (a recording cut off), bytes overwritten, the metadata mangled, or the data file
missing. The reader must end with one short ``ZmpkitError`` line, never another exception.
"""

from __future__ import annotations

import shutil
import tempfile
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from rosbags.rosbag2 import Writer
from rosbags.rosbag2.enums import StoragePlugin
from rosbags.typesys import Stores, get_typestore

from helpers.fuzz import Census, reader_problems
from zmpkit.io import read_ros2_bag

TS = get_typestore(Stores.LATEST)
WRENCH = "geometry_msgs/msg/WrenchStamped"
T0_NS = 1_712_345_678_000_000_000
PLUGINS = {"sqlite3": StoragePlugin.SQLITE3, "mcap": StoragePlugin.MCAP}
_SETTINGS = {
    "deadline": None,
    "derandomize": True,
    "database": None,
    "suppress_health_check": [HealthCheck.too_slow, HealthCheck.data_too_large],
}


def _wrench(stamp_ns: int, w: np.ndarray) -> object:
    m = TS.types
    header = m["std_msgs/msg/Header"](
        stamp=m["builtin_interfaces/msg/Time"](sec=stamp_ns // 10**9, nanosec=stamp_ns % 10**9),
        frame_id="ft",
    )
    vector = m["geometry_msgs/msg/Vector3"]
    wrench = m["geometry_msgs/msg/Wrench"](force=vector(*w[:3]), torque=vector(*w[3:]))
    return m[WRENCH](header=header, wrench=wrench)


def _bag(path: Path, plugin: StoragePlugin, n: int = 20) -> Path:
    with Writer(path, version=9, storage_plugin=plugin) as writer:
        for topic, sign in (("/ft/right", 1.0), ("/ft/left", -1.0)):
            connection = writer.add_connection(topic, WRENCH, typestore=TS)
            for k in range(n):
                stamp = T0_NS + k * 1_000_000
                w = sign * (np.arange(6.0) + 300.0)
                writer.write(connection, stamp + 7, TS.serialize_cdr(_wrench(stamp, w), WRENCH))
    return path


@pytest.fixture(scope="module")
def bags(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Path]:
    root = tmp_path_factory.mktemp("bags")
    return {name: _bag(root / name, plugin) for name, plugin in PLUGINS.items()}


CORRUPTIONS = st.tuples(
    st.sampled_from(sorted(PLUGINS)),
    st.sampled_from(("truncate", "overwrite", "metadata", "missing")),
    st.floats(0.0, 1.0),
    st.binary(min_size=1, max_size=64),
)


def _corrupt(bag: Path, into: Path, kind: str, where: float, junk: bytes) -> Path:
    shutil.copytree(bag, into)
    data = next(p for p in into.iterdir() if p.name != "metadata.yaml")
    if kind == "missing":
        data.unlink()
        return into
    target = into / "metadata.yaml" if kind == "metadata" else data
    raw = target.read_bytes()
    at = int(where * len(raw))
    if kind == "truncate":
        target.write_bytes(raw[:at])
    else:
        target.write_bytes(raw[:at] + junk + raw[at + len(junk) :])
    return into


def _run(bags: dict[str, Path], examples: int) -> Census:
    census = Census("reader rosbag")

    @settings(max_examples=examples, **_SETTINGS)
    @given(CORRUPTIONS)
    def fuzz(case: tuple[str, str, float, bytes]) -> None:
        plugin, kind, where, junk = case
        with tempfile.TemporaryDirectory() as tmp:
            bag = _corrupt(bags[plugin], Path(tmp) / "bag", kind, where, junk)

            def read() -> object:
                return read_ros2_bag(bag, right_topic="/ft/right", left_topic="/ft/left")

            census.record(reader_problems(read, Path(tmp)), case)

    fuzz()
    return census


def test_an_intact_bag_reads() -> None:
    with tempfile.TemporaryDirectory() as tmp:
        for name, plugin in PLUGINS.items():
            log = read_ros2_bag(_bag(Path(tmp) / name, plugin), right_topic="/ft/right",
                                left_topic="/ft/left")  # fmt: skip
            assert log.ft.right_wrench.shape == (20, 6)


def test_fuzz_rosbag_fast(bags: dict[str, Path]) -> None:
    census = _run(bags, 40)
    assert census.cases >= 40
    assert census.bad == 0, census.summary()


@pytest.mark.slow
def test_fuzz_rosbag_many(bags: dict[str, Path]) -> None:
    census = _run(bags, 600)
    assert census.cases >= 600
    assert census.bad == 0, census.summary()
