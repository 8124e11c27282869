"""``python -m cga``: the same command line as the ``cga`` script."""

from .cli import main

raise SystemExit(main())
