"""Full-pipeline check of a table_segments.py result (or, for comparison, a gain table from table.py): every hole,
8-bit codes, at the Rust test's eyes (-40, 0, +40 mm) and at eyes every 0.25 mm, for uniform content and three
contents neither search saw.

    python3 check_segments.py table_segments_K64.npy
"""
import sys
import numpy as np
from hololine import *
from robust import compensate, stats, EYES

def cut_factors(w, q):
    w = np.array(np.broadcast_to(np.asarray(w, float)[:, None] if np.ndim(w) == 1 else w, (E, 96)))
    for h in HOLES:
        s0 = h - 16
        for k in range(Z):
            for e in range(E):
                n0 = 64 * e + 1024 * k
                if (s0 - n0) % 32 == 0 and 0 <= (s0 - n0) // 32 < 32:
                    v = 95 - (32 * k + (s0 - n0) // 32)
                    w[e, v] *= q[v]
    return w

if __name__ == '__main__':
    x = np.load(sys.argv[1]); K = 64; n = Z * 2 * K
    if x.dtype == complex:
        gx = x; q = np.ones(96)
    else:
        gx = x[:n] + 1j * x[n:2 * n]; q = 1 + x[2 * n:2 * n + 96]
    g = 1 + gx.reshape(Z, 2 * K)
    test_eyes = np.array([-0.04, 0.0, 0.04])
    rng = np.random.default_rng(11)
    contents = [('uniform 0.5', np.full(E, np.sqrt(0.5))),
                ('random 0.2-1', np.sqrt(rng.uniform(0.2, 1.0, (E, 96)))),
                ('smooth, other frequencies', np.sqrt(0.5 + 0.45 * np.sin(np.arange(E)[:, None] / 4.0 + np.arange(96)[None, :] / 17.0 + 1.0))),
                ('bands 0.2/0.9', np.sqrt(np.where((np.arange(E)[:, None] // 9 + np.arange(96)[None, :] // 24) % 2 == 0, 0.9, 0.2)))]
    for name, w in contents:
        a = signals(w)
        b = compensate(signals(cut_factors(w, q)), g, K)
        for eyes, what in [(test_eyes, 'test eyes'), (EYES, 'all eyes')]:
            r = stats(a, b, True, eyes=eyes)
            print('  %-26s %-9s 8-bit R %.3f..%.3f  test-ratio %.3f..%.3f  clipped %d' % (name, what, *r)); sys.stdout.flush()
