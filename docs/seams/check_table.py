"""Held-out checks of a gain table from table.py in the full hololine pipeline: every hole, float and 8-bit
codes (clipping counted), R (each column against the same display unblanked) and the Rust test's ratio (each
column against the median of its 6 neighbours each side), over eyes every 0.25 mm off the search's grid, for
contents, pupils and distances the search did not see.

    python3 check_table.py table_K32.npy
"""
import sys
import numpy as np
from hololine import *
from robust import compensate, show, EYES

if __name__ == '__main__':
    gx = np.load(sys.argv[1])
    K = len(gx) // (2 * Z)
    g = 1 + gx.reshape(Z, 2 * K)
    print(sys.argv[1], 'K = %d, |g| max %.2f' % (K, np.abs(g).max()))
    a = uniform_signals(0.5)
    raw = a.copy(); raw[:, BLANKED] = 0
    show('raw, uniform 0.5', a, raw)
    show('gains, uniform 0.5', a, compensate(a, g, K))
    show('gains, uniform 1.0', uniform_signals(1.0), compensate(uniform_signals(1.0), g, K))
    for pupil in [2.5e-3, 5e-3]:
        show('raw, pupil %.1f mm' % (pupil * 1e3), a, raw, pupil=pupil)
        show('gains, pupil %.1f mm' % (pupil * 1e3), a, compensate(a, g, K), pupil=pupil)
    for dist in [0.5, 0.7]:
        show('raw, viewer at %.0f mm' % (dist * 1e3), a, raw, dist=dist, eyes=EYES * dist / D)
        show('gains, viewer at %.0f mm' % (dist * 1e3), a, compensate(a, g, K), dist=dist, eyes=EYES * dist / D)
    rng = np.random.default_rng(11)
    contents = [('random 0.2-1 (new seed)', np.sqrt(rng.uniform(0.2, 1.0, (E, 96)))),
                ('random 0-1', np.sqrt(rng.uniform(0.0, 1.0, (E, 96)))),
                ('smooth, other frequencies', np.sqrt(0.5 + 0.45 * np.sin(np.arange(E)[:, None] / 4.0 + np.arange(96)[None, :] / 17.0 + 1.0))),
                ('edges: bands of 0.2 and 0.9', np.sqrt(np.where((np.arange(E)[:, None] // 9 + np.arange(96)[None, :] // 24) % 2 == 0, 0.9, 0.2)))]
    for name, w in contents:
        s = signals(w)
        b = s.copy(); b[:, BLANKED] = 0
        show('raw, ' + name, s, b)
        show('gains, ' + name, s, compensate(s, g, K))
