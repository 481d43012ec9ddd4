#!/usr/bin/env python3
"""Plot a bridgetwin run: the Python package's overview (``bridgetwin.plot.overview``).

    python3 tools/plot_run.py run.mcap --out run.png        # or 'day-*.mcap', day.mcap
    python3 -m bridgetwin run.mcap --out run.png       # the same

Needs the package: ``pip install ./python`` (see docs/python.md). The overview draws a few
representative accelerometers, strain and deflection with each vehicle's time on the
bridge shaded, a PSD with the true f1 marked and per-vehicle peaks, decimated so that an
hour draws in seconds.

Exit status (the package's ``bridgetwin.plot.main``): 0 when drawn; 3 when a file is
damaged or cut short and its intact part was drawn; 2, one line on stderr naming the file,
when there is nothing to draw (no such file, empty, not an MCAP file, nothing intact, no
sensor topic) or the package is not installed.
"""

import sys

try:
    from bridgetwin.plot import main
except ImportError as e:
    print(f"tools/plot_run.py needs the bridgetwin package ({e}): pip install ./python", file=sys.stderr)
    sys.exit(2)

if __name__ == "__main__":
    sys.exit(main())
