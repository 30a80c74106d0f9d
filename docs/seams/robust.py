"""Check a compensation found on hole 1 with 4 mm pupils at 600 mm in the full hololine pipeline:
every hole, 8-bit codes (clipping counted), the Rust test's statistic (column / median of +-6),
other pupils and distances, and - for per-sample gains - other content."""
import numpy as np, sys
from hololine import *
from lsq import HOLE, apply

EYES = np.arange(-0.080, 0.08001, 0.00025) + 0.0001   # off the optimisation grid

def positions(K):
    return np.concatenate([np.arange(HOLE - K, HOLE), np.arange(HOLE + 16, HOLE + 16 + K)])

def gains_from(c, K):
    a = uniform_signals(0.5)
    pos = positions(K)
    ideal = np.array([a[k, pos] for k in range(Z)])
    return 1 + c.reshape(Z, 2 * K) / ideal

def compensate(a, g, K):
    """Per-sample complex gains g (Z x 2K) beside every hole, on signals a."""
    b = a.copy()
    pos = positions(K)
    for h in HOLES:
        p = pos - HOLE + h
        ok = (p >= 0) & (p < N)
        for k in range(Z):
            b[k, p[ok]] *= g[k, ok]
    b[:, BLANKED] = 0
    return b

def stats(a, b, quant, pupil=PUPIL, dist=D, eyes=EYES):
    clipped = 0
    if quant:
        x = np.concatenate([b.real.ravel(), b.imag.ravel()])
        clipped = int(np.sum((128 + 127 * x > 255.5) | (128 + 127 * x < -0.5)))
        b = quantize(b); a = quantize(a)
    cu, lo, hi = seen_many(spectra(emitter_plane(a)), eyes, pupil, dist)
    cb, _, _ = seen_many(spectra(emitter_plane(b)), eyes, pupil, dist)
    ok = (lo > -0.2) & (hi < 0.2)
    R = np.where(ok, cb / cu, np.nan)
    T = ratio_stats(cb, lo, hi)
    return np.nanmin(R), np.nanmax(R), np.nanmin(T), np.nanmax(T), clipped

def show(name, a, b, **kw):
    for quant in [False, True]:
        r = stats(a, b, quant, **kw)
        print('  %-34s %s R %.3f..%.3f  test-ratio %.3f..%.3f  clipped %d' % (name, '8-bit' if quant else 'float', *r))
    sys.stdout.flush()

if __name__ == '__main__':
    K = int(sys.argv[1]); path = sys.argv[2]
    c = np.load(path)
    g = gains_from(c, K)
    print(path, 'gain |g| max %.2f, |g-1| rms %.2f' % (np.abs(g).max(), np.sqrt(np.mean(np.abs(g - 1) ** 2))))
    a = uniform_signals(0.5)
    b0 = a.copy(); b0[:, BLANKED] = 0
    show('raw, uniform 0.5', a, b0)
    show('compensated, uniform 0.5', a, compensate(a, g, K))
    show('compensated, uniform 1.0', uniform_signals(1.0), compensate(uniform_signals(1.0), g, K))
    for pupil in [2e-3, 3e-3, 6e-3]:
        show('pupil %.0f mm' % (pupil * 1e3), a, compensate(a, g, K), pupil=pupil)
    for dist in [0.45, 0.8]:
        show('viewer at %.0f mm' % (dist * 1e3), a, compensate(a, g, K), dist=dist, eyes=EYES * dist / D)
    rng = np.random.default_rng(1)
    w = np.sqrt(rng.uniform(0.2, 1.0, (E, 96)))
    ar = signals(w)
    show('random content 0.2-1 (gains)', ar, compensate(ar, g, K))
    ws = np.sqrt(0.5 + 0.4 * np.sin(np.arange(E) / 7.0))
    asm = signals(ws)
    show('smooth varying content (gains)', asm, compensate(asm, g, K))
