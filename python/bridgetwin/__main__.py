"""``python -m bridgetwin RUN [--out overview.png] [--sensors T ...]``: the overview of a
run (a file, a glob of hourly parts or a split run's name); see bridgetwin.plot.main."""

from .plot import main

raise SystemExit(main())
