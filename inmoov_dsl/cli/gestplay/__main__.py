"""``python -m inmoov_dsl.cli.gestplay``."""

import sys

from . import main

sys.exit(main())
