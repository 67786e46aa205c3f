"""``zmpkit demo``: the main job on the built-in virtual robots."""

from __future__ import annotations

from pathlib import Path

import click

from zmpkit.cli.options import report_option
from zmpkit.cli.progress import RichDisplays
from zmpkit.cli.video_option import video_option
from zmpkit.pipelines.demo import DemoConfig, run_demo
from zmpkit.pipelines.demo_files import write_demo

__all__ = ["demo_command"]


@click.command("demo")
@click.option(
    "--out", "out_dir", type=click.Path(path_type=Path), default=Path("out/demo"), show_default=True
)
@report_option
@video_option(True, "the rigid and the all-effects walk side by side and a balance step trial")
def demo_command(out_dir: Path, report_format: str, video: bool) -> None:
    """Run the main job on the built-in virtual robot and write a report to --out."""
    config = DemoConfig(report_format=report_format, video=video)
    result = run_demo(config, out_dir, echo=click.echo, displays=RichDisplays())
    result = write_demo(result, out_dir, echo=click.echo)
    for path in result.videos:
        click.echo(f"video: {path}")
    click.echo(f"report: {result.report_path}")
