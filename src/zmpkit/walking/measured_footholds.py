r"""Where the feet of an adjusted step are: measured, not commanded (leg odometry).

The state estimator (:mod:`zmpkit.walking.state_estimator`) places the robot by the feet in
contact, each where the walk says it is, ``Δ = Σ F_{z,i} (\hat s_i - s_i) / Σ F_{z,i}``.
For the plan's own steps that is where the plan put them. A step the step adjustment moves
(:mod:`zmpkit.walking.step_adjustment`) does not land where it was aimed: a robot tilted by
a push meets the ground early, short of its goal, and its foot then stays there. With the
commanded landing as its anchor the estimate was carried with the command: after a 20 N
push along x (``zmpip``, the built-in walker, all effects) the foot landed 3.5 cm short
and slipped 3 cm more; the swing foot that followed scuffed the ground while its goal moved
13 cm forward; the estimated DCM error then read +16 to +34 cm along x while the
simulator's was -7 to -14 cm, and the steps went the wrong way.

So for a step whose swing was re-planned:

- **while it swings**, its anchor is where the estimate from the other feet places it,
  ``\hat s_i = s_i + Δ`` (a scuff then adds nothing: ``\hat s_i - s_i = Δ``);
- **it lands** at its first contact (``F_z`` at least the contact threshold) after
  :attr:`~.StepAdjustmentParameters.touchdown_contact_fraction` of its swing *and after it
  was in the air* (``F_z`` below the threshold since lift-off), or at its re-planned
  touchdown, whichever comes first. A foot that never left the ground is not landing: after
  a 20 N push along -y at a quarter of the seventh step (``zmpip``, all effects) the robot
  rolled 0.36 rad over its right sole's outer edge, the left foot hung 2.4 to 4.3 cm above the
  ground with 1 N on it, and the right foot, lifted on the plan's clock, kept 45 to 113 N on it
  through its whole swing: its unbroken contact was taken for a touchdown at half the swing,
  0.23 s early and 20 cm behind its goal (what the step events then reported);
- **once down** it is where it was measured at that tick: its anchor and its IK target
  (the IK no longer drags a loaded foot towards a goal it did not reach), and the landing
  offset every later step moves by, ``o = G_{measured} - U``.

The plan's steps keep the plan's anchors: a walk that is not pushed walks as before.
"""

from __future__ import annotations

from zmpkit.walking.state_estimator import KinematicStateEstimator

__all__ = ["MeasuredFootholds"]


class MeasuredFootholds:
    """The measured sole positions and touchdowns of a walk's moved steps (module docstring).

    Args:
        estimator: the walk's state estimator (updated before each tick's adjustment).
        contact_fraction: the share of a swing after which a contact is its touchdown [-].
    """

    def __init__(self, estimator: KinematicStateEstimator, contact_fraction: float) -> None:
        self._estimator = estimator
        self._force_z = estimator.force_z_n
        self._threshold = estimator.threshold_n
        self._fraction = contact_fraction
        self._airborne = False  # the swing foot was unloaded since lift-off

    def lift(self) -> None:
        """A swing lifts off: none of its contacts is a touchdown until it is unloaded."""
        self._airborne = False

    def landed(self, foot: int, frame: int, lift: int, touchdown: float) -> bool:
        """Whether swing ``foot`` is down at ``frame`` [-], lifted at ``lift`` [-].

        Down: in contact after the share of the swing to ``touchdown`` [frames] and after it
        was unloaded since :meth:`lift`, or at ``touchdown``. Called every frame of the swing
        (it watches for the foot being unloaded).
        """
        loaded = self._force_z.item(foot) >= self._threshold
        if not loaded:
            self._airborne = True
        if frame >= touchdown:
            return True
        if frame < lift + self._fraction * (touchdown - lift):
            return False
        return loaded and self._airborne

    def at(self, foot: int, axis: int) -> float:
        """The measured sole centre of ``foot`` along ``axis`` (0 x, 1 y, 2 z) [m]."""
        return self._estimator.sole_in_world(foot, axis)
