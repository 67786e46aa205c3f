"""Benchmark of the ZMP from ankle F-T sensors: scalar fast path and time series.

Usage::

    python benchmarks/bench_zmp.py [--json PATH] [--samples N]

Measures in one run, with :mod:`timeit` (best of several repeats):

1. one double-support sample: :class:`zmpkit.sensors.DoubleSupportZmp` on lists of floats vs
   a plain numpy implementation of the same sample (``R @ f`` per foot, eq. 5, eq. 6) on
   (6,) arrays [ns/sample], for TEO's mount (rotated π about x) and for a general rotation;
2. a time series: :func:`zmpkit.sensors.zmp_series` on 1e6 samples [samples/s], against a
   bare numpy pass over the same data (one ``np.divide`` of two columns) timed alongside.

Speed is reported, never asserted.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from numpy.typing import NDArray

from harness import base_parser, best_of, environment, print_table, write_json
from zmpkit.sensors import (
    CONTACT_FORCE_THRESHOLD_N,
    DoubleSupportZmp,
    SensorMount,
    moment_coefficients,
    zmp_series,
)

__all__ = ["main"]

REPEATS = 7


def best_seconds(stmt: str, namespace: dict[str, object], number: int) -> float:
    """Best time of one execution of ``stmt`` over :data:`REPEATS` repeats [s]."""
    return best_of(stmt, number, REPEATS, namespace)


def numpy_sample(
    right_wrench: NDArray[np.float64],
    left_wrench: NDArray[np.float64],
    right: SensorMount,
    left: SensorMount,
) -> tuple[float, float] | None:
    """The double-support ZMP of one sample, written plainly with small numpy arrays [m]."""
    total_fz, total_moment = 0.0, np.zeros(2)
    for wrench, mount in ((right_wrench, right), (left_wrench, left)):
        force = np.dot(mount.rotation, wrench[:3])
        moment = np.dot(mount.rotation, wrench[3:])
        if force[2] < CONTACT_FORCE_THRESHOLD_N:
            continue
        h = mount.sole_height
        cop = (
            mount.position[:2]
            + np.array([-(moment[1] + h * force[0]), moment[0] - h * force[1]]) / force[2]
        )
        total_fz += force[2]
        total_moment += cop * force[2]
    return None if total_fz == 0.0 else tuple(total_moment / total_fz)


def numpy_coefficient_sample(
    right_wrench: NDArray[np.float64],
    left_wrench: NDArray[np.float64],
    right_c: NDArray[np.float64],
    left_c: NDArray[np.float64],
) -> tuple[float, float] | None:
    """The same sample with precomputed (6, 3) coefficient matrices: numpy at its leanest [m]."""
    right_m, left_m = np.dot(right_wrench, right_c), np.dot(left_wrench, left_c)
    right_in, left_in = (
        right_m[0] >= CONTACT_FORCE_THRESHOLD_N,
        left_m[0] >= CONTACT_FORCE_THRESHOLD_N,
    )
    if not (right_in or left_in):
        return None
    total = right_m * right_in + left_m * left_in
    return total[1] / total[0], total[2] / total[0]


def bench_sample(rpy: tuple[float, float, float]) -> dict[str, float]:
    """ns per double-support sample, fast path and numpy, for mounts with this rotation."""
    right = SensorMount.from_rpy((0.01, -0.1285, 0.01), rpy, 0.01, "right")
    left = SensorMount.from_rpy((-0.01, 0.1285, 0.01), rpy, 0.01, "left")
    rng = np.random.default_rng(0)
    load = np.array([5.0, -3.0, 300.0])
    wrenches = []
    for mount in (right, left):
        moment = rng.normal(scale=2.0, size=3)
        wrenches.append(np.concatenate([mount.rotation.T @ load, mount.rotation.T @ moment]))
    fast = DoubleSupportZmp(right, left)
    lists = [w.tolist() for w in wrenches]
    right_c, left_c = moment_coefficients(right), moment_coefficients(left)
    reference = numpy_sample(*wrenches, right, left)
    lean = numpy_coefficient_sample(*wrenches, right_c, left_c)
    error = np.max(np.abs(np.subtract([fast(*lists), lean], [reference, reference])))
    namespace = {
        "fast": fast,
        "numpy_sample": numpy_sample,
        "wr": wrenches[0],
        "wl": wrenches[1],
        "lr": lists[0],
        "ll": lists[1],
        "right": right,
        "left": left,
        "numpy_coefficient_sample": numpy_coefficient_sample,
        "cr": right_c,
        "cl": left_c,
    }
    fast_s = best_seconds("fast(lr, ll)", namespace, 200_000)
    numpy_s = best_seconds("numpy_sample(wr, wl, right, left)", namespace, 20_000)
    lean_s = best_seconds("numpy_coefficient_sample(wr, wl, cr, cl)", namespace, 20_000)
    return {
        "fast_ns": fast_s * 1e9,
        "numpy_ns": numpy_s * 1e9,
        "speedup": numpy_s / fast_s,
        "numpy_coefficients_ns": lean_s * 1e9,
        "speedup_vs_numpy_coefficients": lean_s / fast_s,
        "max_abs_difference_m": float(error),
    }


def bench_series(n: int) -> dict[str, float]:
    """samples/s of zmp_series on n samples, and of one np.divide over the same arrays."""
    right = SensorMount.from_rpy((0.0, -0.1285, 0.01), (math.pi, 0, 0), 0.01, "right")
    left = SensorMount.from_rpy((0.0, 0.1285, 0.01), (math.pi, 0, 0), 0.01, "left")
    rng = np.random.default_rng(1)
    time = np.arange(n) * 1e-3
    right_wrench = rng.normal(scale=[5, 5, 50, 2, 2, 0.5], size=(n, 6))
    left_wrench = rng.normal(scale=[5, 5, 50, 2, 2, 0.5], size=(n, 6))
    right_wrench[:, 2] -= 300.0  # sensor z points down on TEO: loaded = negative
    left_wrench[:, 2] -= 300.0 * (np.arange(n) % 1000 < 700)  # left foot lifted 30 % of the time
    namespace = {
        "zmp_series": zmp_series,
        "np": np,
        "t": time,
        "wr": right_wrench,
        "wl": left_wrench,
        "right": right,
        "left": left,
    }
    series_s = best_seconds("zmp_series(t, wr, wl, right, left)", namespace, 3)
    divide_s = best_seconds("np.divide(wr[:, 4], wr[:, 2])", namespace, 3)
    return {
        "samples": n,
        "series_s": series_s,
        "series_samples_per_s": n / series_s,
        "divide_s": divide_s,
        "divide_samples_per_s": n / divide_s,
        "series_over_divide": series_s / divide_s,
    }


def report(results: dict[str, Any]) -> None:
    """Print the results as a table (rich if available)."""
    rows = []
    for label, sample in results["sample"].items():
        rows.append((f"1 sample, {label}: fast path", f"{sample['fast_ns']:.0f} ns", ""))
        rows.append(
            (
                f"1 sample, {label}: numpy",
                f"{sample['numpy_ns']:.0f} ns",
                f"fast is {sample['speedup']:.1f}x faster",
            )
        )
        rows.append(
            (
                f"1 sample, {label}: numpy, precomputed (6, 3) coefficients",
                f"{sample['numpy_coefficients_ns']:.0f} ns",
                f"fast is {sample['speedup_vs_numpy_coefficients']:.1f}x faster",
            )
        )
    series = results["series"]
    rows.append(
        (
            f"zmp_series, {series['samples']:.0e} samples",
            f"{series['series_samples_per_s']:.3g} samples/s",
            f"{series['series_s'] * 1e3:.1f} ms",
        )
    )
    rows.append(
        (
            "np.divide of two columns (baseline)",
            f"{series['divide_samples_per_s']:.3g} samples/s",
            f"zmp_series takes {series['series_over_divide']:.1f}x its time",
        )
    )
    title = f"zmpkit ZMP benchmark ({results['python']}, numpy {results['numpy']})"
    print_table(title, ("case", "speed", "note"), rows)


def main(argv: list[str] | None = None) -> dict[str, Any]:
    """Run the benchmark, print a table, write JSON if asked; returns the results."""
    parser = base_parser(__doc__.splitlines()[0])
    parser.add_argument("--samples", type=int, default=1_000_000, help="time-series length")
    args = parser.parse_args(argv)
    results = {
        **environment(),
        "repeats": REPEATS,
        "sample": {
            "TEO mount (pi about x)": bench_sample((math.pi, 0.0, 0.0)),
            "general rotation": bench_sample((2.9, 0.2, -0.4)),
        },
        "series": bench_series(args.samples),
    }
    report(results)
    if args.json is not None:
        write_json(args.json, results)
    return results


if __name__ == "__main__":
    main()
