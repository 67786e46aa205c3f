"""zmpkit: measure, model and compensate the gap between the LIPM and the robot that moves."""

from importlib.metadata import PackageNotFoundError, version

from zmpkit.errors import (
    InputFileError,
    InputFileProblemsError,
    ModelError,
    ParameterError,
    SimulationDivergedError,
    ZmpkitError,
)

try:
    __version__ = version("zmpkit")
except PackageNotFoundError:  # running from a source tree that was never installed
    __version__ = "0.0.0+unknown"

__all__ = [
    "InputFileError",
    "InputFileProblemsError",
    "ModelError",
    "ParameterError",
    "SimulationDivergedError",
    "ZmpkitError",
    "__version__",
]
