"""Axles and speed from the free-of-axle-detector (FAD) strain gauges near the supports
(tools/bwim_check.py docstring, step 1): steps at the entry support confirmed one delay
later at the exit support, the bridge's second mode cancelled first."""

from __future__ import annotations

import math

import numpy as np
from scipy.ndimage import median_filter
from scipy.signal import butter, find_peaks, sosfiltfilt, welch

from .io import Record, weighing_sections
from .vehicles import Geometry, Vehicle


def step_filter(x: np.ndarray, w: int) -> np.ndarray:
    """mean(x[i : i + w]) - mean(x[i - w : i]) at every i (cumulative sums, O(n))."""
    c = np.concatenate([[0.0], np.cumsum(x)])
    n = len(x)
    i = np.arange(n)
    lo, hi = np.clip(i - w, 0, n), np.clip(i + w, 0, n)
    return (c[hi] - c[i]) / np.maximum(hi - i, 1) - (c[i] - c[lo]) / np.maximum(i - lo, 1)


def fill_nan(x: np.ndarray) -> np.ndarray:
    bad = np.isnan(x)
    if not bad.any():
        return x
    i = np.arange(len(x))
    return np.interp(i, i[~bad], x[~bad])


def first_frequency(rec: Record, fad_max_m: float) -> float | None:
    """The bridge's first natural frequency, picked blind: the lowest peak above 1 Hz of
    the weighing gauges' summed Welch spectrum that stands 6 dB above its surroundings."""
    inner = np.where((rec.positions_m > fad_max_m) & (rec.positions_m < rec.span_m - fad_max_m))[0]
    if len(inner) == 0:
        return None
    n = min(8192, rec.values.shape[0])
    psd = None
    for c in inner:
        f, p = welch(fill_nan(rec.values[:, c]), fs=rec.fs_hz, nperseg=n)
        psd = p if psd is None else psd + p
    m = (f >= 1.0) & (f <= 0.4 * rec.fs_hz)
    k, _ = find_peaks(10 * np.log10(psd[m] + 1e-30), prominence=6.0)
    return float(f[m][k[0]]) if len(k) else None


def antisymmetric_reference(rec: Record, fad_max_m: float, f1: float | None):
    """The second mode's vibration, from two weighing sections placed symmetrically (x and
    L - x): their difference cancels the symmetric modes, band-passed around 4 f1 (a
    simply supported girder's f2) from 2.8 f1 to 5.6 f1. None without such a pair."""
    if f1 is None:
        return None
    sections = weighing_sections(rec, fad_max_m)
    L = rec.span_m
    for x, y in sections:
        for x2, y2 in sections:
            if x < L / 2 - 0.5 and abs(x + x2 - L) < 0.05:
                hi = min(5.6 * f1, 0.4 * rec.fs_hz)
                if 2.8 * f1 >= hi:
                    return None
                sos = butter(4, [2.8 * f1, hi], "bandpass", fs=rec.fs_hz, output="sos")
                return sosfiltfilt(sos, fill_nan(y) - fill_nan(y2))
    return None


def cancel_reference(x: np.ndarray, ref: np.ndarray | None, fs: float, f1: float | None) -> np.ndarray:
    """x less its least-squares share of the reference vibration (in the reference's band)."""
    if ref is None:
        return x
    sos = butter(4, [2.8 * f1, min(5.6 * f1, 0.4 * fs)], "bandpass", fs=fs, output="sos")
    xb = sosfiltfilt(sos, x)
    return x - float(np.dot(xb, ref) / max(np.dot(ref, ref), 1e-30)) * ref


def fad_channels(rec: Record, fad_max_m: float) -> dict:
    """{'W': averaged signal of the gauges near x = 0, 'E': near x = L} and their positions."""
    west = np.where(rec.positions_m <= fad_max_m)[0]
    east = np.where(rec.positions_m >= rec.span_m - fad_max_m)[0]
    if len(west) == 0 or len(east) == 0:
        raise ValueError(f"no FAD gauges within {fad_max_m} m of both supports (positions {rec.positions_m.tolist()})")
    return {
        "W": (fill_nan(np.nanmean(rec.values[:, west], axis=1)), float(rec.positions_m[west].mean()), west),
        "E": (fill_nan(np.nanmean(rec.values[:, east], axis=1)), float(rec.positions_m[east].mean()), east),
    }


def robust_sd(x: np.ndarray) -> float:
    return max(1.4826 * float(np.median(np.abs(x - np.median(x)))), 1e-12)


def peak_times(d: np.ndarray, fs: float, height: float, dist: int, lobe: int = 0) -> tuple[np.ndarray, np.ndarray]:
    """Times (s, refined by a parabola through the top three samples) and heights of the
    peaks of d above height. With lobe > 0, a peak with a deeper trough of the other sign
    within lobe samples is dropped: it is the rebound of that other step, not a step."""
    k, p = find_peaks(d, height=height, distance=dist, prominence=0.5 * height)
    k = k[(k > 0) & (k < len(d) - 1)]
    if lobe > 0 and len(k):
        lo = np.clip(k - lobe, 0, len(d))
        hi = np.clip(k + lobe + 1, 0, len(d))
        trough = np.array([-d[a:b].min() for a, b in zip(lo, hi, strict=True)])
        k = k[trough < d[k]]
    a, b, c = d[k - 1], d[k], d[k + 1]
    den = a - 2 * b + c
    frac = np.where(np.abs(den) > 1e-15, 0.5 * (a - c) / np.where(den == 0, 1, den), 0.0)
    return (k + np.clip(frac, -0.5, 0.5)) / fs, b


def group_axles(times: np.ndarray, max_gap_s: float) -> list[np.ndarray]:
    if len(times) == 0:
        return []
    cuts = np.where(np.diff(times) > max_gap_s)[0] + 1
    return np.split(times, cuts)


def xcorr_delay(a: np.ndarray, b: np.ndarray, k0: int, k1: int, lag_min: int, lag_max: int):
    """The lag (samples, parabola-refined) in [lag_min, lag_max] maximising the normalised
    correlation of a[k0:k1] with b[k0 + lag : k1 + lag], and that correlation."""
    lag_max = min(lag_max, len(b) - k1)
    if lag_max <= lag_min or k1 - k0 < 3:
        return None
    seg = a[k0:k1]
    c = np.correlate(b[k0 + lag_min : k1 + lag_max], seg, mode="valid")
    sq = np.concatenate([[0.0], np.cumsum(b[k0 + lag_min : k1 + lag_max] ** 2)])
    n = k1 - k0
    norm = np.sqrt(np.maximum((sq[n:] - sq[:-n]) * np.dot(seg, seg), 1e-30))
    r = c / norm
    i = int(np.argmax(r))
    frac = 0.0
    if 0 < i < len(r) - 1:
        den = r[i - 1] - 2 * r[i] + r[i + 1]
        frac = float(np.clip(0.5 * (r[i - 1] - r[i + 1]) / den, -0.5, 0.5)) if den != 0 else 0.0
    return lag_min + i + frac, float(r[i])


def detect_vehicles(rec: Record, geo: Geometry | None, args) -> tuple[list[Vehicle], dict, Geometry]:
    """Vehicles from the FAD steps (tools/bwim_check.py docstring, step 1), in two passes: a
    vehicle is a group of clear steps (above --fad-threshold) at the entry support whose step
    pattern reappears at the exit support one delay later (the delay by cross-correlation of
    the two step records); its axles are the peaks of the sum of the entry steps and the exit
    steps shifted by the delay (both ends' evidence, --axle-threshold), at least
    --min-spacing-m apart. The bridge's second mode, which the step filter would take for axles, is first
    removed from the FAD records with a reference: the difference of two symmetric
    weighing sections, band-passed around 4 f1 (f1 found blind)."""
    fad = fad_channels(rec, args.fad_max_m)
    fs = rec.fs_hz
    w = max(2, int(round(args.fad_window_s * fs)))
    f1 = first_frequency(rec, args.fad_max_m)
    ref = antisymmetric_reference(rec, args.fad_max_m, f1) if args.cancel_mode2 else None
    filt = {}
    for end, (x, _, _) in fad.items():
        d = step_filter(cancel_reference(x, ref, fs, f1), w)
        # Less its running median: the slow part of the influence line (every axle on the
        # span tilts the record a little) is not a step.
        filt[end] = d - median_filter(d, size=max(3, int(args.trend_window_s * fs)) | 1, mode="nearest")
    sd = {end: robust_sd(d) for end, d in filt.items()}
    info = {"fad_noise_microstrain": sd, "step_filter_samples": w, "f1_hz": f1, "mode2_cancelled": ref is not None}
    L = rec.span_m
    a_w, a_e = fad["W"][1], L - fad["E"][1]
    if geo is None:  # nominal: the middle of each steep part of the influence line
        geo = Geometry(L, {1: a_w / 2, -1: a_e / 2}, {1: L - a_e / 2 - a_w / 2, -1: L - a_w / 2 - a_e / 2})
    vehicles = []
    unconfirmed = 0
    n = len(filt["W"])
    dist0 = max(1, int(round(args.min_axle_sep_s * fs)))
    for direction, ent, ext in ((1, "W", "E"), (-1, "E", "W")):
        d_in, d_out = filt[ent], -filt[ext]
        lobe = int(round(args.lobe_s * fs))
        up, _ = peak_times(d_in, fs, args.fad_threshold * sd[ent], dist0, lobe)
        D = geo.distance[direction]
        groups = group_axles(up, args.max_axle_gap_s)
        for g, seeds in enumerate(groups):
            lo = seeds[0] - args.max_axle_gap_s
            hi = seeds[-1] + args.max_axle_gap_s
            if g > 0:
                lo = max(lo, 0.5 * (groups[g - 1][-1] + seeds[0]))
            if g + 1 < len(groups):
                hi = min(hi, 0.5 * (seeds[-1] + groups[g + 1][0]))
            k0, k1 = max(int(lo * fs), 0), min(int(hi * fs), n)
            # The delay: the exit record's steps correlated with the entry record's.
            xc = xcorr_delay(
                np.maximum(d_in, 0.0),
                np.maximum(d_out, 0.0),
                k0,
                k1,
                int(D / args.v_max * fs),
                int(D / args.v_min * fs) + 1,
            )
            if xc is None or xc[1] < args.min_correlation:
                unconfirmed += 1
                continue
            lag = xc[0]
            delay = lag / fs
            speed = D / delay
            li = int(round(lag))
            k1 = min(k1, n - li)
            both = d_in[k0:k1] + d_out[k0 + li : k1 + li]
            sep = max(1, int(args.min_spacing_m / speed * fs))
            t_ax, _ = peak_times(both, fs, args.axle_threshold * math.hypot(sd[ent], sd[ext]), sep, lobe)
            kk = np.rint(t_ax * fs).astype(int)
            # Each end must see the step on its own too.
            ok = (d_in[k0 + kk] > args.end_threshold * sd[ent]) & (d_out[k0 + li + kk] > args.end_threshold * sd[ext])
            t_ax = t_ax[ok] + k0 / fs
            keep = np.array(sorted(t for t in t_ax if np.min(np.abs(seeds - t)) <= args.max_axle_gap_s))
            if len(keep) == 0:
                unconfirmed += 1
                continue
            # Axles farther apart than any vehicle's belong to different vehicles (a car
            # close ahead of a truck); lone axles are dropped.
            for part in np.split(keep, np.where(np.diff(keep) * speed > args.max_spacing_m)[0] + 1):
                if len(part) >= 2:
                    vehicles.append(Vehicle(direction, part, speed, matched_exit=len(part)))
                else:
                    info["lone_axles"] = info.get("lone_axles", 0) + 1
    vehicles.sort(key=lambda v: v.t_axle[0] - geo.s_entry[v.direction] / v.speed)
    for k, v in enumerate(vehicles):
        v.index = k
    info["unconfirmed_groups"] = unconfirmed
    return vehicles, info, geo
