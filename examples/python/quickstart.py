"""Simulate 2 min of ambient monitoring, read it, plot the overview, identify f1 with pyOMA2
and score it against the truth: python examples/python/quickstart.py [overview.png]"""
import sys
from pathlib import Path

import numpy as np
import bridgetwin
from pyoma2.algorithms import FDD
from pyoma2.setup import SingleSetup

scenario = Path(__file__).resolve().parents[1] / "ambient_monitoring.toml"
bridgetwin.simulate(scenario, out="ambient.mcap", duration_s=120.0, force=True)  # the CLI's bytes
run = bridgetwin.read("ambient.mcap")  # topic -> pandas DataFrame, decoded in Rust
bridgetwin.plot.overview(run, out=sys.argv[1] if len(sys.argv) > 1 else "overview.png")

accel = run.sensors("accel")  # /sensors/accel/<id>, vertical accelerations (m/s²)
rate_hz = float(run[accel[0]].attrs["sample_rate_hz"])
rows = min(len(run[t]) for t in accel)
data = np.column_stack([run[t]["acceleration_m_s2"].to_numpy()[:rows] for t in accel])
setup = SingleSetup(data - data.mean(axis=0), fs=rate_hz)
setup.add_algorithms(FDD(name="FDD", nxseg=1024, method_SD="per"))
setup.run_all()
freq_hz, s1 = np.asarray(setup["FDD"].result.freq), np.asarray(setup["FDD"].result.S_val[0, 0])
band = (freq_hz > 1.0) & (freq_hz < 0.4 * rate_hz)
f1_found = freq_hz[band][np.argmax(s1[band])]
f1_true = run.natural_frequencies_hz[0]
print(f"f1: identified {f1_found:.3f} Hz, true {f1_true:.3f} Hz ({100 * (f1_found / f1_true - 1):+.2f} %)")
sys.exit(0 if abs(f1_found / f1_true - 1) < 0.02 else 1)
