#!/usr/bin/env python3
"""Drive-by (indirect) identification of a bridge's first natural frequency from an
instrumented vehicle's axle accelerometers, scored against the run's own truth.

    python3 tools/driveby_check.py run.mcap                      # every instrumented pass
    python3 tools/driveby_check.py run.mcap --tol 0.02 --json f1.json --plot spectra.svg

What it does, as the operator of a test vehicle would with its files (steps 1-4 see only
the measured streams and what an operator knows: the bridge's length and the vehicle's own
parameters; the truth is read after the estimate, to score it):

1. reads the vehicle accelerometers (``/vehicles/<id>/accel/*``; the channel's ``mount``,
   "axle N", says where each sits) and the vehicle's GNSS (``/vehicles/<id>/gnss/*``), the
   span L from the ``bridge_model`` metadata record, and the parameters of the
   instrumented vehicles only (``/truth/vehicles``: a test vehicle's masses, springs and
   dampers are known to its operator, who weighed and tested it; no other vehicle's are
   used). The ``bridgetwin`` package reads what it decodes, ``tools/read_run.py`` the rest;
2. per pass (one instrumented vehicle): the record runs from ``--trim-s`` after the first
   fix to the last; the front axle is on the bridge while the GNSS position is in [0, L]
   (times interpolated between fixes), T = L / v long; the rear axle is at the same place
   tau0 = d / v later (d the wheelbase). Off the bridge (the approach, ``--margin-m``
   before it, 1 s clear of the record's start) the road alone drives both axles: there
   tau is refined by the peak of the cross-correlation of the two contact signals
   (parabola, sub-sample) and their relative gain g (the sensors' gain errors) fitted by
   least squares;
3. four signals, band-passed to [0.5 Hz, 1.5 x the band's top]:
   (a) ``axle``: the axle accelerations, as Yang et al. [1];
   (b) ``contact``: the contact-point acceleration back-calculated from the axle's [2].
       Per axle i (up positive; m_a axle mass, k~_s = k_s + i w c_s suspension, k~_t =
       k_t + i w c_t tyre), m_a y_a'' = -k_t (y_a - u_c) - c_t (y_a' - u_c')
       + k_s (y_b,i - y_a) + c_s (y_b,i' - y_a') gives, in the frequency domain,
           U_c'' = Y_a'' + [-w^2 m_a Y_a'' - k~_s (Y_b,i'' - Y_a'')] / k~_t
       with the body's accelerations above the axles, Y_b,i'' = Z'' + s_i TH'' (s_i the
       axle's offset from the centre of gravity), from the body's bounce and pitch driven
       by the measured axles: [K_b - w^2 diag(m_b, I_b)] (Z'', TH'') = sum_i k~_s,i (1, s_i)
       Y_a,i'' with K_b = sum_i k~_s,i [[1, s_i], [s_i, s_i^2]]. All in accelerations: no
       integration. The vehicle's own frequencies drop out; the road's profile stays;
   (c) ``contact_residual``: front minus g x rear shifted by tau, both contact points at
       the same place x [3, 4]: u_c = r(x) - w(x, t) for both, so the road profile r
       cancels and r_c(t) = w(x, t + tau) - w(x, t) remains, the bridge seen through
       |2 sin(pi f tau)| (blind at f = k v / d); ``axle_residual`` the same on the axles.
   Spectra: Hann window over the part on the bridge (front, and the rear tau later),
   zero-padded to a grid of ``--df-hz``, divided by the same signal's spectrum off the
   bridge (segments as long, averaged, smoothed over max(0.5 Hz, 2/T)): what the bridge
   adds, an SNR, 1 where the record on the bridge looks like the road's. f1 is the highest
   point in ``--band-hz`` (parabola through three bins), outside +/- ``--exclude-rel`` of
   the vehicle's frequencies (its modes on rigid ground, from its parameters) and any
   ``--exclude-hz`` band, per pass and on the mean of the passes' spectra;
4. the bound a record supports, set before the truth is read: 2/T = 2v/L, the half-width
   of the Hann window's main lobe. Within it the spectrum cannot tell the bridge's
   resonance from what shapes it: the moving observer's frequencies f1 +/- v/(2L) [1]
   and, on a rough road, the spectrum of the van's tyre forces (two axles tau apart on
   the same road), which tilt the peak by a few percent with a sign that changes with the
   speed (+2 % at 2 m/s, -1 % at 1 m/s on the 30 m span: docs/figures/driveby/summary.md).
   A peak counts only ``--min-snr-db`` (10 dB) above the floor:
   for the ~B T independent bins of a band B on the bridge, the highest of a spectrum like
   the road's passes 10 dB with probability about B T e^-10, < 1 % for B T < 200;
5. only then reads ``/truth/bridge`` (natural_frequency_hz at t = 0) and scores.

Exit status 0 when the chosen estimator's (``--estimator``, default contact_residual) f1
of all passes stands ``--min-snr-db`` over the floor and is within ``--tol`` (relative;
default the bound of step 4 for the slowest pass) of the truth, and that bound is not
coarser than ``--tol`` (a record too short to resolve f1 to the tolerance cannot pass,
whatever its number); 1 otherwise; 2 on bad input, one line on stderr naming the file (no
such file, empty, not an MCAP file, truncated; no vehicle accelerometer: not the drive_by
example; no accelerometer on a vehicle's axle, no GNSS on it, no pass over the bridge, no
parameters of the instrumented vehicle, no record off the bridge: ``tools/bad_input.py``);
4 when the tool itself failed.

[1] Y.B. Yang, C.W. Lin, J.D. Yau, Extracting bridge frequencies from the dynamic response
    of a passing vehicle, J. Sound Vib. 272 (2004) 471-493.
[2] Y.B. Yang, B. Zhang, Y. Qian, Y. Wu, Contact-point response for modal identification
    of bridges by a moving test vehicle, Int. J. Struct. Stab. Dyn. 18 (2018) 1850073.
[3] Y.B. Yang, Y.C. Li, K.C. Chang, Using two connected vehicles to measure the frequencies
    of bridges with rough surface: a theoretical study, Acta Mech. 223 (2012) 1851-1861.
[4] J. Keenahan, E.J. OBrien, P.J. McGetrick, A. Gonzalez, The use of a dynamic
    truck-trailer drive-by system to monitor bridge damping, Struct. Health Monit. 13
    (2014) 143-157.
"""

from __future__ import annotations

import argparse
import json
import re
import sys
from pathlib import Path

import numpy as np
from scipy import signal

sys.path.insert(0, str(Path(__file__).resolve().parent))
from bad_input import check_mcap, fail, guard, reader_error, require_topics  # noqa: E402

VEH, TRUTH_BRIDGE, TRUTH_VEHICLES = "/vehicles/", "/truth/bridge", "/truth/vehicles"
ESTIMATORS = ("axle", "contact", "axle_residual", "contact_residual")


def read(path: str, wanted: list[str]):
    """({topic: {column: array}}, {topic: channel metadata}, {record: metadata}) for the
    topics matching `wanted` (regexes): the native package where it decodes the topic,
    tools/read_run.py for the rest (an older package skips schemas it does not know)."""
    from mcap.reader import make_reader

    with open(path, "rb") as f:
        reader = make_reader(f)
        summary = reader.get_summary()
        if summary is None:
            raise ValueError(f"{path}: no summary (a damaged or partial file)")
        channels = {c.topic: dict(c.metadata) for c in summary.channels.values()}
        meta = {m.name: dict(m.metadata) for m in reader.iter_metadata()}
    topics = sorted(t for t in channels if any(re.fullmatch(w, t) for w in wanted))
    out: dict = {}
    try:
        import bridgetwin

        run = bridgetwin.read(path, topics=topics) if topics else {}
        out = {t: {c: df[c].to_numpy() for c in df.columns} for t, df in run.items()}
    except ImportError:
        pass
    rest = [t for t in topics if t not in out]
    if rest:
        from read_run import load_topics

        out.update(load_topics(path, rest))
    return out, channels, meta


class Vehicle:
    """One body (bounce, pitch) on its axles: the parameters of /truth/vehicles."""

    def __init__(self, p: dict):
        n = 1
        while f"axle_{n + 1}_mass_kg" in p:
            n += 1
        get = lambda key: np.array([float(p[f"axle_{i + 1}_{key}"]) for i in range(n)])  # noqa: E731
        self.ma, self.ks, self.cs = get("mass_kg"), get("suspension_stiffness_n_m"), get("suspension_damping_n_s_m")
        self.kt, self.ct, self.x = get("tyre_stiffness_n_m"), get("tyre_damping_n_s_m"), get("offset_m")
        self.s = self.x - float(p["cg_behind_front_m"])  # offsets from the centre of gravity
        self.mb, self.ib = float(p["body_mass_kg"]), float(p["pitch_inertia_kg_m2"])

    def frequencies(self) -> np.ndarray:
        """Damped natural frequencies (Hz) of the vehicle on rigid ground."""
        n = len(self.ma)
        m = np.diag(np.r_[self.mb, self.ib, self.ma])
        k, c = np.zeros((n + 2, n + 2)), np.zeros((n + 2, n + 2))
        for i in range(n):
            v = np.zeros(n + 2)
            v[:2], v[2 + i] = (1.0, self.s[i]), -1.0  # suspension stretch
            k += self.ks[i] * np.outer(v, v)
            c += self.cs[i] * np.outer(v, v)
            k[2 + i, 2 + i] += self.kt[i]
            c[2 + i, 2 + i] += self.ct[i]
        mi = np.linalg.inv(m)
        a = np.block([[np.zeros_like(m), np.eye(n + 2)], [-mi @ k, -mi @ c]])
        lam = np.linalg.eigvals(a)
        return np.sort(np.abs(lam[lam.imag > 0].imag) / (2 * np.pi))

    def contact(self, acc: np.ndarray, fs: float) -> np.ndarray:
        """Contact-point accelerations [n, axles] from the axle accelerations (up
        positive), in the frequency domain (module doc, step 3b)."""
        n = len(acc)
        nfft = 1 << int(np.ceil(np.log2(2 * n)))  # zero-padded: no wrap-around
        w = 2 * np.pi * np.fft.rfftfreq(nfft, 1 / fs)[:, None]
        ya = np.fft.rfft(acc * signal.windows.tukey(n, 0.02)[:, None], nfft, axis=0)
        ks, kt = self.ks + 1j * w * self.cs, self.kt + 1j * w * self.ct
        one = np.ones_like(self.s)
        kb = np.stack([[(ks * one).sum(1), (ks * self.s).sum(1)], [(ks * self.s).sum(1), (ks * self.s**2).sum(1)]])
        kb = np.moveaxis(kb, 2, 0) - w[:, :, None] ** 2 * np.diag([self.mb, self.ib])
        rhs = np.stack([(ks * ya).sum(1), (ks * self.s * ya).sum(1)], 1)
        q = np.linalg.solve(kb, rhs[:, :, None])[:, :, 0]
        yb = q[:, :1] + self.s * q[:, 1:]
        uc = ya + (-(w**2) * self.ma * ya - ks * (yb - ya)) / kt
        return np.fft.irfft(uc, nfft, axis=0)[:n]


def shifted(x: np.ndarray, fs: float, dt: float) -> np.ndarray:
    """x(t + dt), a fractional shift through the FFT (zero-padded)."""
    n = len(x)
    nfft = 1 << int(np.ceil(np.log2(2 * n)))
    f = np.fft.rfftfreq(nfft, 1 / fs)
    return np.fft.irfft(np.fft.rfft(x, nfft) * np.exp(2j * np.pi * f * dt), nfft)[:n]


def lag_and_gain(front: np.ndarray, rear: np.ndarray, fs: float, tau0: float, off: np.ndarray):
    """tau (s) maximising the correlation of front(t) and rear(t + tau) over the samples
    `off` (off the bridge), searched within +/- 3 % of tau0, sub-sample by a parabola; the
    least-squares gain g of rear(t + tau) onto front(t) there. Where the two hardly
    correlate (a smooth road: nothing common to align), tau0 and g = 1."""
    n = len(front)
    nfft = 1 << int(np.ceil(np.log2(2 * n)))
    r = np.fft.irfft(np.conj(np.fft.rfft(front * off, nfft)) * np.fft.rfft(rear, nfft), nfft)
    lo, hi = int(np.floor(0.97 * tau0 * fs)), int(np.ceil(1.03 * tau0 * fs)) + 1
    k = lo + int(np.argmax(r[lo:hi]))
    y0, y1, y2 = r[k - 1], r[k], r[k + 1]
    tau = (k + 0.5 * (y0 - y2) / (y0 - 2 * y1 + y2)) / fs
    rs = shifted(rear, fs, tau)
    rho = np.dot(front[off], rs[off]) / np.sqrt(np.dot(front[off], front[off]) * np.dot(rs[off], rs[off]))
    if not rho > 0.5:
        return tau0, 1.0
    return tau, float(np.dot(front[off], rs[off]) / np.dot(rs[off], rs[off]))


def spectrum(seg: np.ndarray, nfft: int) -> np.ndarray:
    """Power spectral density (up to a constant) of the Hann-windowed, zero-padded segment."""
    win = np.hanning(len(seg))
    return np.abs(np.fft.rfft(signal.detrend(seg) * win, nfft)) ** 2 / np.sum(win**2)


def floor(x: np.ndarray, off: np.ndarray, n_on: int, nfft: int, smooth: int) -> np.ndarray:
    """The off-bridge spectrum of `x`: segments of the on-bridge length (half overlap; the
    whole stretch when shorter) of each stretch where `off`, averaged, then a moving
    average over `smooth` bins: the road's leftover, the noise and the vehicle's shape."""
    edges = np.flatnonzero(np.diff(np.r_[0, off.astype(np.int8), 0]))
    got = []
    for lo, hi in zip(edges[::2], edges[1::2]):
        if hi - lo < n_on // 4:
            continue
        starts = range(lo, hi - n_on + 1, max(1, n_on // 2)) if hi - lo >= n_on else [lo]
        got += [spectrum(x[i : min(i + n_on, hi)], nfft) for i in starts]
    if not got:
        raise ValueError("no record off the bridge to compare with (lengthen the approach)")
    return np.convolve(np.mean(got, axis=0), np.ones(smooth) / smooth, mode="same")


def peak(f: np.ndarray, p: np.ndarray, keep: np.ndarray) -> tuple[float, float]:
    """(frequency, height in dB) of the highest point where `keep`,
    refined by a parabola through it and its neighbours (in dB)."""
    if not keep.any():
        return float("nan"), float("nan")
    i = int(np.flatnonzero(keep)[np.argmax(p[keep])])
    fi = f[i]
    if 0 < i < len(p) - 1 and p[i - 1] > 0 and p[i + 1] > 0:
        y0, y1, y2 = 10 * np.log10(p[i - 1 : i + 2])
        den = y0 - 2 * y1 + y2
        if den < 0:
            fi += 0.5 * (y0 - y2) / den * (f[1] - f[0])
    return float(fi), float(10 * np.log10(p[i]))


def load_passes(path: str, trim_s: float):
    """The span and one dict per instrumented vehicle (module doc, steps 1-2)."""
    data, channels, meta = read(path, [r"/vehicles/\d+/accel/.+", r"/vehicles/\d+/gnss/.+", TRUTH_VEHICLES])
    span = float(meta.get("bridge_model", {}).get("span_m", "nan"))
    if not np.isfinite(span):
        raise ValueError(f"{path}: no span in the run's metadata (bridge_model.span_m)")
    axles: dict[int, dict[int, str]] = {}
    for t in data:
        m = re.fullmatch(r"/vehicles/(\d+)/accel/.+", t)
        mount = re.fullmatch(r"axle (\d+)", channels[t].get("mount", ""))
        if m and mount and len(data[t].get("timestamp_ns", [])) > 1:
            axles.setdefault(int(m.group(1)), {})[int(mount.group(1))] = t
    if not axles:
        raise ValueError(f"{path}: no accelerometer on a vehicle's axle ({VEH}<id>/accel/*, mount 'axle N')")
    vt = data.get(TRUTH_VEHICLES, {})
    passes, skipped = [], []
    for vid in sorted(axles):
        gnss = sorted(t for t in channels if t.startswith(f"{VEH}{vid}/gnss/"))
        if not gnss:
            raise ValueError(f"{path}: vehicle {vid} carries accelerometers but no GNSS ({VEH}{vid}/gnss/*)")
        row = np.flatnonzero(np.asarray(vt.get("vehicle_id", []), int) == vid)
        if len(row) == 0:
            raise ValueError(f"{path}: no parameters of the instrumented vehicle {vid} ({TRUTH_VEHICLES})")
        params = {k[len("parameters.") :]: vt[k][row[0]] for k in vt if k.startswith("parameters.")}
        veh = Vehicle(params)
        g = data.get(gnss[0], {})
        gt, gx = np.asarray(g.get("timestamp_ns", []), np.int64), np.asarray(g.get("position_m", []), float)
        if len(gx) < 2 or not (gx.min() < 0 and gx.max() > span):
            skipped.append(vid)
            continue
        topics = [axles[vid][a] for a in sorted(axles[vid])]
        stamps = [np.asarray(data[t]["timestamp_ns"], np.int64) for t in topics]
        period = float(np.median(np.diff(stamps[0])))
        t0 = int(gt[0] + trim_s * 1e9)  # the record: the vehicle on the modelled road
        grid = t0 + period * np.arange(int((gt[-1] - t0) / period))
        acc = np.column_stack(
            [-np.interp(grid, s, np.asarray(data[t]["acceleration_m_s2"], float)) for s, t in zip(stamps, topics)]
        )  # up positive
        order = np.argsort(gt)
        t_in = float(np.interp(0.0, np.maximum.accumulate(gx[order]), gt[order]))
        t_out = float(np.interp(span, np.maximum.accumulate(gx[order]), gt[order]))
        passes.append(
            {
                "vehicle": vid,
                "axles": sorted(axles[vid]),
                "topics": topics,
                "fs": 1e9 / period,
                "t_ns": grid,
                "acc": acc,
                "x_m": np.interp(grid, gt[order], gx[order]),
                "i_on": (int((t_in - t0) / period), int((t_out - t0) / period)),
                "speed": span / ((t_out - t_in) * 1e-9),
                "veh": veh,
                # Samples at the ADC's rail (the channel's full scale): the axle shook harder
                # than the sensor's range, and the record is no longer linear.
                "clipped": int(
                    sum(np.sum(np.abs(acc[:, c]) >= 0.999 * float(channels[t].get("chain.adc_range", "inf"))) for c, t in enumerate(topics))
                ),
            }
        )
    if not passes:
        raise ValueError(f"{path}: no instrumented vehicle crossed the bridge [0, {span:g}] m by its GNSS")
    return span, passes, skipped


def analyse(p: dict, span: float, args) -> tuple[dict, dict, np.ndarray]:
    """The spectra of one pass on the bridge (on the grid k df), and their peaks."""
    fs, acc, veh = p["fs"], p["acc"], p["veh"]
    nfft = int(round(fs / args.df_hz))
    f = np.fft.rfftfreq(nfft, 1 / fs)
    # Above the band the back-calculation amplifies the sensor noise by w^2 m_a / k_t.
    sos = signal.butter(4, [0.5, min(0.4 * fs, 1.5 * args.band_hz[1])], "bandpass", fs=fs, output="sos")
    full = len(p["axles"]) == len(veh.ma) and p["axles"] == list(range(1, len(veh.ma) + 1))
    sig = {"axle": signal.sosfiltfilt(sos, acc - acc.mean(0), axis=0)}
    if full:
        sig["contact"] = signal.sosfiltfilt(sos, veh.contact(acc - acc.mean(0), fs), axis=0)
    a, b = p["i_on"]
    n_tau = 0
    out = {"tau_s": float("nan"), "gain": float("nan")}
    # Off the bridge: on the approach, 1 s clear of the record's start (the taper's and the
    # filters' edges). Not after the bridge: the record ends where the road does.
    d = veh.x[1] - veh.x[0] if len(veh.x) > 1 else 0.0
    off = (p["x_m"] < -args.margin_m) & (np.arange(len(acc)) > fs)
    if len(p["axles"]) >= 2 and p["axles"][:2] == [1, 2]:
        src = sig.get("contact", sig["axle"])
        tau, gain = lag_and_gain(src[:, 0], src[:, 1], fs, d / p["speed"], off)
        out.update(tau_s=tau, gain=gain)
        n_tau = int(round(tau * fs))
        for name in ("axle", "contact"):
            if name in sig:
                x = sig[name]
                sig[name + "_residual"] = (x[:, 0] - gain * shifted(x[:, 1], fs, tau))[:, None]
    band = (f >= args.band_hz[0]) & (f <= args.band_hz[1])
    excl = np.zeros_like(band)
    for fv in veh.frequencies():
        excl |= np.abs(f - fv) <= args.exclude_rel * fv
    for lo, hi in args.exclude_hz:
        excl |= (f >= lo) & (f <= hi)
    # Each spectrum on the bridge over the same signal's off-bridge floor: what the bridge
    # adds (an SNR; 1 where the record on the bridge looks like the road's).
    smooth = max(3, int(round(max(0.5, 2 * fs / (b - a)) / (f[1] - f[0]))))
    spectra, found = {}, {}
    for name, x in sig.items():
        cols = [(0, 0)] + ([(1, n_tau)] if x.shape[1] > 1 and b + n_tau <= len(x) else [])
        s = np.mean([spectrum(x[a + k : b + k, c], nfft) / floor(x[:, c], off, b - a, nfft, smooth) for c, k in cols], axis=0)
        keep = band & ~excl
        spectra[name] = s
        found[name] = peak(f, s, keep)
    out.update(
        vehicle=p["vehicle"],
        speed_m_s=p["speed"],
        t_on_s=(b - a) / fs,
        resolution_hz=fs / (b - a),
        vehicle_hz=[float(v) for v in veh.frequencies()],
        f_hz={k: v[0] for k, v in found.items()},
        snr_db={k: v[1] for k, v in found.items()},
        clipped_samples=p["clipped"],
    )
    return out, spectra, excl


def plot(path: str, f, per_pass, mean, est, truth_f1, band, excl, min_snr_db):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    names = [n for n in ESTIMATORS if n in mean]
    fig, axes = plt.subplots(len(names), 1, figsize=(8, 2.3 * len(names)), sharex=True)
    show = (f >= band[0]) & (f <= band[1])
    for ax, name in zip(np.atleast_1d(axes), names):
        for s in per_pass:
            if name in s:
                ax.semilogy(f[show], s[name][show], color="0.75", lw=0.6)
        ax.semilogy(f[show], mean[name][show], color="C0", lw=1.2, label="mean of passes")
        ax.axvline(truth_f1, color="C3", ls="--", label=f"true f1 {truth_f1:.3f} Hz")
        ax.axvline(est[name], color="C2", lw=0.8, label=f"estimate {est[name]:.3f} Hz")
        ax.fill_between(f[show], 0, 1, where=excl[show], color="0.9", transform=ax.get_xaxis_transform())
        ax.axhline(10 ** (min_snr_db / 10), color="0.4", ls=":", lw=0.8, label=f"detection {min_snr_db:g} dB")
        ax.set_ylabel("on / off bridge")
        ax.set_title(f"{name}: on-bridge spectrum over the off-bridge floor (grey: vehicle frequencies)", fontsize=9, loc="left")
        ax.legend(fontsize=7, loc="upper right")
    np.atleast_1d(axes)[-1].set_xlabel("frequency (Hz)")
    fig.tight_layout()
    fig.savefig(path)


def options(argv: list[str] | None = None) -> argparse.Namespace:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("run", help="bridgetwin MCAP file")
    p.add_argument("--estimator", choices=ESTIMATORS, default="contact_residual", help="the one scored (contact_residual)")
    p.add_argument("--tol", type=float, default=None, help="relative tolerance (default: 2/T = 2v/L over f1, step 4)")
    p.add_argument("--band-hz", type=float, nargs=2, default=[1.0, 10.0], help="where f1 is sought (1 10)")
    p.add_argument("--exclude-hz", type=float, nargs=2, action="append", default=[], help="a band left out (axle)")
    p.add_argument("--exclude-rel", type=float, default=0.15, help="+/- around each vehicle frequency left out (0.15)")
    p.add_argument("--margin-m", type=float, default=2.0, help="off the bridge: this far from it (2 m)")
    p.add_argument("--trim-s", type=float, default=2.0, help="ignore the first seconds on the road (2 s)")
    p.add_argument("--df-hz", type=float, default=0.002, help="spectral grid (0.002 Hz)")
    p.add_argument("--min-snr-db", type=float, default=10.0, help="a bridge peak stands this far above the off-bridge floor (10 dB)")
    p.add_argument("--json", help="write the result here")
    p.add_argument("--plot", help="write the spectra here (SVG)")
    return p.parse_args([] if argv is None else argv)


def estimate(path: str, args: argparse.Namespace) -> dict:
    """Steps 1-4 (blind): per pass and all passes, each estimator's f1."""
    span, passes, skipped = load_passes(path, args.trim_s)
    rows, per_pass, excls = [], [], []
    for ps in passes:
        row, spectra, ex = analyse(ps, span, args)
        rows.append(row)
        per_pass.append(spectra)
        excls.append(ex)
    n = min(len(e) for e in excls)  # passes at other rates share the grid k df up to the lowest Nyquist
    f = np.arange(n) * args.df_hz
    excl = np.any([e[:n] for e in excls], axis=0)
    per_pass = [{k: v[:n] for k, v in s.items()} for s in per_pass]
    band = (f >= args.band_hz[0]) & (f <= args.band_hz[1])
    mean, est, snr = {}, {}, {}
    for name in ESTIMATORS:
        got = [s[name] for s in per_pass if name in s]
        if got:
            mean[name] = np.mean(got, axis=0)
            est[name], snr[name] = peak(f, mean[name], band & ~excl)
    return {"span_m": span, "passes": rows, "skipped": skipped, "f": f, "per_pass": per_pass, "mean": mean, "f1_hz": est, "snr_db": snr, "excl": excl}


def truth_f1(path: str) -> float:
    """The true f1 (Hz): /truth/bridge natural_frequency_hz at t = 0."""
    values = read(path, [TRUTH_BRIDGE])[0][TRUTH_BRIDGE]["natural_frequency_hz"]
    return float(np.asarray(values[0], float).ravel()[0])


def main(argv: list[str]) -> int:
    args = options(argv)
    check_mcap(args.run)
    require_topics(
        args.run,
        (VEH,),
        "vehicle accelerometer",
        "drive_by",
        keep=lambda t: re.fullmatch(r"/vehicles/\d+/accel/.+", t),
        shown=f"{VEH}<id>/accel/*",
    )
    try:
        res = estimate(args.run, args)
    except ValueError as e:  # what the steps find wrong: the message names the file
        return fail("driveby_check", e)
    except Exception as e:  # noqa: BLE001 - a file the readers cannot read is bad input
        return fail("driveby_check", reader_error(args.run, e))
    est, rows, name = res["f1_hz"], res["passes"], args.estimator
    if name not in est:
        return fail("driveby_check", f"{args.run}: {name} needs accelerometers on axles 1 and 2")
    # Decided before the truth: the bound the records support (step 4, the slowest pass)
    # and whether a peak stands out of the off-bridge floor at all.
    bound_hz = 2 * max(r["resolution_hz"] for r in rows)
    detected = res["snr_db"][name] >= args.min_snr_db
    # Blind up to here: the truth is read only to score.
    try:
        f1 = truth_f1(args.run)
    except (KeyError, IndexError, ValueError) as e:
        return fail("driveby_check", f"{args.run}: no truth f1 ({TRUTH_BRIDGE}): {e}")
    bound = bound_hz / f1
    tol = args.tol if args.tol is not None else bound
    names = [n for n in ESTIMATORS if n in est]
    print(f"{args.run}: span {res['span_m']:g} m, {len(rows)} passes, {len(res['skipped'])} instrumented vehicles never on it")
    print(f"vehicle frequencies (rigid ground): {', '.join(f'{v:.2f}' for v in rows[0]['vehicle_hz'])} Hz")
    print("pass  v (m/s)  T on (s)  1/T (Hz)  tau (ms)   gain" + "".join(f"  {n:>17}" for n in names) + "  SNR (dB)")
    for r in rows:
        r["error"] = {n: (v - f1) / f1 for n, v in r["f_hz"].items()}
        cells = "".join(f"  {r['f_hz'][n]:>7.3f} {100 * r['error'][n]:>+7.2f}%" if n in r["f_hz"] else " " * 19 for n in names)
        print(
            f"{r['vehicle']:>4}  {r['speed_m_s']:>7.2f}  {r['t_on_s']:>8.2f}  {r['resolution_hz']:>8.4f}  "
            f"{1e3 * r['tau_s']:>8.2f}  {r['gain']:>5.3f}{cells}  {r['snr_db'].get(name, float('nan')):>8.1f}"
        )
        if r["clipped_samples"]:
            print(f"      vehicle {r['vehicle']}: {r['clipped_samples']} samples at the sensor's full scale (clipped)")
    cells = "".join(f"  {est[n]:>7.3f} {100 * (est[n] - f1) / f1:>+7.2f}%" for n in names)
    print(f" all  {'':>7}  {'':>8}  {'':>8}  {'':>8}  {'':>5}{cells}  {res['snr_db'][name]:>8.1f}")
    err = (est[name] - f1) / f1
    print(
        f"true f1 {f1:.4f} Hz; {name} (all passes) {est[name]:.4f} Hz, error {100 * err:+.2f} %, "
        f"{res['snr_db'][name]:.1f} dB over the off-bridge floor; bound 2/T = {100 * bound:.2f} % of f1; tolerance {100 * tol:.2f} %"
    )
    why = []
    if not detected:
        why.append(f"no peak {args.min_snr_db:g} dB above the off-bridge floor (the records on the bridge look like the road's)")
    if bound > tol * (1 + 1e-9):
        why.append("the records on the bridge are too short to resolve f1 to the tolerance")
    if not abs(err) <= tol:
        why.append("the estimate is off")
    ok = not why
    print(f"{'PASS' if ok else 'FAIL'}: drive-by f1 within {100 * tol:.2f} % of the truth" + ("" if ok else ": " + "; ".join(why)))
    if args.json:
        out = {k: res[k] for k in ("span_m", "f1_hz", "snr_db", "passes", "skipped")}
        out.update(true_f1_hz=f1, estimator=name, tolerance=tol, resolution_rel=bound, failures=why)
        out["error"] = {n: (v - f1) / f1 for n, v in est.items()}
        out["pass"] = ok
        Path(args.json).write_text(json.dumps(out, indent=2))
    if args.plot:
        plot(args.plot, res["f"], res["per_pass"], res["mean"], est, f1, args.band_hz, res["excl"], args.min_snr_db)
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(guard("driveby_check", main, sys.argv[1:]))
