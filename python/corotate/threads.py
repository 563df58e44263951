"""The thread count of the C++ core's parallel loops (process-wide, 1 by default).

The element sweep of a step (rotations, forces, stiffness assembly), the matrix-vector
products and the block-Jacobi smoother of PCG run on this many threads when the core was
built with OpenMP (``have_openmp()``). Results do not depend on it: a run on two threads
repeats a one-thread run to the last bit (docs/benchmarks.md has the speed-ups).

The default is 1 because a simulator shares its cores (a renderer, a haptic loop, other
jobs) and one thread cannot lose to itself there. Waiting threads sleep at barriers instead
of spinning (corotate sets OMP_WAIT_POLICY=PASSIVE at import unless it is set, see
_wait_policy.py): on a busy 2-core machine two threads then took 0.84-0.98x one thread's
time (bench/contention.py). ``set_threads(n)`` changes the count; so does the environment
variable COROTATE_THREADS=n, read when corotate is imported (a value that is not an integer
>= 1 is ignored with a warning that names it).
"""

from __future__ import annotations

import numbers
import os
import warnings

import corotate._core as _core

#: The environment variable that sets the thread count at import.
THREADS_VARIABLE = "COROTATE_THREADS"


def set_threads(n: int) -> None:
    """Run the core's parallel loops on ``n`` threads (an integer >= 1; more than
    ``available_threads()`` is allowed but oversubscribes). Takes effect at the next step.

    Raises ``TypeError`` for a non-integer and ``ValueError`` for n < 1, or n > 1 in a build
    without OpenMP."""
    if isinstance(n, bool) or not isinstance(n, numbers.Integral):
        raise TypeError(f"the thread count must be an integer, got {n!r}")
    _core.set_threads(int(n))


def threads() -> int:
    """The thread count set by ``set_threads`` (1 by default)."""
    return int(_core.threads())


def available_threads() -> int:
    """Threads the hardware offers (1 in a build without OpenMP)."""
    return int(_core.available_threads())


def have_openmp() -> bool:
    """Whether the core was built with OpenMP; without it everything runs on one thread."""
    return bool(_core.have_openmp())


def _threads_from_environment() -> None:
    """set_threads(COROTATE_THREADS) when the variable is set; a bad value warns (naming the
    variable and why) and leaves the count as it was: an import must not fail over it."""
    value = os.environ.get(THREADS_VARIABLE, "").strip()
    if not value:
        return
    try:
        n = int(value)
    except ValueError:
        reason = "not an integer"
    else:
        try:
            set_threads(n)
            return
        except ValueError as e:
            reason = str(e)
    warnings.warn(
        f"{THREADS_VARIABLE}={value!r} ignored ({reason}); the core runs on {threads()} thread(s)",
        RuntimeWarning,
        stacklevel=2,
    )


_threads_from_environment()
