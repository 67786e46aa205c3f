r"""The fit's cost as a vector of residuals, for a least-squares (Gauss–Newton) refinement.

Each term of :mod:`~zmpkit.simfit.cost` is an RMS, so an experiment's cost
:math:`w_q e_q^2 + w_p e_p^2 + w_f e_f^2 + w_s e_s^2` is the squared norm of one vector
:math:`r = (\sqrt{w_q}\, r_q,\ \sqrt{w_p}\, r_p,\ \sqrt{w_f}\, r_f,\ \sqrt{w_s}\, r_s)`:

.. math::
    r_q = \frac{q_{sim} - q_{rec}}{\operatorname{RMS}(q_{rec} - q_{cmd}) \sqrt{N J}},\qquad
    r_p = \frac{\mathcal{S}_p(p_{sim}) - \mathcal{S}_p(p_{rec}) - \bar d}{s_p \sqrt{N_p}},\qquad
    r_f = \frac{\mathcal{S}(f_{sim}) - \mathcal{S}(f_{rec})}{\bar W \sqrt{N_f}},\qquad
    r_s = \frac{A_{sim} - A_{rec}}{\lVert A_{rec} \rVert_2},

over every sample and joint, the :math:`N_p` rows where both ZMPs are defined (the others
0: a row whose simulated ZMP is undefined enters neither the cost nor the vector), the
:math:`N_f` rows where both feet's forces are (likewise; :math:`r_f` only when the fit
models the loads), and the spectrum band. The fit's mean over :math:`E` experiments is the
squared norm of their vectors stacked and divided by :math:`\sqrt{E}`
(:func:`stacked_residuals`). The vector has a fixed length per experiment, whatever the
candidate, so a Jacobian of it by finite differences is defined; a rollout that did not
reproduce the whole recording has none.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from numpy.typing import NDArray

from zmpkit.simfit.cost import (
    CostWeights,
    force_rows,
    load_scale_n,
    smoothed_forces,
    spectrum_in_band,
    tracking_scale_rad,
    zmp_miss,
)
from zmpkit.simfit.recorded import RecordedSignals

__all__ = ["experiment_residuals", "stacked_residuals"]

_MIN_SCALE = 1e-6


def _zmp_residuals(
    rec: RecordedSignals, zmp_m: NDArray[np.float64], keep_mean: bool
) -> NDArray[np.float64]:
    """:math:`r_p` over the recorded rows with a ZMP, ``(2 N_rec,)`` [-]."""
    defined = np.all(np.isfinite(rec.zmp_m), axis=1)
    simulated = np.asarray(zmp_m, dtype=np.float64)[defined]
    both = np.all(np.isfinite(simulated), axis=1)
    out = np.zeros_like(simulated)
    if np.count_nonzero(both) < 3:
        return out.ravel()
    compared = defined.copy()
    compared[defined] = both
    miss, scale = zmp_miss(rec, compared, simulated[both], keep_mean)
    out[both] = miss / (scale * np.sqrt(np.count_nonzero(both)))
    return out.ravel()


def _force_residuals(rec: RecordedSignals, force_z_n: NDArray[np.float64]) -> NDArray[np.float64]:
    """:math:`r_f` over the rows whose recorded forces are finite, ``(2 N_rec,)`` [-]."""
    recorded = np.all(np.isfinite(rec.force_z_n), axis=1)
    both = force_rows(rec, force_z_n)[recorded]
    out = np.zeros((np.count_nonzero(recorded), 2))
    count = np.count_nonzero(both)
    if count < 3:
        return out.ravel()
    rec_rows = rec.force_z_n[recorded][both]
    sim_rows = np.asarray(force_z_n, dtype=np.float64)[recorded][both]
    miss = smoothed_forces(sim_rows, rec.dt_s) - smoothed_forces(rec_rows, rec.dt_s)
    out[both] = miss / (load_scale_n(rec_rows) * np.sqrt(count))
    return out.ravel()


def experiment_residuals(
    recorded: RecordedSignals,
    simulated: RecordedSignals,
    weights: CostWeights,
    models_loads: bool = False,
) -> NDArray[np.float64] | None:
    """The residual vector :math:`r` of ``simulated`` against ``recorded`` (module docstring).

    Its squared norm is :func:`~zmpkit.simfit.cost.experiment_cost`'s total with
    ``weights``.

    Returns:
        :math:`r` [-], or None when the rollout did not reproduce the whole recording.
    """
    n = recorded.time_s.size
    if simulated.time_s.size < n:
        return None
    count = recorded.q_meas_rad.size
    q_scale = tracking_scale_rad(recorded)
    r_q = (simulated.q_meas_rad[:n] - recorded.q_meas_rad).ravel() / (q_scale * np.sqrt(count))
    r_p = _zmp_residuals(recorded, simulated.zmp_m[:n], models_loads)
    r_f = _force_residuals(recorded, simulated.force_z_n[:n]) if models_loads else np.zeros(0)
    _, a_rec = spectrum_in_band(recorded.trunk_tilt_rad, recorded.dt_s)
    _, a_sim = spectrum_in_band(simulated.trunk_tilt_rad[:n], recorded.dt_s)
    r_s = (a_sim - a_rec) / max(float(np.linalg.norm(a_rec)), _MIN_SCALE)
    return np.concatenate(
        [
            np.sqrt(weights.joint) * r_q,
            np.sqrt(weights.zmp) * r_p,
            np.sqrt(weights.force) * r_f,
            np.sqrt(weights.spectrum) * r_s,
        ]
    )


def stacked_residuals(parts: Sequence[NDArray[np.float64] | None]) -> NDArray[np.float64] | None:
    r"""The experiments' vectors stacked, divided by :math:`\sqrt{E}`; None if one is None."""
    if not parts or any(p is None for p in parts):
        return None
    return np.concatenate([p for p in parts if p is not None]) / np.sqrt(len(parts))
