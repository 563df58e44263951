"""Attributes that take effect or refuse: assigning to a read-only or unknown public
attribute of a Body or a simulation raises AttributeError instead of being ignored."""

from __future__ import annotations

from typing import Any, ClassVar


class SettableOnly:
    """Public attributes may be assigned only through a property with a setter; others raise
    AttributeError naming the attribute and, where ``_READ_ONLY_HINTS`` has one, what to do
    instead. Private names (leading underscore) are free."""

    _READ_ONLY_HINTS: ClassVar[dict[str, str]] = {}

    def __setattr__(self, name: str, value: Any) -> None:
        if not name.startswith("_"):
            attr = getattr(type(self), name, None)
            if not (isinstance(attr, property) and attr.fset is not None):
                cls = type(self).__name__
                if attr is None:
                    raise AttributeError(f"{cls} has no attribute {name!r} to set (a typo?)")
                hint = self._READ_ONLY_HINTS.get(name, "")
                raise AttributeError(f"{cls}.{name} is read-only" + (f": {hint}" if hint else ""))
        object.__setattr__(self, name, value)
