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
    """Write the constraints to stdout; fail on a dependency without a ``>=`` bound."""
    pyproject = Path(__file__).resolve().parents[1] / "pyproject.toml"
    dependencies = tomllib.loads(pyproject.read_text())["project"]["dependencies"]
    for requirement in dependencies:
        match = _LOWER.match(requirement)
        if match is None:
            print(f"no lower bound in {requirement!r}", file=sys.stderr)
            return 1
        print(f"{match.group(1)}=={match.group(2)}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
