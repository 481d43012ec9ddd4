"""Bridge weigh-in-motion (B-WIM) of a bridgetwin run: the pipeline behind tools/bwim_check.py.

The method, its options and its references are in the docstring of ``tools/bwim_check.py``
(the command line); one job per module:

- ``io``: the run's strain records on one grid, its axle-detector hits, the truth vehicles.
- ``vehicles``: a detected vehicle (axle times, speed) and where its axles are.
- ``axles``: axles and speed from the free-of-axle-detector (FAD) strain gauges.
- ``tapes``: axles and speed from road axle detectors (tape switches), pairs a known
  distance apart.
- ``calibration``: influence lines by the matrix method on the calibration truck's runs.
- ``weighing``: axle loads by Moses' least squares, overlapping vehicles jointly.
- ``cost323``: the COST 323 tolerances, acceptance levels and the class reached.
- ``scoring``: detections matched to the truth, relative errors per criterion.
- ``report``: the printed report, the JSON and the figure.
- ``pipeline``: the whole run, from the file to the exit status.
"""

import os

# Small matrices only: one BLAS thread is faster than two fighting over a shared machine.
for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")
