"""``zmpkit identify``: balance models and simulator parameters from recorded data."""

from __future__ import annotations

from pathlib import Path

import click

from zmpkit.cli.identify_plan import identify_plan_command
from zmpkit.cli.options import SEED, WORKERS, Bounded, BoundedInt, report_option
from zmpkit.cli.progress import GenerationProgress
from zmpkit.cli.robot_option import robot_option
from zmpkit.pipelines.identify_balance import run_identify_balance
from zmpkit.pipelines.identify_balance_files import write_identify_balance
from zmpkit.pipelines.identify_sim import IdentifySimConfig, IdentifySimResult, run_identify_sim
from zmpkit.pipelines.identify_sim_files import write_identify_sim
from zmpkit.robots.registry import DEFAULT_FIT_ROBOT
from zmpkit.robots.robot import Robot
from zmpkit.simfit.least_squares_refit import REFINEMENTS, refinement_line
from zmpkit.simfit.optimizer import MAX_POPSIZE, MAX_RESTARTS, FitInterruptedError
from zmpkit.simfit.pooled_cost import WINDOW_POOLINGS
from zmpkit.simfit.refit_intervals import REFIT_REPLICAS, ParameterInterval
from zmpkit.simfit.shooting_window import DEFAULT_BURN_IN_S, DEFAULT_WINDOW_S

__all__ = [
    "identify_balance_command",
    "identify_compare_command",
    "identify_group",
    "identify_sim_command",
]

MAX_MASS_KG = 1000.0
"""Heaviest pendulum mass ``--mass`` takes [kg]: a tonne, beyond any humanoid."""
MAX_LENGTH_M = 5.0
"""Longest pendulum ``--length`` takes [m]: ankle to CoM of a humanoid is 0.2 to 1.2 m."""
MAX_GENERATIONS = 100_000
"""Most CMA-ES generations ``--generations`` takes."""


@click.group("identify")
def identify_group() -> None:
    """Identify models of the robot from recorded data."""


identify_group.add_command(identify_plan_command)


@identify_group.command("balance")
@click.argument("dataset", type=click.Path(path_type=Path))
@click.option(
    "--out", "out_dir", type=click.Path(path_type=Path), required=True, help="Output folder."
)
@click.option(
    "--mass",
    type=Bounded(0.0, MAX_MASS_KG, "kg", low_open=True),
    help="Pendulum mass [kg] (default: the robot's design).",
)
@click.option(
    "--length",
    type=Bounded(0.0, MAX_LENGTH_M, "m", low_open=True),
    help="Pendulum length, ankle to CoM [m] (default: the dataset's lean length).",
)
@robot_option(
    None,
    needs="balance",
    help_text="A step dataset's robot, whose design mass is the pendulum's (default: the one "
    "its meta.json records)",
)
@report_option
def identify_balance_command(
    dataset: Path,
    out_dir: Path,
    mass: float | None,
    length: float | None,
    robot: str | None,
    report_format: str,
) -> None:
    """Fit the steady-state ZMP error model (eq. 13) and transients of recorded steps.

    DATASET is a step dataset folder (zmpkit sim push) or a step manifest .yaml listing a
    robot's logs (CSV, Parquet, ROS 2 bag, YARP dump) with each step's target and time.
    """
    identified = run_identify_balance(dataset, mass_kg=mass, length_m=length, robot=robot)
    result = write_identify_balance(identified, out_dir, report_format)
    plane = next(iter(result.identification.planes.values()))
    click.echo(f"{plane.error_fit.model.equation}: {dict(plane.error_fit.model.as_dict())}")
    files = result.files
    click.echo(f"wrote {files['params']}, {files['figure']} and {files['report']}")


@identify_group.command("sim")
@click.argument("data", nargs=-1, type=click.Path(path_type=Path))
@robot_option(DEFAULT_FIT_ROBOT, needs="fit", as_robot=True)
@click.option(
    "--effects",
    default="M,G",
    show_default=True,
    help="Effects whose parameters are fitted: letters M, I, G, F, S, C (mass/CoM: CAD vs "
    "real, e.g. a payload or the torso).",
)
@click.option(
    "--out", "out_dir", type=click.Path(path_type=Path), required=True, help="Output folder."
)
@click.option(
    "--backend",
    type=click.Choice(("local", "pool", "serial", "ray", "warp")),
    default="local",
    show_default=True,
    help="Where rollouts run: MuJoCo thread-pool batches here (local), a local process "
    "pool, this process one by one, a Ray cluster, or MuJoCo Warp batches on a GPU.",
)
@click.option("--address", help="Ray cluster address (with --backend ray), e.g. HOST:6379.")
@click.option(
    "--resume",
    type=click.Path(path_type=Path),
    help="Continue the fit checkpointed in this folder.",
)
@click.option(
    "--generations",
    type=BoundedInt(1, MAX_GENERATIONS),
    help="CMA-ES generations per run (default 40; 30 quick), at CMA-ES's default "
    "population; a larger default population runs G ln(λ0)/ln(λ).",
)
@click.option(
    "--popsize",
    type=BoundedInt(4, MAX_POPSIZE),
    help="Candidates per CMA-ES generation (default CMA-ES's 4 + 3 ln n, or what the "
    "backend evaluates in the time of one if more: 256 on a GPU, a Ray cluster's CPUs; "
    "with correspondingly fewer generations).",
)
@click.option(
    "--restarts",
    type=BoundedInt(0, MAX_RESTARTS),
    help="IPOP-CMA-ES: after a run stops, restart from a random point with twice the "
    "population, keeping the best of all runs (--generations is per run; --popsize the "
    "first run's). Default: as many as fit in the wall time of one run at CMA-ES's default "
    "population on this backend.",
)
@click.option(
    "--workers", type=WORKERS, default=2, show_default=True, help="Local threads or processes."
)
@click.option("--seed", type=SEED, default=1, show_default=True, help="Seed of the fit.")
@click.option("--quick", is_flag=True, help="A small, fast fit (2-3 parameters).")
@click.option(
    "--self-test",
    is_flag=True,
    help="Record experiments from a seed-perturbed robot, fit them, write recovery.csv.",
)
@click.option(
    "--designed",
    is_flag=True,
    help="With --self-test: also record and fit the designed double-support experiments "
    "(crouch_hold, squat, sway_sagittal, sway_frontal; see zmpkit identify plan).",
)
@click.option(
    "--refine",
    type=click.Choice(REFINEMENTS),
    default="none",
    show_default=True,
    help="After CMA-ES: lm refines its best by Levenberg-Marquardt on the cost's residuals "
    "(a Jacobian a batch; kept where cheaper; refinement.json), on this machine's CPUs.",
)
@click.option(
    "--sensor-readings",
    type=click.Choice(("sampled", "expected")),
    default="sampled",
    show_default=True,
    help="The simulated sensors: their whole chain with noise and quantisation (sampled), "
    "or their expected readings (no noise, no quantisation: a smoother cost).",
)
@click.option(
    "--window-pooling",
    type=click.Choice(WINDOW_POOLINGS),
    default="mean",
    show_default=True,
    help="How a walk log's windows enter the cost: their mean, or their median (a window "
    "whose replay diverged from its estimated start does not decide the fit; falls are "
    "charged in full).",
)
@click.option(
    "--held-out",
    multiple=True,
    type=click.Path(path_type=Path),
    help="Recorded experiments checked but not fitted (repeatable).",
)
@click.option(
    "--window",
    "window_s",
    type=Bounded(0.0, 60.0, "s", low_open=True),
    default=DEFAULT_WINDOW_S,
    show_default=True,
    help="A walk log's multiple-shooting windows [s], each replayed from its measured state "
    "(its first --burn-in not scored).",
)
@click.option(
    "--burn-in",
    "burn_in_s",
    type=Bounded(0.0, 30.0, "s"),
    default=DEFAULT_BURN_IN_S,
    show_default=True,
    help="The unscored start of each multiple-shooting window [s], shorter than --window: "
    "long enough for what the sensors do not see to settle (longer on a heavy, compliant "
    "robot).",
)
@click.option(
    "--interval-replicas",
    type=click.IntRange(min=0),
    default=REFIT_REPLICAS,
    show_default=True,
    help="Walk logs: replicas of the fitted model recorded through the data's pipeline (a "
    "zmpkit walk log walked again with its controller; any other log's windows replayed "
    "again from earlier and re-cut from the replica's own sensors), each re-fitted, for 95 % "
    "intervals that hold the estimator's bias (0: noise-only intervals).",
)
@report_option
def identify_sim_command(
    data: tuple[Path, ...],
    robot: Robot,
    effects: str,
    out_dir: Path,
    backend: str,
    address: str | None,
    resume: Path | None,
    generations: int | None,
    popsize: int | None,
    restarts: int | None,
    workers: int,
    seed: int,
    quick: bool,
    self_test: bool,
    designed: bool,
    refine: str,
    sensor_readings: str,
    window_pooling: str,
    held_out: tuple[Path, ...],
    window_s: float,
    burn_in_s: float,
    interval_replicas: int,
    report_format: str,
) -> None:
    """Fit the simulator's effect parameters to recorded DATA.

    DATA: walk folders (zmpkit walk), step datasets, or walk logs of any controller (a
    .csv/.parquet with time, cmd_<joint>, enc_<joint>, imu_quat_w..z and the F-T columns
    right_fx..left_tz, or a folder holding walk_log.csv), fitted by multiple shooting.
    """
    config = IdentifySimConfig(
        data=tuple(str(d) for d in data),
        robot=robot,
        effects=effects,
        held_out=tuple(str(h) for h in held_out),
        backend=backend,
        address=address,
        workers=workers,
        resume=None if resume is None else str(resume),
        generations=generations,
        popsize=popsize,
        restarts=restarts,
        seed=seed,
        quick=quick,
        self_test=self_test,
        designed=designed,
        refine=refine,
        sensor_readings=sensor_readings,
        window_pooling=window_pooling,
        window_s=window_s,
        burn_in_s=burn_in_s,
        interval_replicas=interval_replicas,
    )
    try:
        with GenerationProgress() as progress:
            fit = run_identify_sim(
                config, out_dir, progress=progress, replica_progress=progress.replicas
            )
    except FitInterruptedError as exc:  # Ctrl-C: every finished generation is checkpointed
        click.echo(f"zmpkit: {exc}", err=True)
        raise click.exceptions.Exit(130) from None
    _echo_result(write_identify_sim(fit, out_dir, report_format), out_dir)


def _echo_result(result: IdentifySimResult, out_dir: Path) -> None:
    """The fitted values, their intervals, the adequacy verdict and the files, on stdout."""
    intervals = {i.name: i for i in result.intervals}
    for name, value in result.fitted.items():
        interval = intervals.get(name)
        if interval is None or interval.half_width != interval.half_width:  # NaN: unmeasured
            click.echo(f"{name} = {value:.6g}")
        else:
            click.echo(f"{name} = {value:.6g}, {_interval_text(interval)}")
    if result.intervals:
        click.echo(f"intervals: {result.intervals[0].method}")
    if result.refinement is not None:
        click.echo(refinement_line(result.refinement))
    if result.adequacy is not None:
        click.echo(result.adequacy.verdict)
    if "recovery" in result.files:
        click.echo(f"recovery: {result.files['recovery']}")
    click.echo(f"fitted truth: {Path(out_dir) / 'fitted_truth.yaml'} (best cost {result.cost:.4g})")
    click.echo(f"report: {result.files['report']}")


def _interval_text(interval: ParameterInterval) -> str:
    """``95 % interval [lo, hi] (±w %)``, with its centre and the bias when corrected."""
    text = f"95 % interval [{interval.lower:.6g}, {interval.upper:.6g}]"
    if interval.bias == interval.bias:  # a bias was estimated
        return (
            f"{text} about the bias-corrected {interval.corrected:.6g} (estimator bias "
            f"{100 * interval.bias:+.2g} %, ±{100 * interval.half_width:.2g} %)"
        )
    return f"{text} (±{100 * interval.half_width:.2g} %)"


@identify_group.command("compare")
@click.argument("fit_a", type=click.Path(path_type=Path))
@click.argument("fit_b", type=click.Path(path_type=Path))
def identify_compare_command(fit_a: Path, fit_b: Path) -> None:
    """Do two simulator fits agree? Each parameter against the fits' resolutions.

    FIT_A and FIT_B are folders written by ``zmpkit identify sim`` (or their
    fitted_parameters.yaml) of the same robot and effects: another backend (Warp on a GPU
    against the CPU), seed or data set. A parameter agrees when the fits differ by no more
    than the larger of their resolutions (the step at which the cost rises visibly); one
    that either fit finds not identifiable is shown, not judged. Exit status 0 when every
    judged parameter agrees, 1 when one does not (as diff), 2 on bad input.
    """
    from zmpkit.simfit.fit_agreement import compare_fits

    result = compare_fits(fit_a, fit_b)
    click.echo(f"{'parameter':24s} {'A':>12s} {'B':>12s} {'B-A':>9s} {'within':>8s}  verdict")
    for p in result.parameters:
        verdict = "not judged" if p.agree is None else ("agree" if p.agree else "DIFFER")
        within = "inf" if p.tolerance == float("inf") else f"{100 * p.tolerance:.2f}%"
        click.echo(
            f"{p.name:24s} {p.value_a:12.6g} {p.value_b:12.6g} {100 * p.difference:+8.2f}% "
            f"{within:>8s}  {verdict}{'' if p.judged else ' (not identifiable)'}"
        )
    differ = [p.name for p in result.parameters if p.agree is False]
    if differ:
        click.echo(f"the fits differ in {', '.join(differ)}")
        raise click.exceptions.Exit(1)
    click.echo("the fits agree in every identifiable parameter")
