"""OpenMP threads that wait at a barrier sleep instead of spinning, unless the user chose
otherwise (OMP_WAIT_POLICY set): imported before the core, since libgomp reads the variable
once, when it is loaded (with the core). It has no effect where another library loaded
OpenMP first.

Why: a simulator shares its cores (a renderer, a haptic loop, other jobs), and spinning
threads take the cores the others need. On a 2-core machine kept busy by two other processes
(bench/contention.py), two threads took 38x and 1.6x one thread's time at 15,360 and 122,880
tets with libgomp's default policy, 0.84x and 0.87x with this one; on the idle machine 0.73x
and 0.62x (0.85x and 0.62x spinning). The variable is set in this process's environment, so
programs it starts inherit it.
"""

from __future__ import annotations

import os

os.environ.setdefault("OMP_WAIT_POLICY", "PASSIVE")
