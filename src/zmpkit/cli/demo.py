"""``zmpkit demo``: the main job on the built-in virtual robots."""

from __future__ import annotations

from pathlib import Path

import click

from zmpkit.cli.progress import RichDisplays
from zmpkit.pipelines.demo import run_demo

__all__ = ["demo_command"]


@click.command("demo")
@click.option(
    "--out", "out_dir", type=click.Path(path_type=Path), default=Path("out/demo"), show_default=True
)
def demo_command(out_dir: Path) -> None:
    """Run the main job on the built-in virtual robot and write a report to --out."""
    result = run_demo(out_dir, echo=click.echo, displays=RichDisplays())
    click.echo(f"report: {result.report_path}")
