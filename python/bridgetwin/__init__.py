"""bridgetwin from Python: read runs into pandas, simulate scenarios, plot an overview.

    import bridgetwin
    run = bridgetwin.simulate(duration_s=5.0)          # the default scenario, in memory
    run["/sensors/accel/A4"]                            # a pandas DataFrame
    bridgetwin.read("day-*.mcap", topics="/sensors/*")  # hourly parts as one run
    bridgetwin.plot.overview(run)

Units are in the column names (``acceleration_m_s2``, ``strain_microstrain``,
``displacement_m``, ``force_n``); times are ``log_time_ns`` (true, Unix-epoch ns),
``time_s`` (since the run's start) and ``timestamp_ns`` (the DAQ node's stamp).
"""

from ._native import ReadError, ScenarioError, SimulationError, __version__
from ._read import DamagedFileWarning, InterruptedRunWarning, Run, read, run_files
from ._simulate import check, default_scenario, simulate
from . import plot

__all__ = [
    "DamagedFileWarning",
    "InterruptedRunWarning",
    "ReadError",
    "Run",
    "ScenarioError",
    "SimulationError",
    "__version__",
    "check",
    "default_scenario",
    "plot",
    "read",
    "run_files",
    "simulate",
]
