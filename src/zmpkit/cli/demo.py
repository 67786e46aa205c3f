"""``zmpkit demo``: the main job on the built-in virtual robots."""

from __future__ import annotations

from pathlib import Path

import click

from zmpkit.cli.options import report_option
from zmpkit.cli.progress import RichDisplays
from zmpkit.pipelines.demo import DemoConfig, run_demo

__all__ = ["demo_command"]


@click.command("demo")
@click.option(
    "--out", "out_dir", type=click.Path(path_type=Path), default=Path("out/demo"), show_default=True
)
@report_option
def demo_command(out_dir: Path, report_format: str) -> None:
    """Run the main job on the built-in virtual robot and write a report to --out."""
    config = DemoConfig(report_format=report_format)
    result = run_demo(out_dir, config, echo=click.echo, displays=RichDisplays())
    click.echo(f"report: {result.report_path}")
