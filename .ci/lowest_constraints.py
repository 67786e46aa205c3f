"""Print ``name==lowest`` for every direct dependency of pyproject.toml (pip constraints).

The CI check ``make test-lowest`` installs zmpkit against these, so a lower bound that is
not true (an API used that the lowest allowed version lacks) fails a test instead of a user.
"""

from __future__ import annotations

import re
import sys
import tomllib
from pathlib import Path

_LOWER = re.compile(r"^\s*([A-Za-z0-9_.\-]+)\s*(?:\[[^\]]*\])?\s*>=\s*([0-9][^,;\s]*)")


def main() -> int:
    """Write the constraints to stdout; fail on a dependency without a ``>=`` bound.

    ``--build``: the build system's requirements instead (``[build-system] requires``), the
    ones with a ``>=`` bound at it, the others as they are.
    """
    pyproject = tomllib.loads((Path(__file__).resolve().parents[1] / "pyproject.toml").read_text())
    if sys.argv[1:] == ["--build"]:
        for requirement in pyproject["build-system"]["requires"]:
            match = _LOWER.match(requirement)
            print(requirement if match is None else f"{match.group(1)}=={match.group(2)}")
        return 0
    dependencies = pyproject["project"]["dependencies"]
    for requirement in dependencies:
        match = _LOWER.match(requirement)
        if match is None:
            print(f"no lower bound in {requirement!r}", file=sys.stderr)
            return 1
        print(f"{match.group(1)}=={match.group(2)}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
