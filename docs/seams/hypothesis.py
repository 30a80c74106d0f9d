"""Is the taper's overbright light a multi-emitter effect (light of other chirps' raises landing
in this window) or the chirp's own? Compare, for the emitters crossing hole 1, what eyes see
(a) with every emitter lit (uniform 0.5), (b) with only that emitter lit (its own chirp alone),
each relative to the same display unblanked. R as a function of the pupil centre's offset from
the direction in which the emitter's chirp crosses the hole."""
import numpy as np
from hololine import *
from taper import taper_gain
from where import hole_sin
EYES = np.arange(-0.080, 0.08001, 0.0001)
HOLE_J = 1
ES = np.arange(84, 124, 3)       # emitters whose chirp crosses hole 1 (80..127), every third

def profile(gain, single, es=ES):
    out = []
    for e in es:
        w = np.zeros(E); w[:] = np.sqrt(0.5)
        if single:
            w[:] = 0; w[e] = np.sqrt(0.5)
        a = signals(w)
        b = a * gain; b[:, BLANKED] = 0
        su = spectra(emitter_plane(a), [e]); sb = spectra(emitter_plane(b), [e])
        cu, lo, hi = seen_many(np.repeat(su, E, 0)[:E], EYES)   # only column e is meaningful
        cb, _, _ = seen_many(np.repeat(sb, E, 0)[:E], EYES)
        s = (lo[:, e] + hi[:, e]) / 2
        ok = (lo[:, e] > -0.2) & (hi[:, e] < 0.2)
        ds = s - hole_sin(e, HOLE_J)
        R = cb[:, e] / cu[:, e]
        out.append((e, ds[ok], R[ok]))
    return out

if __name__ == '__main__':
    cases = {'raw': np.ones(N), 'taper K5 A2.8 cos': taper_gain(5, 2.8), 'taper K8 A1.8 lin': taper_gain(8, 1.8, lin=True)}
    for name, g in cases.items():
        for single in [True, False]:
            res = profile(g, single)
            allR = np.concatenate([r for _, _, r in res]); allds = np.concatenate([d for _, d, _ in res])
            near = np.abs(allds) < 0.004
            far = np.abs(allds) > 0.012
            print('%-20s %-8s R min %.3f max %.3f | |ds|<0.004: %.3f..%.3f | 0.004..0.012: %.3f..%.3f | |ds|>0.012: %.3f..%.3f' % (
                name, 'single' if single else 'all', allR.min(), allR.max(), allR[near].min(), allR[near].max(),
                allR[~near & ~far].min(), allR[~near & ~far].max(), allR[far].min(), allR[far].max()))
            if name != 'raw' and not single:
                e, d, r = res[len(res) // 2]
                sel = np.abs(d) < 0.02
                print('   emitter', e, 'R vs ds:', ' '.join('%+.4f:%.2f' % (x, y) for x, y in zip(d[sel][::6], r[sel][::6])))
