"""``python -m inmoov_dsl.cli.gestc``."""

import gc
import sys

gc.disable()  # as the console script starts (inmoov_dsl.cli._start)
from . import main  # noqa: E402

sys.exit(main())
