"""``python -m inmoov_dsl.cli.gestc``."""

import sys

from . import main

sys.exit(main())
