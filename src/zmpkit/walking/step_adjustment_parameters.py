"""When and how far a feedback walk adjusts its steps (:mod:`zmpkit.walking.step_adjustment`).

**How the defaults were chosen, and what they give** (the walking robot, all effects, seed 0;
``zmpkit walk sweep --controllers zmpip,dcm --effects all --workers 1 [--no-step-adjustment]``
on the built-in walker). Tuning set: ``zmpip``'s 16 pushes of 20 N along ±x and ±y (6 fall
without the adjustment: 20 N x @ 0.25, y @ 0.25 and the four -y, outward over the stance foot,
which no step within the legs' reach and without crossing captures in the LIPM). Falls of 16
with the adjustment: anchored where commanded (before
:mod:`~zmpkit.walking.measured_footholds`), 10; measured footholds, 8 (a contact counted as
touchdown after 0.8 or 1.0 of the swing, 9 and 10; no shortening, 8; reach margin 0.4 or 0.3, 8
and 9; trigger (0.06, 0.03) m, 8; CoP margins (0.07, 0.04) m, 8); the CoP margin the whole
sole, (0.08, 0.045) m on the built-in walker (kept, as the sole's half size), 6; with the next
swing lifting early after an uncaptured early landing, 9 (it is off).
Judged, unchanged, on the cases that chose nothing (without → with): ``zmpip``'s 20 N diagonal
pushes 4 → 3 of 16, its 30 N pushes 29 → 27 of 32, its 10 N pushes 0 → 0 of 32, its 20 unpushed
walks 0 → 0 (none moved a step, their speed errors equal); ``dcm`` 54 → 53 of 116 (none lost;
its two sideways walks fall with and without, and move steps). In all: ``zmpip`` 39 → 36 of
116, ``dcm`` 54 → 53. Most 30 N pushes still fall: one step of its reach captures little of a
9 cm DCM jump, and the swing legs lag fast re-planned swings by 4–8 cm. It is not on by
default (``--step-adjustment`` turns it on): its trigger and the reach of its steps were set
on the built-in walker, and on a robot none of them was set on, the Berkeley Humanoid
(``robot init`` from MuJoCo Menagerie, all effects, 10 s, not pushed), it moved all 20 steps
(19 reported as not capturing) of a walk that moves none without it, and one of the walks of
``tests/robots/test_unseen_humanoids.py`` fell with it (none without).

Issue 31, this session (``zmpip``'s 16 pushes of 20 N along the axes, all effects, the tuning
set again; a contact counted as touchdown only after the foot was in the air): 6 fall (x @
0.25, -x @ 0.5, the four -y), as before. Level swing soles (:attr:`level_swing`): 7; two
steps on the plan's timing (:attr:`two_step`): 6; both: 5 (-x @ 0.5 caught); the soles
levelled in roll as well as pitch (either sign): 9. Tried and not kept: a lift-off held while
the stance foot is unloaded, 7 (-x @ 0.75 fell); a foot still in the air at its touchdown
lowered at 2 z_c/s to 0.12 z_c below the ground, 7 (y @ 0 fell; the IK stopped at 2.6 cm).
Judged on the cases that chose nothing (``zmpip``, all 116 with the adjustment, the same
command with both on): 36 → 32 falls; 20 N diagonals 3 → 0 of 16, 30 N 27 → 27 of 32, 10 N
and unpushed 0 → 0 (no unpushed step moved; the level soles change their speed error by up
to +1.9 points); ``dcm`` 53 → 44 (20 N 23 → 12, 30 N 28 → 29; its unpushed turn at
0.3 rad/s falls with them). Both opt-ins stay off: the two-step tick peaks at 96 B in
``test_tick_allocations`` (not allocation-free yet), and the level soles act on every walk.

Before (the references re-planned every tick, 15 to 28 of 32 pushes of 10 and 20 N; the
exact LIPM capture, 31; CoP margins (0.04, 0.015) m, 20–21, (0.06, 0.035) m, 12; the
earliest capturing touchdown preferred to the latest, 32; the swing's acceleration limited
at 5 to 20 m/s², no net change). The trigger along the feet, 0.04 m, is set above the
unpushed walk's rocking, not by pushes.
"""

from __future__ import annotations

from dataclasses import dataclass

from zmpkit import _validate
from zmpkit.walking.step_reach import DEFAULT_REACH_MARGIN

__all__ = ["StepAdjustmentParameters"]


@dataclass(frozen=True)
class StepAdjustmentParameters:
    """When and how far a feedback walk adjusts its steps (:mod:`.step_adjustment`).

    Attributes:
        enabled: False walks the planned footsteps.
        trigger_dcm_error_m: the DCM error (along, across the stance sole) beyond which a
            step is adjusted [m].
        cop_margin_m: m, the CoP shift left to the stance ankle (along, across) [m]; None:
            the stance sole's half length and half width (the walk's
            :class:`~zmpkit.walking.gait.FootShape`): a step moves only for a DCM the sole
            cannot hold.
        landing_margin_m: how far off its centre the new sole may take the DCM at the end of
            the transfer (along, across) [m].
        min_swing_fraction: the shortest swing, as a share of the planned one [-].
        latest_trigger_fraction: a step is adjusted only if the DCM error passes the trigger
            before this share of its swing (later, the next step is adjusted) [-].
        min_remaining_s: a touchdown is never moved nearer than this, nor changed within
            it [s].
        reach_margin: ρ of :func:`~zmpkit.walking.step_reach.step_reach` [-].
        max_swing_acceleration_mps2: a re-planned landing moves at most ``a D² / 5.77`` from
            the current one, D the time left to touchdown (a quintic's peak acceleration: a
            swing leg accelerated harder pushes the body the other way) [m/s²].
        habit_rate: α, how fast the walk's own repeated DCM deviation is learned [-]; 0: not
            learned.
        measured_footholds: a moved step's foot is anchored where it is measured, and lands
            at its first contact (:mod:`zmpkit.walking.measured_footholds`); False: where it
            was commanded.
        touchdown_contact_fraction: the share of a moved swing after which a contact is its
            touchdown [-].
        early_next_lift: a step that could not capture and landed early has the next swing
            lift as much earlier (its planned touchdown with it): the plan's double support,
            not the plan's clock, follows the early landing (the ``zmpip`` walk only).
        two_step: a triggered step lands, at its planned touchdown, nearest the plan
            where the next step captures on the plan's timing, when two such steps exist
            (:mod:`zmpkit.walking.two_step_capture`); else one step is re-timed and placed.
        level_swing: the swing sole is kept level in pitch: the trunk's measured pitch
            change is taken off it (:mod:`zmpkit.walking.level_swing`).
    """

    enabled: bool = True
    trigger_dcm_error_m: tuple[float, float] = (0.04, 0.02)
    cop_margin_m: tuple[float, float] | None = None
    landing_margin_m: tuple[float, float] = (0.0, 0.0)
    min_swing_fraction: float = 0.7
    latest_trigger_fraction: float = 0.6
    min_remaining_s: float = 0.05
    reach_margin: float = DEFAULT_REACH_MARGIN
    habit_rate: float = 0.25
    max_swing_acceleration_mps2: float = 5.0
    measured_footholds: bool = True
    touchdown_contact_fraction: float = 0.5
    early_next_lift: bool = False
    two_step: bool = False
    level_swing: bool = False

    def __post_init__(self) -> None:
        for name in ("trigger_dcm_error_m", "cop_margin_m", "landing_margin_m"):
            for value in getattr(self, name) or ():
                _validate.non_negative(f"StepAdjustmentParameters.{name}", value, "m")
        _validate.in_range(
            "StepAdjustmentParameters.min_swing_fraction", self.min_swing_fraction, 0.05, 1.0
        )
        _validate.in_range(
            "StepAdjustmentParameters.latest_trigger_fraction", self.latest_trigger_fraction,
            0.0, 1.0,
        )  # fmt: skip
        _validate.non_negative(
            "StepAdjustmentParameters.min_remaining_s", self.min_remaining_s, "s"
        )
        _validate.in_range("StepAdjustmentParameters.reach_margin", self.reach_margin, 1e-3, 1.0)
        _validate.in_range("StepAdjustmentParameters.habit_rate", self.habit_rate, 0.0, 1.0)
        _validate.in_range(
            "StepAdjustmentParameters.touchdown_contact_fraction",
            self.touchdown_contact_fraction, 0.0, 1.0,
        )  # fmt: skip
        _validate.positive(
            "StepAdjustmentParameters.max_swing_acceleration_mps2",
            self.max_swing_acceleration_mps2, "m/s²",
        )  # fmt: skip
