"""The one clock every tool reads, and the one sleep: edges take them as parameters
(``now``, ``sleep``) so tests drive time, and default to these.

``perf_counter`` is monotonic and fine-grained on every system (on Windows
``monotonic`` ticks every 15.6 ms, too coarse for a byte every millisecond).
"""

from __future__ import annotations

import time
from collections.abc import Callable

Clock = Callable[[], float]  #: seconds, monotonic, arbitrary origin
Sleep = Callable[[float], None]  #: sleeps about that many seconds

now: Clock = time.perf_counter
sleep: Sleep = time.sleep
