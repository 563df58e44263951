"""``python -m corotate`` is the ``corotate`` command."""

from __future__ import annotations

import sys

from .cli import main

sys.exit(main())
