"""``python -m climb_ompl`` runs the ``climb-ompl`` command."""

import sys

from climb_ompl.cli import main

sys.exit(main())
