"""``python -m corotate`` is the ``corotate`` command."""
import sys

from .cli import main

sys.exit(main())
