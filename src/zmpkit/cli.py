"""The ``zmpkit`` command. Thin: parse, build a configuration, call one library function.

Every user mistake (bad file, bad option) ends with one line on stderr and exit code 2.
"""

from __future__ import annotations

import sys
from collections.abc import Sequence
from pathlib import Path

import click

from zmpkit import __version__
from zmpkit.errors import ZmpkitError

__all__ = ["cli", "main"]

ROBOT_CHOICES = ("teo",)
EXIT_USAGE = 2


@click.group(context_settings={"help_option_names": ["-h", "--help"]})
@click.version_option(__version__, "--version", prog_name="zmpkit")
def cli() -> None:
    """zmpkit: measure, model and compensate the gap between the LIPM and the real robot."""


@cli.command("zmp")
@click.argument("log", type=click.Path(path_type=Path))
@click.option("--right-topic", help="ROS 2 bag: WrenchStamped topic of the right foot.")
@click.option("--left-topic", help="ROS 2 bag: WrenchStamped topic of the left foot.")
@click.option(
    "--units",
    "units_path",
    type=click.Path(path_type=Path),
    help="Units/frames YAML: axis order, signs, N vs daN, N·m vs dN·m, mounting rotation.",
)
@click.option(
    "--time-source",
    type=click.Choice(("header", "receive")),
    default="header",
    show_default=True,
    help="Bags and YARP logs: the message header (sender) stamp or the receive time.",
)
@click.option(
    "--feet",
    "feet_path",
    type=click.Path(path_type=Path),
    help="FEET.yaml: each foot's sensor position [m], rpy [rad] and sole_height [m].",
)
@click.option(
    "--robot",
    type=click.Choice(ROBOT_CHOICES),
    help="Use a built-in robot's sensor mounts instead of --feet.",
)
@click.option(
    "--columns",
    "columns_path",
    type=click.Path(path_type=Path),
    help="Column-map YAML {canonical_name: header_in_file} for logs with other headers.",
)
@click.option(
    "--contact-threshold",
    type=float,
    default=None,
    help="Minimum normal force for a foot to be in contact [N] (default 10).",
)
@click.option(
    "--out", "out_dir", type=click.Path(path_type=Path), required=True, help="Output folder."
)
def zmp_command(
    log: Path,
    right_topic: str | None,
    left_topic: str | None,
    units_path: Path | None,
    time_source: str,
    feet_path: Path | None,
    robot: str | None,
    columns_path: Path | None,
    contact_threshold: float | None,
    out_dir: Path,
) -> None:
    """ZMP of a recorded force-torque LOG: CSV, Parquet, ROS 2 bag (folder, .db3, .mcap) or
    YARP dump folder; writes zmp.csv and zmp.png."""
    from zmpkit.pipelines.zmp_log import run_zmp_log
    from zmpkit.sensors import CONTACT_FORCE_THRESHOLD_N

    if (feet_path is None) == (robot is None):
        raise click.UsageError("give exactly one of --feet FEET.yaml or --robot ROBOT")
    feet = _robot_feet(robot) if robot is not None else None
    threshold = CONTACT_FORCE_THRESHOLD_N if contact_threshold is None else contact_threshold
    result = run_zmp_log(
        log,
        out_dir,
        feet=feet,
        feet_path=feet_path,
        columns_path=columns_path,
        contact_threshold_n=threshold,
        right_topic=right_topic,
        left_topic=left_topic,
        units_path=units_path,
        time_source=time_source,
    )
    s = result.series
    click.echo(
        f"{len(s.time)} samples, ZMP defined on {len(s.time) - s.n_undefined}; "
        f"wrote {result.csv_path} and {result.figure_path}"
    )


@cli.command("demo")
@click.option(
    "--out", "out_dir", type=click.Path(path_type=Path), default=Path("out/demo"), show_default=True
)
def demo_command(out_dir: Path) -> None:
    """Run the main job on the built-in virtual robot and write a report to --out."""
    from zmpkit.pipelines.demo import run_demo

    result = run_demo(out_dir, echo=click.echo)
    click.echo(f"report: {result.report_path}")


@cli.group("sim")
def sim_group() -> None:
    """Run experiments on a virtual robot and write their datasets and analyses."""


@sim_group.command("push")
@click.option("--robot", default="teo", show_default=True, help="Virtual robot: teo.")
@click.option(
    "--targets",
    default="0:0.10:0.01",
    show_default=True,
    help="ZMP targets [m]: START:STOP:STEP (stop included) or a comma list, e.g. 0,0.05.",
)
@click.option(
    "--plane", default="sagittal", show_default=True, help="sagittal (ZMP x) or frontal (ZMP y)."
)
@click.option(
    "--effects",
    default="all",
    show_default=True,
    help="Simulated effects: all, none, or letters M,I,G,F,S (motor, inductance, gear, flex, "
    "sensors).",
)
@click.option("--seed", type=int, default=0, show_default=True, help="Seed of the sensor noise.")
@click.option(
    "--out",
    "out_dir",
    type=click.Path(path_type=Path),
    required=True,
    help="Output folder (resumed if it holds the same sweep).",
)
@click.option(
    "--truth", type=click.Path(path_type=Path), help="Truth YAML replacing the shipped one."
)
@click.option("--push-force", type=float, help="Push at the CoM along the plane's axis [N].")
@click.option("--push-duration", type=float, help="Duration of the push [s].")
@click.option("--hold", type=float, help="Recorded time after the step [s] (default 15).")
@click.option("--workers", type=int, default=2, show_default=True, help="Parallel processes.")
def sim_push_command(
    robot: str,
    targets: str,
    plane: str,
    effects: str,
    seed: int,
    out_dir: Path,
    truth: Path | None,
    push_force: float | None,
    push_duration: float | None,
    hold: float | None,
    workers: int,
) -> None:
    """ZMP step / push sweep (paper A Fig. 14): dataset, steady_state.csv and steps.png."""
    from zmpkit.pipelines.sim_push import run_sim_push, sim_push_config

    config = sim_push_config(
        robot=robot,
        targets=targets,
        plane=plane,
        effects=effects,
        seed=seed,
        truth=truth,
        push_force=push_force,
        push_duration=push_duration,
        hold=hold,
    )
    from zmpkit.pipelines.progress import TrialProgressBar

    with TrialProgressBar(len(config.targets_m)) as progress:
        result = run_sim_push(config, out_dir, workers=workers, progress=progress)
    for line in result.warnings:
        click.echo(f"warning: {line}", err=True)
    click.echo(
        f"{len(result.dataset.trials)} trials in {out_dir}; wrote "
        f"{result.steady_state_path} and {result.figure_path}"
    )


@cli.command("balance")
@click.option("--robot", type=click.Choice(ROBOT_CHOICES), default="teo", show_default=True)
@click.option(
    "--out",
    "out_dir",
    type=click.Path(path_type=Path),
    required=True,
    help="Output folder (resumed: finished trials are kept).",
)
@click.option("--quick", is_flag=True, help="Fewer targets and shorter holds (under 2 min).")
@click.option(
    "--truth",
    type=click.Path(path_type=Path),
    help="Truth YAML replacing the virtual robot's shipped one.",
)
@click.option("--seed", type=int, default=0, show_default=True, help="Seed of the sensor noise.")
@click.option(
    "--effects",
    default="all",
    show_default=True,
    help="Simulated effects: all, none, or letters M,I,G,F,S.",
)
@click.option(
    "--plane",
    "planes",
    multiple=True,
    type=click.Choice(("sagittal", "frontal")),
    help="Plane(s) to run; default both.",
)
@click.option("--workers", type=int, default=2, show_default=True, help="Parallel processes.")
@click.option(
    "--dlipm-pace",
    type=click.Choice(("servo", "paper")),
    default="servo",
    show_default=True,
    help="servo: the fastest DLIPM the servos' acceleration limit allows, per target; "
    "paper: paper A's fixed time scale sqrt(180/pi).",
)
def balance_command(
    robot: str,
    out_dir: Path,
    quick: bool,
    truth: Path | None,
    seed: int,
    effects: str,
    planes: tuple[str, ...],
    workers: int,
    dlipm_pace: str,
) -> None:
    """Paper A end to end: LIPM steps, DLIPM identification, scheduled controller, Table 1."""
    from zmpkit.pipelines.balance import BalanceConfig
    from zmpkit.pipelines.balance_run import balance_with_progress

    changes = {
        "robot": robot,
        "seed": seed,
        "effects": effects,
        "workers": workers,
        "truth": None if truth is None else str(truth),
    }
    if planes:
        changes["planes"] = planes
    if dlipm_pace == "paper":
        from zmpkit.control import PAPER_A_TIME_SCALE

        changes.update(time_scale=PAPER_A_TIME_SCALE, servo_paced=False)
    config = BalanceConfig.quick(**changes) if quick else BalanceConfig(**changes)
    artifacts = balance_with_progress(config, out_dir, echo=click.echo)
    click.echo(f"report: {artifacts.report}")


@cli.group("walk", invoke_without_command=True)
@click.option("--robot", type=click.Choice(("nao",)), default="nao", show_default=True)
@click.option("--speed", type=float, default=0.2, show_default=True, help="Forward speed [m/s].")
@click.option(
    "--step-duration", type=float, default=0.5, show_default=True, help="Duration of one step [s]."
)
@click.option("--duration", type=float, default=10.0, show_default=True, help="Walking time [s].")
@click.option(
    "--effects",
    default="all",
    show_default=True,
    help="Simulated effects: all, none, or letters M,I,G,F,S.",
)
@click.option("--seed", type=int, default=0, show_default=True, help="Seed of the sensor noise.")
@click.option(
    "--truth",
    type=click.Path(path_type=Path),
    help="Truth YAML replacing the virtual robot's shipped one.",
)
@click.option(
    "--out",
    "out_dir",
    type=click.Path(path_type=Path),
    help="Output folder (required when walking).",
)
@click.pass_context
def walk_group(
    ctx: click.Context,
    robot: str,
    speed: float,
    step_duration: float,
    duration: float,
    effects: str,
    seed: int,
    truth: Path | None,
    out_dir: Path | None,
) -> None:
    """Walk the virtual robot with the 3D-LIPM pattern (paper B) and analyse the walk."""
    if ctx.invoked_subcommand is not None:
        return
    if out_dir is None:
        raise click.UsageError("walking needs --out DIR")
    from zmpkit.pipelines.progress import SimTimeProgress
    from zmpkit.pipelines.walk import WalkConfig, run_walk

    config = WalkConfig(
        robot=robot,
        speed_mps=speed,
        step_duration_s=step_duration,
        duration_s=duration,
        effects=effects,
        seed=seed,
        truth=None if truth is None else str(truth),
    )
    with SimTimeProgress(f"walk ({config.effects or 'none'})") as progress:
        result = run_walk(config, out_dir, progress=progress)
    s = result.summary
    click.echo(
        f"fell: {s.fell}; speed {_num(s.mean_speed_mps, '.4f')} m/s (commanded "
        f"{s.commanded_speed_mps:.4f}); trunk pitch peak {_num(s.trunk_pitch_peak_hz, '.2f')} "
        f"Hz, {_num(s.trunk_pitch_peak_amplitude_rad, '.4f')} rad"
    )
    click.echo(f"summary: {Path(out_dir) / 'summary.json'}")


@walk_group.command("compensate")
@click.option(
    "--method",
    type=click.Choice(("alg1", "alg2", "half-sine", "sawtooth", "fourier", "auto")),
    default="auto",
    show_default=True,
    help="alg1/alg2: paper B's Algorithms 1 and 2; half-sine, sawtooth, fourier: a tuned "
    "periodic offset on the desired ZMP; auto: tune every shape and keep the best.",
)
@click.option("--robot", type=click.Choice(("nao",)), default="nao", show_default=True)
@click.option("--quick", is_flag=True, help="Fewer tuning walks (under 5 min on 2 cores).")
@click.option("--speed", type=float, default=0.2, show_default=True, help="Tuning speed [m/s].")
@click.option("--effects", default="all", show_default=True, help="Simulated effects.")
@click.option("--seed", type=int, default=0, show_default=True, help="Seed of the sensor noise.")
@click.option("--workers", type=int, default=2, show_default=True, help="Parallel processes.")
@click.option(
    "--out", "out_dir", type=click.Path(path_type=Path), required=True, help="Output folder."
)
def walk_compensate_command(
    method: str,
    robot: str,
    quick: bool,
    speed: float,
    effects: str,
    seed: int,
    workers: int,
    out_dir: Path,
) -> None:
    """Compensate the walk's model abstractions; validate on walks not used for tuning."""
    from zmpkit.pipelines.progress import StageProgress
    from zmpkit.pipelines.walk_compensate import CompensateConfig, run_walk_compensate

    config = CompensateConfig(
        method=method,
        robot=robot,
        quick=quick,
        speed_mps=speed,
        effects=effects,
        seed=seed,
        workers=workers,
    )
    with StageProgress() as progress:
        result = run_walk_compensate(config, out_dir, progress=progress)
    s = result.summary
    if s["peak_reduction_pct"] is None:
        click.echo(f"{s['method']}: no validation walk where both versions stood to compare")
    else:
        click.echo(
            f"{s['method']}: step-frequency peak {s['peak_reduction_pct']:.1f} % lower, "
            f"oscillation std {s['std_reduction_pct']:.1f} % lower on "
            f"{s['walks_compared']} validation walks; compensated falls: "
            f"{s['compensated_falls']}"
        )
    click.echo(f"summary: {Path(out_dir) / 'summary.json'}")


@cli.group("identify")
def identify_group() -> None:
    """Identify models of the robot from recorded data."""


@identify_group.command("balance")
@click.argument("dataset", type=click.Path(path_type=Path))
@click.option(
    "--out", "out_dir", type=click.Path(path_type=Path), required=True, help="Output folder."
)
@click.option("--mass", type=float, help="Pendulum mass [kg] (default: the robot's design).")
@click.option(
    "--length",
    type=float,
    help="Pendulum length, ankle to CoM [m] (default: the dataset's lean length).",
)
def identify_balance_command(
    dataset: Path, out_dir: Path, mass: float | None, length: float | None
) -> None:
    """Fit the steady-state ZMP error model (eq. 13) and transients of a step DATASET."""
    from zmpkit.pipelines.identify_balance import run_identify_balance

    result = run_identify_balance(dataset, out_dir, mass_kg=mass, length_m=length)
    plane = next(iter(result.identification.planes.values()))
    click.echo(f"{plane.error_fit.model.equation}: {dict(plane.error_fit.model.as_dict())}")
    click.echo(f"wrote {result.params_path}, {result.figure_path} and {result.summary_path}")


@identify_group.command("sim")
@click.argument("data", nargs=-1, type=click.Path(path_type=Path))
@click.option("--robot", type=click.Choice(("nao", "teo")), default="nao", show_default=True)
@click.option(
    "--effects",
    default="M,G",
    show_default=True,
    help="Effects whose parameters are fitted: letters M, I, G, F, S, C (mass/CoM, TEO).",
)
@click.option(
    "--out", "out_dir", type=click.Path(path_type=Path), required=True, help="Output folder."
)
@click.option(
    "--backend",
    type=click.Choice(("local", "serial", "ray")),
    default="local",
    show_default=True,
    help="Where rollouts run: a local process pool, this process, or a Ray cluster.",
)
@click.option("--address", help="Ray cluster address (with --backend ray), e.g. HOST:6379.")
@click.option(
    "--resume",
    type=click.Path(path_type=Path),
    help="Continue the fit checkpointed in this folder.",
)
@click.option("--generations", type=int, help="CMA-ES generations (default 40; 30 quick).")
@click.option("--workers", type=int, default=2, show_default=True, help="Local processes.")
@click.option("--seed", type=int, default=1, show_default=True, help="Seed of the fit.")
@click.option("--quick", is_flag=True, help="A small, fast fit (2-3 parameters).")
@click.option(
    "--self-test",
    is_flag=True,
    help="Record experiments from a seed-perturbed robot, fit them, write recovery.csv.",
)
@click.option(
    "--held-out",
    multiple=True,
    type=click.Path(path_type=Path),
    help="Recorded experiments checked but not fitted (repeatable).",
)
def identify_sim_command(
    data: tuple[Path, ...],
    robot: str,
    effects: str,
    out_dir: Path,
    backend: str,
    address: str | None,
    resume: Path | None,
    generations: int | None,
    workers: int,
    seed: int,
    quick: bool,
    self_test: bool,
    held_out: tuple[Path, ...],
) -> None:
    """Fit the simulator's effect parameters to recorded DATA (walk folders, step datasets)."""
    from zmpkit.identify.simfit.optimizer import FitInterruptedError
    from zmpkit.pipelines.identify_sim import IdentifySimConfig, run_identify_sim
    from zmpkit.pipelines.progress import GenerationProgress

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
        seed=seed,
        quick=quick,
        self_test=self_test,
    )
    try:
        with GenerationProgress() as progress:
            result = run_identify_sim(config, out_dir, progress=progress)
    except FitInterruptedError as exc:  # Ctrl-C: every finished generation is checkpointed
        click.echo(f"zmpkit: {exc}", err=True)
        raise click.exceptions.Exit(130) from None
    for name, value in result.fitted.items():
        click.echo(f"{name} = {value:.6g}")
    if "recovery" in result.files:
        click.echo(f"recovery: {result.files['recovery']}")
    click.echo(f"fitted truth: {Path(out_dir) / 'fitted_truth.yaml'} (best cost {result.cost:.4g})")


def _num(value: float | None, spec: str) -> str:
    """``value`` formatted, or "undefined" (e.g. a walk too short to fit its speed)."""
    return "undefined" if value is None else format(value, spec)


def _robot_feet(robot: str):
    from zmpkit.io import feet_from_mapping

    if robot == "teo":
        from zmpkit.robots.teo import teo_feet_mounts

        return feet_from_mapping(teo_feet_mounts(), source="built-in robot 'teo'")
    raise click.UsageError(f"unknown robot {robot!r}; valid: {', '.join(ROBOT_CHOICES)}")


def main(argv: Sequence[str] | None = None) -> int:
    """Run the CLI and return its exit code (tests call this with ``argv``)."""
    args = list(sys.argv[1:] if argv is None else argv)
    try:
        result = cli.main(args=args, prog_name="zmpkit", standalone_mode=False)
    except click.ClickException as exc:
        exc.show()
        return exc.exit_code
    except click.Abort:
        click.echo("zmpkit: aborted", err=True)
        return 130
    except ZmpkitError as exc:
        click.echo(f"zmpkit: error: {exc}", err=True)
        return EXIT_USAGE
    return result if isinstance(result, int) else 0


if __name__ == "__main__":
    sys.exit(main())
