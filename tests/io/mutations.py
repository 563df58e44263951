"""Random mutations of mesh files for the fuzz tests: each takes {suffix: bytes} and a
seeded random.Random and returns the files with one of them changed."""

from __future__ import annotations

import random


def pick_file(files: dict[str, bytes], rng: random.Random) -> str:
    return rng.choice(sorted(files))


def byte_flip(files: dict[str, bytes], rng: random.Random) -> dict[str, bytes]:
    k = pick_file(files, rng)
    b = bytearray(files[k])
    for _ in range(rng.choice([1, 1, 2, 5])):
        i = rng.randrange(len(b))
        b[i] = rng.randrange(256) if rng.random() < 0.5 else b[i] ^ (1 << rng.randrange(8))
    return {**files, k: bytes(b)}


def truncate(files: dict[str, bytes], rng: random.Random) -> dict[str, bytes]:
    k = pick_file(files, rng)
    return {**files, k: files[k][: rng.randrange(len(files[k]))]}


def delete_line(files: dict[str, bytes], rng: random.Random) -> dict[str, bytes]:
    k = pick_file(files, rng)
    lines = files[k].split(b"\n")
    del lines[rng.randrange(len(lines))]
    return {**files, k: b"\n".join(lines)}


def repeat_line(files: dict[str, bytes], rng: random.Random) -> dict[str, bytes]:
    k = pick_file(files, rng)
    lines = files[k].split(b"\n")
    i = rng.randrange(len(lines))
    lines.insert(i, lines[i])
    return {**files, k: b"\n".join(lines)}
