"""``python -m zmpkit.cli``."""

import sys

from zmpkit.cli import main

sys.exit(main())
