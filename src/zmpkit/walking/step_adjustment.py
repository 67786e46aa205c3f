r"""Step adjustment: a feedback walk that steps to where it can capture its DCM.

Ankle torque and CoM motion keep the measured ZMP inside the stance sole; a push that moves the
DCM ``ξ`` further than the sole can hold (a 2 N·s impulse on the built-in walker moves it
about 6 cm) can only be caught by where and when the swing foot lands (Khadiv et al.,
"Stepping stabilization using a combination of DCM tracking and step adjustment", ICRA 2016;
Griffin et al., "Walking stabilization using step timing and location adjustment on the
humanoid robot Atlas", IROS 2017). Every control tick of a single support:

1. **The DCM error.** ``e = ξ̂ - ξ^{ref} - o_s - h`` with ``ξ̂ = ĉ + \hat{\dot c}/ω`` from the
   kinematic state estimate (:mod:`zmpkit.walking.state_estimator`: encoders, IMU, the feet
   in contact), ``ξ^{ref}`` the plan's, ``o_s`` the offset the stance foot landed with and
   ``h`` the walk's own repeated deviation at this point of the swing (learned over the
   earlier swings of the foot). (The ZMP/IP observer's DCM trusts the plan's jerk: after
   a 20 N push its error stayed below 1 cm, the estimate's 5.3, the simulator's 5.5.)
2. **The trigger.** The built-in walker (all effects) rocks its DCM by up to 3.4 cm along and
   1.1 cm across the feet at every step; a step is adjusted once ``|e|`` passes
   :attr:`StepAdjustmentParameters.trigger_dcm_error_m` on either axis early enough in its
   swing, and is then re-planned every tick until shortly before touchdown. A walk that is
   not pushed walks as planned.
3. **Where and when.** :func:`~zmpkit.walking.capture_step.solve_capture` chooses the
   touchdown ``T' ≤ T`` and the landing ``G`` within the legs' reach
   (:mod:`zmpkit.walking.step_reach`: no crossing, no over-stretched knee) that capture the
   DCM, or the step that leaves the least of it (reported: :data:`NOT_CAPTURED`), the
   ankle holding the CoP within ``m`` of the sole's centre (default: the whole sole). A fast
   swing leg pushes the body the other way (a kid-size robot's leg is a fifth of its mass):
   the landing moves at most ``a D² / 5.77`` from the plan's, ``D`` the time left.
4. **The swing** is re-planned to ``G`` at ``T'`` (:mod:`zmpkit.walking.adjusted_swing`).
5. **The rest of the walk** moves with the step once the foot is down: every later footstep
   by ``o = G - U`` (``U`` the planned landing), and the ZMP reference with it, the transfer
   to the new sole starting at ``T'``:

   .. math:: δp(t) = o_s + (G - S)\,r(t - T') - (U - S^{ref})\,r(t - T),

   ``S = S^{ref} + o_s`` the stance sole, ``r`` the unit transfer over the double support.
   The ``zmpip`` walk's preview control tracks the reference so re-planned; the ``dcm`` walk
   gets the matching DCM, ZMP and CoM references:
   ``δξ(t) = o_s + (G - S) Ξ(T' - t) - (U - S^{ref}) Ξ(T - t)`` with ``Ξ`` the DCM of the
   unit transfer (:func:`~zmpkit.walking.capture_step.transfer_dcm`), and the CoM reference
   following it, ``δ\dot c = ω (δξ - δc)``, ``δ\ddot c = ω^2 (δc - δp)`` (re-planned every
   tick instead, they moved the CoM towards the new landing and grew the error).
6. **The next swing lifts early** when a step could not capture and landed early, by as
   much (``zmpip`` only): the plan's double support follows the landing, not its clock.

The state estimator places the robot by the feet in contact: a moved step's foot is placed
where it is measured, and lands where it touches down (:mod:`.measured_footholds`).

The trigger, margins and timing limits are :class:`StepAdjustmentParameters`
(:mod:`zmpkit.walking.step_adjustment_parameters`, with how their defaults were chosen).

A tick allocates nothing: plan tables, reference views and buffers are made with the
walk, a tick writes floats and runs ufuncs into them.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from zmpkit.models.pendulum import STANDARD_GRAVITY_MPS2
from zmpkit.walking.adjusted_swing import AdjustedSwing
from zmpkit.walking.capture_step import double_support_factor, solve_capture
from zmpkit.walking.dcm_habit import DcmHabit
from zmpkit.walking.measured_footholds import MeasuredFootholds
from zmpkit.walking.pattern import WalkingPattern
from zmpkit.walking.planned_steps import planned_steps
from zmpkit.walking.replanned_dcm import ReplannedDcmReference
from zmpkit.walking.replanned_zmp import ReplannedZmpReference
from zmpkit.walking.scalar_limits import clip
from zmpkit.walking.step_adjustment_parameters import StepAdjustmentParameters
from zmpkit.walking.step_events import NOT_CAPTURED, StepEvent, StepLog
from zmpkit.walking.step_reach import StepReach
from zmpkit.walking.two_step_capture import solve_two_step_into

__all__ = ["NOT_CAPTURED", "StepAdjustment", "StepAdjustmentParameters", "StepEvent"]

_MOVED_M = 1e-5  # a landing that moves less than this is not re-planned [m]


class StepAdjustment:
    """The step adjustment of one walk (module docstring), one tick at a time.

    Args:
        pattern: the planned walk.
        feet: the feet, in the order of ``soles``.
        reach: where a swing foot may land.
        parameters: trigger, margins and timing limits.
        targets: each foot's sole-centre targets [m], shape (N, 3), written frame by frame.
        soles: the feet's targets in one array [m], shape (N, F, 3) (the state estimator's
            anchors), written frame by frame.

    Attributes:
        dcm_error_in_world: the DCM error ``e`` of each frame of a single support [m],
            shape (N, 2); NaN elsewhere.
    """

    def __init__(
        self,
        pattern: WalkingPattern,
        feet: tuple[str, ...],
        reach: StepReach,
        parameters: StepAdjustmentParameters,
        targets: dict[str, NDArray[np.float64]],
        soles: NDArray[np.float64],
    ) -> None:
        self.parameters, self.reach = parameters, reach
        config = pattern.config
        self._dt = dt = config.control_period_s
        self._omega = math.sqrt(STANDARD_GRAVITY_MPS2 / config.com_height_m)
        self._t_d = config.gait.double_support_s
        self._t_d_frames = max(self._t_d / dt, 1e-9)
        self._kappa = double_support_factor(self._omega, self._t_d)
        foot = config.limits.foot
        self._cop_margin = parameters.cop_margin_m or (foot.length_m / 2, foot.width_m / 2)
        self._steps = planned_steps(pattern, feet)
        self._n = n = pattern.time_s.size
        self._step_at = [-1] * n
        for j, step in enumerate(self._steps):
            self._step_at[step.lift + 1 :] = [j] * (n - step.lift - 1)
        self._min_remaining = parameters.min_remaining_s / dt
        spans = [(s.lift, s.touchdown - s.lift) for s in self._steps]
        self._min_swing = [math.ceil(parameters.min_swing_fraction * d) for _, d in spans]
        self._latest_trigger = [a + parameters.latest_trigger_fraction * d for a, d in spans]
        com = pattern.com
        dcm = com.com_position_in_world + com.com_velocity_in_world / self._omega
        self._dcm_plan = np.ascontiguousarray(dcm[:, :2])
        plans = [getattr(pattern.feet, f).position_in_world for f in feet]
        self._feet = tuple(zip(range(len(feet)), plans, [targets[f] for f in feet], strict=True))
        self._soles = soles
        self._init_state(len(feet), config.step_height_m)

    def _init_state(self, nfeet: int, step_height_m: float) -> None:
        """The adjustment's state, before the walk's first step, and its logs per step."""
        # each foot's placement against the plan, and o of the last placement (every later one
        # moves by it); arrays: a foot's first landing keeps no new float objects
        self._offsets = np.zeros((nfeet, 2))
        self._global = np.zeros(2)
        self._swing = AdjustedSwing(step_height_m)
        self._span, self._goal, self._planned_goal = -1, [0.0, 0.0], [0.0, 0.0]
        self._shift_along = self._shift_lateral = 0.0
        self._asked = [0.0, 0.0, 0.0, 0.0]  # touchdown [frames], along, lateral, left [m]
        self._two = [0.0, 0.0, 0.0]  # one axis's two-step capture: u_1, u_2, left [m]
        # what the capture of a tick reads once _adjust is done: the DCM error and the plan's
        # DCM (along, across) [m], the landing's shift box [m], touchdown, earliest [frames]
        self._capture_inputs = [0.0] * 10
        self._two_pending = False
        self._stance_offset, self._touchdown, self._asking = [0.0, 0.0], 0.0, False
        self._active = self._modified = self._landed = self._moved = False
        self._reference: ReplannedZmpReference | None = None
        self._footholds: MeasuredFootholds | None = None
        self._lift, self._ahead, self._early = 0, 0, -1  # lift-off, lead, next early lift [-]
        self._planned_touchdown, self._uncaptured = 0.0, False  # the last capture left error
        self.replans_dcm = False
        """Whether :meth:`update` re-plans the DCM, ZMP and CoM references (the ``dcm`` walk)."""
        self.dcm_reference = ReplannedDcmReference(self._omega, self._dt, self._t_d)
        """The change of the DCM, ZMP and CoM references (:mod:`zmpkit.walking.replanned_dcm`)."""
        self.dcm_error_in_world = np.full((self._n, 2), np.nan)
        swing = max((s.touchdown - s.lift for s in self._steps), default=1)
        self._habit = DcmHabit(nfeet, swing, self.parameters.habit_rate)
        self._log = StepLog(len(self._steps), tuple(s.side for s in self._steps), self._dt)

    def attach_reference(self, reference_by_axis: list[NDArray[np.float64]]) -> None:
        """Re-plan this ZMP reference (one writable array per axis, [m]) with the steps."""
        self._reference = ReplannedZmpReference(reference_by_axis, self._steps, self._t_d_frames)

    def attach_footholds(self, footholds: MeasuredFootholds) -> None:
        """Place a moved step's foot where it is measured (:mod:`.measured_footholds`)."""
        if self.parameters.measured_footholds:
            self._footholds = footholds

    def update(self, frame: int, before: int, dcm_x_m: float, dcm_y_m: float) -> None:
        """Adjust the step under way and write the feet's targets of ``frame``.

        Args:
            frame: the frame whose targets are written [-] (< N).
            before: ``frame - 1``, the frame of the measured DCM [-].
            dcm_x_m: the measured DCM ``ξ̂`` of ``before`` (x) [m].
            dcm_y_m: the same (y) [m].
        """
        if not self.parameters.enabled:
            return
        j = self._step_at[frame]
        j = j if j >= self._span else self._span  # the step under way lifted early
        if j == self._span and 0 <= self._early <= frame:
            j += 1
        if j != self._span:
            self._begin(j, frame)
        if j >= 0:
            if frame < self._touchdown - self._min_remaining:
                self._adjust(j, frame, before, dcm_x_m, dcm_y_m)
            if self._asking:  # (after _adjust: a tick holds fewer floats at once)
                self._asking = False
                if self._two_pending:
                    self._two_pending = False
                    if not self._two_step(j, before):
                        self._one_step(j, before)
                asked = self._asked
                self._land_at(j, frame, asked[1], asked[2], asked[3], asked[0])
            if self._footholds is not None and not self._landed:
                self._watch_landing(j, frame)
            self._advance(j, frame)
        if self._moved:
            self._write_feet(j, frame)
        if self.replans_dcm:
            self._shift_dcm_reference(j, before)

    def _begin(self, j: int, frame: int) -> None:
        """A swing lifts off: start it towards the planned landing moved by the last offset.

        It lifts at ``frame``, earlier than planned when the step before it could not
        capture and landed early: its planned touchdown comes as much earlier.
        """
        self._span, self._early = j, -1
        if j < 0:
            return
        step = self._steps[j]
        lift = frame - 1 if frame - 1 < step.lift else step.lift
        self._lift, early = lift, step.lift - lift
        self._ahead = early  # frames this swing runs ahead of the plan
        offsets, o = self._offsets, self._global
        ox, oy = o.item(0), o.item(1)
        self._stance_offset[0] = offsets.item(step.stance, 0)
        self._stance_offset[1] = offsets.item(step.stance, 1)
        gx, gy = step.land_x + ox, step.land_y + oy
        target = self._feet[step.foot][2]
        self._planned_touchdown = self._touchdown = float(step.touchdown - early)
        self._swing.start(
            float(lift), target.item(lift, 0), target.item(lift, 1), gx, gy, self._touchdown
        )
        self._goal[0], self._goal[1] = gx, gy
        self._shift_along = self._shift_lateral = 0.0  # the landing against the plan's [m]
        self._modified = offsets.item(step.foot, 0) != ox or offsets.item(step.foot, 1) != oy
        if early > 0:
            self._modified = self._moved = True
        self._uncaptured = False
        if self._footholds is not None:
            self._footholds.lift()
        self._habit.begin(self._active)
        self._active = self._landed = False
        if self._reference is not None:
            start = self._stance_offset
            self._reference.begin(
                j, step.stance_x + start[0], step.stance_y + start[1], gx, gy, self._touchdown,
                ox, oy,
            )  # fmt: skip

    def _adjust(self, j: int, frame: int, before: int, dcm_x: float, dcm_y: float) -> None:
        """Re-plan the landing and touchdown of step ``j`` from the DCM of ``before``."""
        step, par, omega, dt = self._steps[j], self.parameters, self._omega, self._dt
        plan, ref = self._dcm_plan, before  # the plan's time of this swing (no int made
        if self._ahead:  # on the plan's clock: ints above 256 are objects)
            ref = before + self._ahead if before + self._ahead < self._n else self._n - 1
        ox, oy = self._stance_offset
        ex, ey = dcm_x - plan.item(ref, 0) - ox, dcm_y - plan.item(ref, 1) - oy
        ex, ey = self._habit.remove(step.foot, before - self._lift, ex, ey, self._active)
        errors = self.dcm_error_in_world
        errors[before, 0], errors[before, 1] = ex, ey
        c, s = step.cos_yaw, step.sin_yaw
        along, across = c * ex + s * ey, -s * ex + c * ey
        if not self._active:
            trigger_x, trigger_y = par.trigger_dcm_error_m
            if -trigger_x <= along <= trigger_x and -trigger_y <= across <= trigger_y:
                return
            if (frame + self._ahead if self._ahead else frame) > self._latest_trigger[j]:
                return
            self._active = True
            log = self._log
            log.trigger_frame[j] = before
            log.trigger_error[j, 0], log.trigger_error[j, 1] = ex, ey
        bx, by = plan.item(ref, 0) - step.stance_x, plan.item(ref, 1) - step.stance_y
        touchdown = self._planned_touchdown
        earliest = float(self._lift + self._min_swing[j])
        soonest = frame + self._min_remaining
        earliest = soonest if soonest > earliest else earliest
        earliest = touchdown if earliest > touchdown else earliest
        (m_x, m_y), (l_x, l_y) = self._cop_margin, par.landing_margin_m
        lo_x, hi_x, lo_y, hi_y = self.reach.shift_box(step.along, step.lateral, step.sign)
        if par.two_step:  # solved in update, once these locals are gone (fewer floats held)
            kept = self._capture_inputs
            kept[0], kept[1] = along, across
            kept[2], kept[3] = c * bx + s * by, -s * bx + c * by
            kept[4], kept[5] = lo_x, hi_x
            kept[6], kept[7] = lo_y, hi_y
            kept[8], kept[9] = touchdown, earliest
            self._asking = self._two_pending = True
            return
        sigma, d_along, d_across, left = solve_capture(
            along, across, c * bx + s * by, -s * bx + c * by,
            math.exp(omega * dt * (touchdown - before)), math.exp(omega * dt * (earliest - before)),
            self._kappa, m_x, m_y, l_x, l_y, lo_x, hi_x, lo_y, hi_y,
        )  # fmt: skip
        self._ask(j, before, sigma, d_along, d_across, left, touchdown, earliest)
        self._asking = True

    def _ask(
        self, j: int, before: int, sigma: float, d_along: float, d_across: float, left: float,
        touchdown: float, earliest: float,
    ) -> None:  # fmt: skip
        """Keep the one-step capture's touchdown and landing for :meth:`_land_at`."""
        step, omega_dt = self._steps[j], self._omega * self._dt
        landing = before + float(round(math.log(sigma) / omega_dt))
        asked = self._asked  # for _land_at, called once these locals are gone (see update)
        landing = earliest if landing < earliest else landing
        asked[0] = touchdown if landing > touchdown else landing
        asked[1], asked[2] = step.along + d_along, step.lateral + step.sign * d_across
        asked[3] = left

    def _one_step(self, j: int, before: int) -> None:
        """The one re-timed step that captures, or leaves the least (:func:`solve_capture`)."""
        kept, omega_dt, par = self._capture_inputs, self._omega * self._dt, self.parameters
        (m_x, m_y), (l_x, l_y) = self._cop_margin, par.landing_margin_m
        touchdown, earliest = kept[8], kept[9]
        sigma, d_along, d_across, left = solve_capture(
            kept[0], kept[1], kept[2], kept[3], math.exp(omega_dt * (touchdown - before)),
            math.exp(omega_dt * (earliest - before)), self._kappa, m_x, m_y, l_x, l_y,
            kept[4], kept[5], kept[6], kept[7],
        )  # fmt: skip
        self._ask(j, before, sigma, d_along, d_across, left, touchdown, earliest)

    def _two_step(self, j: int, before: int) -> bool:
        """Aim step ``j`` at the first of two steps that capture on the plan's timing.

        Reads what :meth:`_adjust` left: ``x_0 = ξ̂ - p_0`` (along, across the stance sole)
        [m] and the shifts of this landing the legs reach [m] (:meth:`~.StepReach.shift_box`),
        and overwrites its one-step answer when two steps capture.
        :func:`~zmpkit.walking.two_step_capture.solve_two_step` with the planned
        touchdowns (σ_1 to this one, σ_2 from it to the next) keeps this touchdown and
        lands nearest the plan where the next step, re-planned in its own swing, can
        capture; the second step's box is the legs' reach from the first landing (no
        crossing). False: no two steps on the plan's timing capture (then the one step,
        re-timed, that leaves the least is taken).
        """
        steps, reach, par = self._steps, self.reach, self.parameters
        if j + 1 >= len(steps):
            return False
        step, touchdown = steps[j], self._planned_touchdown
        omega_dt = self._omega * self._dt
        sigma_1 = math.exp(omega_dt * (touchdown - before))
        sigma_2 = math.exp(omega_dt * (steps[j + 1].touchdown - step.touchdown))
        (m_x, m_y), (l_x, l_y) = self._cop_margin, par.landing_margin_m
        kept = self._capture_inputs
        x0_along, x0_across = kept[0] + kept[2], kept[1] + kept[3]
        lo_x, hi_x, lo_y, hi_y = kept[4], kept[5], kept[6], kept[7]
        far, out = reach.max_along_m, self._two
        solve_two_step_into(
            out, x0_along, sigma_1, sigma_2, step.along, step.along + lo_x,
            step.along + hi_x, -far, far, m_x, l_x,
        )  # fmt: skip
        if out[2] > 0.0:
            return False
        first_x = out[0]
        planned = step.sign * step.lateral  # across, world side
        near, wide = reach.min_lateral_m, reach.max_lateral_m  # the next foot's, other side
        if step.sign > 0.0:
            lo_2, hi_2 = -wide, -near
        else:
            lo_2, hi_2 = near, wide
        solve_two_step_into(
            out, x0_across, sigma_1, sigma_2, planned, planned + lo_y, planned + hi_y, lo_2,
            hi_2, m_y, l_y,
        )  # fmt: skip
        if out[2] > 0.0:
            return False
        asked = self._asked
        asked[0], asked[1] = touchdown, first_x  # (pairs: four make a tuple)
        asked[2], asked[3] = step.sign * out[0], 0.0
        return True

    def _land_at(
        self, j: int, frame: int, along: float, lateral: float, left: float, touchdown: float
    ) -> None:
        """Aim step ``j``'s swing at the landing ``(along, lateral)`` of its stance sole.

        The landing is drawn into the legs' reach, then kept within ``a D² / 5.77`` of the
        planned one (``D`` the time left to touchdown; a shift already made is kept).
        """
        step = self._steps[j]
        along_in, lateral_in = self.reach.limit(along, lateral)
        time = (touchdown - frame) * self._dt
        limit = self.parameters.max_swing_acceleration_mps2 * time * time / 5.774
        bound = abs(self._shift_along)
        bound = limit if limit > bound else bound
        along_in = clip(along_in, step.along - bound, step.along + bound)
        bound = abs(self._shift_lateral)
        bound = limit if limit > bound else bound
        lateral_in = clip(lateral_in, step.lateral - bound, step.lateral + bound)
        moved = math.hypot(along_in - along, lateral_in - lateral)
        if moved > 1e-9:
            left += self._kappa * moved
        self._uncaptured = left > 0.0
        logged = self._log.left
        logged[j] = left if left > logged.item(j) else logged.item(j)
        c, s, across = step.cos_yaw, step.sin_yaw, step.sign * lateral_in
        gx = step.stance_x + self._stance_offset[0] + c * along_in - s * across
        gy = step.stance_y + self._stance_offset[1] + s * along_in + c * across
        goal = self._goal
        if (
            abs(gx - goal[0]) < _MOVED_M
            and abs(gy - goal[1]) < _MOVED_M
            and touchdown == self._touchdown
        ):
            return
        self._swing.retarget(float(frame), gx, gy, touchdown)
        goal[0], goal[1] = gx, gy
        self._shift_along, self._shift_lateral = along_in - step.along, lateral_in - step.lateral
        self._touchdown = touchdown
        self._modified = self._moved = True

    def _watch_landing(self, j: int, frame: int) -> None:
        """A moved swing that is down lands where it is measured, now.

        Every swing is watched from lift-off (a contact is a touchdown only after the foot
        was unloaded, :mod:`.measured_footholds`); only a moved one lands where measured.
        """
        step, feet = self._steps[j], self._footholds
        if feet is None or not feet.landed(step.foot, frame, self._lift, self._touchdown):
            return
        if not self._modified:
            return
        gx, gy = feet.at(step.foot, 0), feet.at(step.foot, 1)
        self._goal[0], self._goal[1] = gx, gy
        self._swing.land(float(frame), gx, gy)
        self._touchdown = float(frame)

    def _advance(self, j: int, frame: int) -> None:
        """The swing's target of ``frame``; at touchdown, the step's placement is kept."""
        self._swing.advance(float(frame))
        if self._landed or frame < self._touchdown:
            return
        step, goal = self._steps[j], self._goal
        ox, oy = goal[0] - step.land_x, goal[1] - step.land_y
        self._offsets[step.foot, 0], self._offsets[step.foot, 1] = ox, oy
        self._global[0], self._global[1] = ox, oy
        log = self._log
        log.shift[j, 0], log.shift[j, 1] = ox, oy
        log.landed_at[j] = (step.touchdown - frame) * self._dt
        self._landed = True
        early = step.touchdown - frame  # [frames]; the dcm walk's references keep the timing
        hurry = self._uncaptured and self.parameters.early_next_lift and not self.replans_dcm
        if hurry and early > 0 and j + 1 < len(self._steps):  # its transfer after its plan's
            early = early if early < self._min_swing[j + 1] else self._min_swing[j + 1]  # lift
            self._early = self._steps[j + 1].lift + 1 - early
        if self._early < 0:  # the plan's clock again: the double support lasts longer
            self._ahead = 0
        if self._reference is not None and self._modified:
            start = self._stance_offset
            self._reference.replan(
                j, step.stance_x + start[0], step.stance_y + start[1], goal[0], goal[1],
                self._touchdown, ox, oy,
            )  # fmt: skip
        if ox != 0.0 or oy != 0.0:
            self._moved = True

    def _write_feet(self, j: int, frame: int) -> None:
        """Each foot's target of ``frame``: the swing's, or its planned place and offset."""
        swinging = self._steps[j].foot if j >= 0 and self._modified else -1
        soles, now = self._soles, frame  # the others where the plan has them
        if self._ahead:
            now = frame + self._ahead if frame + self._ahead < self._n else self._n - 1
        for i, plan, target in self._feet:
            if i == swinging:
                swing = self._swing
                x, y, z = swing.x_m, swing.y_m, swing.z_m
                feet = self._footholds  # anchored where it is (measured_footholds)
                if feet is not None and not self._landed:
                    target[frame, 0], target[frame, 1], target[frame, 2] = x, y, z
                    soles[frame, i, 0], soles[frame, i, 1] = feet.at(i, 0), feet.at(i, 1)
                    soles[frame, i, 2] = feet.at(i, 2)
                    continue
            else:
                x = plan.item(now, 0) + self._offsets.item(i, 0)
                y = plan.item(now, 1) + self._offsets.item(i, 1)
                z = plan.item(now, 2)
            target[frame, 0], target[frame, 1], target[frame, 2] = x, y, z
            soles[frame, i, 0], soles[frame, i, 1], soles[frame, i, 2] = x, y, z

    def _shift_dcm_reference(self, j: int, before: int) -> None:
        """δξ, δp and the CoM reference that follows them, at ``before``.

        Until the foot is down the references are the plan's, moved by the last placement's
        offset: the controllers keep to the plan while the swing is re-planned.
        """
        if j < 0:
            return
        step, goal, touchdown = self._steps[j], self._goal, self._touchdown
        if not self._landed:
            goal, touchdown = self._planned_goal, float(step.touchdown)
            o = self._global
            goal[0], goal[1] = step.land_x + o.item(0), step.land_y + o.item(1)
        self.dcm_reference.update(step, before, self._stance_offset, goal, touchdown)

    def events(self) -> tuple[StepEvent, ...]:
        """The steps adjusted so far, in order."""
        return self._log.events()
