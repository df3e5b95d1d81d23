"""Python's automatic cyclic garbage collection paused for a piece of work (standard library only).

A run's heap holds millions of long-lived objects (numba's typing registries, scipy, matplotlib,
trimesh) that every full collection walks again, while the work makes few cycles: the default run
spent about 2 s of its 12 s of CPU in the collector, which found only a few thousand cycles (closed
figures, a few MB); the isolator's design search makes thousands of small objects that live on.
Reference counting still frees everything that is not in a cycle at once.

>>> import gc
>>> with collector_paused():
...     gc.isenabled()
False
>>> gc.isenabled()
True
"""
from __future__ import annotations

import gc


class collector_paused:
    """Context manager: the automatic collection off inside, back as it was afterwards (left off when it
    was off), whether the work ends or raises."""

    def __enter__(self):
        self.was = gc.isenabled()
        gc.disable()
        return self

    def __exit__(self, *exc):
        if self.was:
            gc.enable()
        return False
