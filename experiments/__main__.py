"""``python -m experiments``: see :mod:`experiments`."""

from experiments import main

raise SystemExit(main())
