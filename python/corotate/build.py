"""What this build of the C++ core has: its optional backends and the instruction set its hot
loops run at on this CPU (shown by ``corotate --version``)."""

from __future__ import annotations

from typing import Any

import corotate._core as _core


def build_info() -> dict[str, Any]:
    """The build's backends, as a dict:

    version          the package version
    cholmod          True when direct solves of large systems use SuiteSparse CHOLMOD (else
                     the library's own supernodal Cholesky: about 1.3x CHOLMOD's time with
                     OpenBLAS, 5x faster than CHOLMOD with Debian's reference BLAS)
    openmp           True when the core can run its loops on several threads (set_threads)
    cpu_clones       True when the hot loops are compiled for several instruction sets
    instruction_set  the one they run at on this CPU: "x86-64-v4 (AVX-512)",
                     "x86-64-v3 (AVX2, FMA)" or "baseline"
    """
    return {"version": str(_core.__version__), **dict(_core.build_info())}


def describe_build() -> str:
    """build_info() in one line, e.g. "corotate 0.1.0: CHOLMOD yes, OpenMP yes, x86-64-v4 (AVX-512)"."""
    info = build_info()
    yes = {True: "yes", False: "no (own supernodal Cholesky)"}
    return (
        f"corotate {info['version']}: CHOLMOD {yes[info['cholmod']]}, OpenMP {'yes' if info['openmp'] else 'no'}, "
        f"hot loops at {info['instruction_set']}"
    )
