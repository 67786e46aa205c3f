"""zmpkit.analysis: metrics of responses (plotting modules live beside, imported on demand)."""

from zmpkit.analysis.step_metrics import StepMetrics, step_metrics

__all__ = ["StepMetrics", "step_metrics"]
