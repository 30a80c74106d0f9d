"""Field-level least squares: corrections on the shown samples within K of a hole
(complex, per zone signal), chosen so that every affected emitter's windowed angular
spectrum (complex, within the fan) matches the unblanked display's."""
import numpy as np, sys, time
from hololine import *

HOLE = HOLES[1]                       # 8176: identical context for holes 0..4
EMS = np.arange(70, 138)              # windows affected by hole 2 (crossing chirps 80..127) +- margin
SIN_BINS = SIN_FIRST + SIN_STEP * np.arange(FFTLEN)
BINS = np.where(np.abs(SIN_BINS) < 0.21)[0][::2]

def cspectra(g, ems=EMS):
    idx = FIRST[ems][:, None] + np.arange(WIN)[None, :]
    F = np.fft.fftshift(np.fft.fft(g[idx], n=FFTLEN, axis=1), axes=1)
    return F[:, BINS]

def field_zone(k, vec):
    A = np.fft.fft(vec)
    fine = np.zeros(N * M, complex)
    fine[:N // 2] = A[:N // 2]; fine[-N // 2:] = A[N // 2:]
    return np.fft.ifft(fine) * M * CARRIER[k]

def positions(K, inside=False):
    left = np.arange(HOLE - K, HOLE); right = np.arange(HOLE + 16, HOLE + 16 + K)
    if inside:
        return np.concatenate([left, np.arange(HOLE, HOLE + 16), right])
    return np.concatenate([left, right])

def response_matrix(pos):
    cols = []
    for k in range(Z):
        for n in pos:
            v = np.zeros(N, complex); v[n] = 1.0
            cols.append(cspectra(propagate(field_zone(k, v))).ravel())
    return np.array(cols).T      # rows: (emitter, bin); cols: (zone, pos)

def target(a):
    b = a.copy(); b[:, BLANKED] = 0
    return (cspectra(emitter_plane(a)) - cspectra(emitter_plane(b))).ravel(), b

def apply(b, pos, x, holes=HOLES):
    """Add correction x (Z*len(pos)) at every hole (same offsets)."""
    out = b.copy()
    x = x.reshape(Z, len(pos))
    for h in holes:
        p = pos - HOLE + h
        ok = (p >= 0) & (p < N)
        for k in range(Z):
            out[k, p[ok]] += x[k, ok]
    return out

if __name__ == '__main__':
    a = uniform_signals(0.5)
    t, b = target(a)
    print('rows', len(t), 'target norm', np.linalg.norm(t))
    for K in [4, 8, 16, 24, 32]:
        pos = positions(K)
        T0 = time.time()
        A = response_matrix(pos)
        x, *_ = np.linalg.lstsq(A, t, rcond=None)
        res = np.linalg.norm(A @ x - t) / np.linalg.norm(t)
        np.save('/tmp/lsq_K%d.npy' % K, x)
        print('K', K, 'relative field residual %.3f' % res, 'max |x| %.3f' % np.abs(x).max(), 'time %.1f' % (time.time() - T0))
        sys.stdout.flush()
