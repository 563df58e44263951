"""The machine a benchmark ran on, for its first line: the CPU model and the instruction set
the core's hot loops run at on it (figures from different machines differ by 3x)."""

from __future__ import annotations

import platform
from pathlib import Path

import corotate as cr


def cpu_name() -> str:
    """The CPU's model name (/proc/cpuinfo), or the architecture where that is not readable."""
    cpuinfo = Path("/proc/cpuinfo")
    if cpuinfo.exists():
        for line in cpuinfo.read_text().splitlines():
            if line.startswith("model name"):
                return line.split(":", 1)[1].strip()
    return platform.machine()


def describe_machine() -> str:
    """E.g. "AMD EPYC; the core runs its x86-64-v3 (AVX2, FMA) code path"."""
    return f"{cpu_name()}; the core runs its {cr.build_info()['instruction_set']} code path"
