"""Bodies of several materials: which material each cell has.

A body's materials are one ``Material`` (every cell), a list (region ids 0, 1, ...) or a dict
{region id: Material}; the region of each cell comes from ``regions=`` or the mesh's
``cell_regions`` (what ``read_mesh`` reads from a file's ``gmsh:physical`` cell data)."""

from __future__ import annotations

import operator
from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING, Union

import numpy as np

from .material import Material

if TYPE_CHECKING:
    from numpy.typing import ArrayLike

#: What a Body takes as its material(s).
Materials = Union[Material, Sequence[Material], Mapping[int, Material]]


def materials_by_region(materials: Materials) -> dict[int, Material]:
    """{region id: Material} from one material (region 0), a list (ids 0, 1, ...) or a dict."""
    if isinstance(materials, Material):
        return {0: materials}
    if isinstance(materials, Mapping):
        items = list(materials.items())
    elif isinstance(materials, (list, tuple)):
        items = list(enumerate(materials))
    else:
        raise TypeError("material must be a corotate.Material, or a list or dict of them (one per region)")
    if not items:
        raise ValueError("no material given: a list or dict of materials needs at least one")
    out: dict[int, Material] = {}
    for region, m in items:
        if not isinstance(m, Material):
            raise TypeError(f"the material of region {region!r} must be a corotate.Material, got {type(m).__name__}")
        if isinstance(region, bool):
            raise TypeError(f"region ids must be integers, got {region!r}")
        try:
            out[operator.index(region)] = m
        except TypeError:
            raise TypeError(f"region ids must be integers, got {region!r}") from None
    return out


def check_cell_regions(regions: ArrayLike, n_cells: int) -> np.ndarray:
    """(m,) int64 copy of per-cell region ids; ValueError for another shape or non-integers."""
    r = np.asarray(regions)
    if r.shape != (n_cells,):
        raise ValueError(f"regions must have shape ({n_cells},): one region id per cell, got {r.shape}")
    if r.dtype == bool or not (np.issubdtype(r.dtype, np.integer) or r.size == 0):
        raise ValueError(f"region ids must be integers, got dtype {r.dtype}")
    return np.array(r, dtype=np.int64)


def dense_regions(
    by_region: dict[int, Material], regions: np.ndarray | None
) -> tuple[list[Material], np.ndarray | None]:
    """(materials in region-id order, each cell's index into them), or (the one material, None)
    when every cell has the same material; ValueError naming a cell whose region has none."""
    if regions is None:
        if len(by_region) > 1:
            raise ValueError(
                f"{len(by_region)} materials need the region of each cell: pass regions=... "
                "((m,) int array) or use a mesh with cell_regions"
            )
        return list(by_region.values()), None
    ids = np.array(sorted(by_region), dtype=np.int64)
    index = np.searchsorted(ids, regions)
    missing = (index >= len(ids)) | (ids[np.minimum(index, len(ids) - 1)] != regions)
    if missing.any():
        cell = int(np.flatnonzero(missing)[0])
        given = ", ".join(str(i) for i in ids)
        raise ValueError(
            f"cell {cell} has region {int(regions[cell])}, which has no material "
            f"(materials are given for region(s) {given}; {int(missing.sum())} cell(s) lack one)"
        )
    return [by_region[int(i)] for i in ids], index.astype(np.int64)
