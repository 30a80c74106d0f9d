"""A faithful 1-D numpy model of one Mark III hololine as `holo view` sees it.

Follows the Rust code step by step (numbers from src/layout/builtin.rs,
src/assemble/chirp.rs, src/reconstruct/{field,propagate,viewer}.rs):

  signals  a_k(n) = (1/16) sum_e w_e exp(i phi_k(n - 64 e - 1024 k)),  k = 0,1,2 (I + iQ)
  blanking a_k(n) = 0 where n mod 4096 >= 4080 (same n in all six signals)
  8-bit    code = round(clamp(128 + 127 x)), decoded (code - 128)/127 (optional)
  field    E(x) = sum_k sinc-interp(a_k)(x) exp(+i 2 pi G_k x/p), M = 3 samples per p
  propag.  band-limited angular spectrum over z_e, padded to fast_len(2 (N M + 1))
  emitter  rectangular window of 192 fine samples starting at round((x_e - pitch/2 - x0)/dx),
           FFT of 2048, power per bin; eye = power in the pupil's sin-theta interval
           (bins spread evenly), divided by the calibration emitter's power there.
"""
import numpy as np

LAM = 633e-9
E = 336
S = 64
L = 1024
Z = 3
N = 24576
P = 0.080 / (E * S)                      # sample pitch 3.7202 um
ZE = Z * L * P / (2 * np.tan(np.radians(12)))   # 26.88 mm
D = 0.600                                # viewer distance (eye z)
PUPIL = 4e-3
M = 3                                    # field oversampling (field.rs: floor(2*1.222*1.1)+1)
LINE, WIDTH = 4096, 4080
NORM = 16.0                              # ceil(L/S)
EPITCH = S * P
WIN = int(round(EPITCH / (P / M)))       # 192
FFTLEN = 1 << (8 * WIN - 1).bit_length() # 2048
DX = P / M
X0 = (0.5 - N / 2) * P                   # x of fine sample 0


def emitter_x(e):
    return (64.0 * np.asarray(e) + 1536 - N / 2) * P


def offset_samples(zone, u):
    return zone * L + u + 0.5 - Z * L / 2


def sin_theta(d):
    d = d * P
    return -d / np.sqrt(d * d + ZE * ZE)


def zone_shift(zone):
    lo = sin_theta(offset_samples(zone, -0.5))
    hi = sin_theta(offset_samples(zone, L - 0.5))
    c = (lo + hi) / 2 * P / LAM
    return np.round(c * S) / S


G = np.array([zone_shift(k) for k in range(Z)])   # +0.8125, 0, -0.8125
C = -G                                             # signal carriers (I/Q: F = 0)


def chirp_phase(d):
    d = d * P
    r = np.sqrt(d * d + ZE * ZE)
    return -2 * np.pi / LAM * (d * d / (r + ZE))


U = np.arange(L)
TEMPLATE = [np.exp(1j * (chirp_phase(offset_samples(k, U)) + 2 * np.pi * np.mod(C[k] * (k * L + U), 1.0)))
            for k in range(Z)]
N_IDX = np.arange(N)
BLANKED = (N_IDX % LINE) >= WIDTH
HOLES = [4096 * j + WIDTH for j in range(6)]        # first blanked sample of each hole


# The basis's tapers (spec/layouts.md §4.2): `segment_taper_samples` T and `piece_taper_samples` T_p, from the
# environment (SEGMENT_TAPER, PIECE_TAPER; both 0, hard segments, unless set), so that every script here can be run
# for either basis: e.g. `PIECE_TAPER=64 python3 table.py ...` for the `mark3` layout's basis.
import os
SEGMENT_TAPER = int(os.environ.get('SEGMENT_TAPER', '0'))
PIECE_TAPER = int(os.environ.get('PIECE_TAPER', '0'))
# Which piece ends T_p fades, for the study of docs/seams/README.md §8: 'both' (spec/layouts.md §4.2), 'zones' (where
# two pieces meet) or 'chirp' (the chirp's own two ends); the others stay as T says.
PIECE_ENDS = os.environ.get('PIECE_ENDS', 'both')
SEG = L // 32                                  # samples per view segment


def _rise(t, width):
    return 0.5 * (1 + np.sin(np.pi * np.clip(t / width, -0.5, 0.5)))


def windows(zone, T=None, Tp=None):
    """(first u, weights 32 x len): every view segment's weight over zone `zone`'s piece, widened by half a taper
    across each edge it shares with a neighbour (chirp.rs `window`): edges inside a piece fade over T, edges between
    pieces over T_p (T when T_p is 0), the chirp's own two ends over T_p/2 (T/2) inside the segment."""
    T = SEGMENT_TAPER if T is None else T
    Tp = PIECE_TAPER if Tp is None else Tp
    piece = Tp if Tp else T
    zone_edge = piece if PIECE_ENDS in ('both', 'zones') else T
    end = piece if PIECE_ENDS in ('both', 'chirp') else T
    end = int(os.environ.get('END_TAPER', end))
    h = max(T, zone_edge) // 2
    u = np.arange(-h, L + h)
    c = u + 0.5
    out = np.zeros((32, len(u)))
    for i in range(32):
        a, b = i * SEG, (i + 1) * SEG
        at_start, at_end = zone == 0 and i == 0, zone == Z - 1 and i == 31
        w_up = zone_edge if i == 0 else T
        w_down = zone_edge if i == 31 else T
        if at_start:
            up = _rise(c - a - end / 4, end / 2) if end else (c >= a) * 1.0
        else:
            up = _rise(c - a, w_up) if w_up else (c >= a) * 1.0
        if at_end:
            down = _rise(b - c - end / 4, end / 2) if end else (c < b) * 1.0
        else:
            down = _rise(b - c, w_down) if w_down else (c < b) * 1.0
        out[i] = up * down
    return -h, out


def _tapered_templates():
    out = []
    for k in range(Z):
        first, win = windows(k)
        u = np.arange(first, first + win.shape[1])
        ph = np.exp(1j * (chirp_phase(offset_samples(k, u)) + 2 * np.pi * np.mod(C[k] * (k * L + u), 1.0)))
        out.append((first, win, ph))
    return out


TAPERED = _tapered_templates() if (SEGMENT_TAPER or PIECE_TAPER) else None


def signals(weights, per_sample=None):
    """Zone signals (Z x N complex) for per-emitter, per-view weights sqrt(m).

    weights: (E,) or (E, 96) array of sqrt(m) (views ascending in theta).
    """
    w = np.asarray(weights, float)
    if w.ndim == 1:
        w = np.repeat(w[:, None], 96, axis=1)
    a = np.zeros((Z, N), complex)
    if TAPERED is not None:
        for k in range(Z):
            first, win, ph = TAPERED[k]
            amp = w[:, 95 - (32 * k + np.arange(32))] @ win          # E x len
            for e in range(E):
                n0 = e * S + k * L + first
                lo, hi = max(n0, 0), min(n0 + win.shape[1], N)
                a[k, lo:hi] += (amp[e] * ph)[lo - n0:hi - n0]
        return a / NORM
    for k in range(Z):
        for e in range(E):
            n0 = e * S + k * L
            # segment i within zone k (along chirp) -> view 95 - (32k + i)
            seg = w[e, 95 - (32 * k + np.arange(32))]
            a[k, n0:n0 + L] += np.repeat(seg, 32) * TEMPLATE[k]
    return a / NORM


def quantize(a):
    def q(x):
        return (np.clip(np.round(128 + 127 * x), 0, 255) - 128) / 127  # numpy rounds half to even
    return q(a.real) + 1j * q(a.imag)


def fast_len(n):
    best = 1 << (n - 1).bit_length()
    p3 = 3
    while p3 < best:
        best = min(best, (1 << (-(-n // p3) - 1).bit_length()) * p3)
        p3 *= 3
    return best


PLEN = fast_len(2 * (N * M + 1))
_f = np.fft.fftfreq(PLEN, DX)
_df = 1 / (PLEN * DX)
_flim = 1 / (LAM * np.sqrt((2 * _df * ZE) ** 2 + 1))
TRANSFER = np.where(np.abs(_f) > _flim, 0, np.exp(2j * np.pi * ZE * np.sqrt(np.maximum(LAM ** -2 - _f ** 2, 0))))
_kf = np.arange(N * M)
CARRIER = [np.exp(-2j * np.pi * C[k] * _kf / M) for k in range(Z)]


def field(a):
    """Hologram-plane field on the fine grid (N*M samples), field.rs."""
    tot = np.zeros(N * M, complex)
    for k in range(Z):
        A = np.fft.fft(a[k])
        fine = np.zeros(N * M, complex)
        fine[:N // 2] = A[:N // 2]
        fine[-N // 2:] = A[N // 2:]
        tot += np.fft.ifft(fine) * M * CARRIER[k]
    return tot


def propagate(f):
    buf = np.zeros(PLEN, complex)
    buf[:len(f)] = f
    return np.fft.ifft(np.fft.fft(buf) * TRANSFER)[:len(f)]


FIRST = np.round((emitter_x(np.arange(E)) - EPITCH / 2 - X0) / DX).astype(int)
SIN_STEP = LAM / (FFTLEN * DX)
SIN_FIRST = -(FFTLEN // 2) * SIN_STEP


def spectra(g, emitters=None):
    """Power per bin (E x FFTLEN, increasing sin theta) of each emitter's window."""
    es = np.arange(E) if emitters is None else np.asarray(emitters)
    idx = FIRST[es][:, None] + np.arange(WIN)[None, :]
    w = g[idx]
    F = np.fft.fft(w, n=FFTLEN, axis=1)
    return np.abs(np.fft.fftshift(F, axes=1)) ** 2


def between(power, lo, hi):
    """EmitterSpectrum::between, vectorised: power (..., n), lo/hi broadcast to (...)."""
    n = power.shape[-1]
    cum = np.concatenate([np.zeros(power.shape[:-1] + (1,)), np.cumsum(power, axis=-1)], axis=-1)

    def F(s):
        u = np.clip((s - SIN_FIRST) / SIN_STEP + 0.5, 0, n)
        k = np.minimum(np.floor(u).astype(int), n - 1)
        frac = u - k
        ck = np.take_along_axis(cum, k[..., None], -1)[..., 0]
        pk = np.take_along_axis(power, k[..., None], -1)[..., 0]
        return ck + frac * pk

    return np.maximum(F(hi) - F(lo), 0)


def pupil_interval(e, eye_x, pupil=PUPIL, dist=D):
    xe = emitter_x(e)
    s = lambda x: (x - xe) / np.sqrt((x - xe) ** 2 + (dist - ZE) ** 2)
    return s(eye_x - pupil / 2), s(eye_x + pupil / 2)


def emitter_plane(a):
    return propagate(field(a))


_CAL = None


def calibration():
    global _CAL
    if _CAL is None:
        w = np.zeros(E)
        w[E // 2] = 1.0
        _CAL = spectra(emitter_plane(signals(w)), [E // 2])[0]
    return _CAL


def seen(spec, eye_xs, emitters=None, pupil=PUPIL):
    """Calibrated brightness: (len(eye_xs), len(emitters))."""
    es = np.arange(E) if emitters is None else np.asarray(emitters)
    ex = np.asarray(eye_xs, float)[:, None]
    lo, hi = pupil_interval(es[None, :], ex, pupil)
    num = between(np.broadcast_to(spec, (ex.shape[0],) + spec.shape), lo, hi)
    cal = calibration()
    ref = between(np.broadcast_to(cal, lo.shape + cal.shape), lo, hi)
    return np.where(ref > 0, num / np.where(ref > 0, ref, 1), 0)


def darkest(cols, lo=6, hi=E - 6):
    """The test's statistic per eye: min and max over emitters lo..hi of column / median(+-6)."""
    cols = np.atleast_2d(cols)
    ratios = np.full(cols.shape, np.nan)
    for e in range(lo, hi):
        nb = np.concatenate([cols[:, e - 6:e], cols[:, e + 1:e + 7]], axis=1)
        ratios[:, e] = cols[:, e] / np.median(nb, axis=1)
    return ratios


def uniform_signals(level=0.5):
    return signals(np.full(E, np.sqrt(level)))


def _cumF(power, cum, rows, s):
    n = power.shape[-1]
    u = np.clip((s - SIN_FIRST) / SIN_STEP + 0.5, 0, n)
    k = np.minimum(np.floor(u).astype(int), n - 1)
    return cum[rows, k] + (u - k) * power[rows, k]


def seen_many(spec, eye_xs, pupil=PUPIL, dist=D):
    """Like `seen` for every emitter and many eyes without broadcasting the spectra."""
    cum = np.concatenate([np.zeros((spec.shape[0], 1)), np.cumsum(spec, axis=1)], axis=1)
    cal = calibration()[None, :]
    ccum = np.concatenate([np.zeros((1, 1)), np.cumsum(cal, axis=1)], axis=1)
    es = np.arange(spec.shape[0])
    ex = np.asarray(eye_xs, float)[:, None]
    lo, hi = pupil_interval(es[None, :], ex, pupil, dist)
    rows = np.broadcast_to(es[None, :], lo.shape)
    num = _cumF(spec, cum, rows, hi) - _cumF(spec, cum, rows, lo)
    z = np.zeros_like(rows)
    ref = _cumF(cal, ccum, z, hi) - _cumF(cal, ccum, z, lo)
    return np.where(ref > 0, num / np.where(ref > 0, ref, 1), 0), lo, hi


def ratio_stats(cols, lo, hi, fan=0.2):
    """The test's ratio (column / median of +-6 neighbours) per eye and emitter,
    NaN where the column or a neighbour looks out of |sin| < fan."""
    ok = (lo > -fan) & (hi < fan)
    nE = cols.shape[1]
    r = np.full(cols.shape, np.nan)
    for e in range(6, nE - 6):
        nb = np.concatenate([cols[:, e - 6:e], cols[:, e + 1:e + 7]], axis=1)
        good = ok[:, e - 6:e + 7].all(axis=1)
        r[:, e] = np.where(good, cols[:, e] / np.median(nb, axis=1), np.nan)
    return r
