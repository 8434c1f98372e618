"""``python -m climb_ompl`` runs the ``climb-ompl`` command."""

import sys

from .cli import main

sys.exit(main())
