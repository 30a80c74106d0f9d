"""A flat-field table from `table.py --flat` against the general table (`table_K64_edges.npy`, made as §6 says):
uniform content at the Rust test's eyes and at every eye, float and 8-bit codes, and nearly uniform content (each
radiance up to d below 0.5) at every eye.

    python3 check_flat.py flat_K128.npy
"""
import sys
import numpy as np
from hololine import *
from robust import compensate, stats, EYES

flat = 1 + np.load(sys.argv[1]).reshape(Z, -1)
gen = 1 + np.load('table_K64_edges.npy').reshape(Z, -1)
test_eyes = np.array([-0.04, 0.0, 0.04])
rng = np.random.default_rng(5)
for level in [0.5, 1.0]:
    a = uniform_signals(level)
    for name, g in [('general', gen), ('flat', flat)]:
        for eyes, what in [(test_eyes, 'test eyes'), (EYES, 'all eyes')]:
            for q in [False, True]:
                r = stats(a, compensate(a, g, g.shape[1] // 2), q, eyes=eyes)
                print('uniform %.1f %-8s %-9s %s R %.3f..%.3f test-ratio %.3f..%.3f clipped %d' % (level, name, what, '8-bit' if q else 'float', *r)); sys.stdout.flush()
for d in [0.01, 0.03, 0.1, 0.3]:
    c = 0.5 * (1 - d * rng.uniform(0, 1, (E, 96)))
    w = np.sqrt(c); a = signals(w)
    for name, g in [('general', gen), ('flat', flat)]:
        r = stats(a, compensate(a, g, g.shape[1] // 2), True, eyes=EYES)
        print('spread %.2f %-8s all eyes 8-bit R %.3f..%.3f test-ratio %.3f..%.3f clipped %d' % (d, name, *r)); sys.stdout.flush()
