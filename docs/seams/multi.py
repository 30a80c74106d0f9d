"""Robust search: one per-sample complex gain table beside the hole (K samples each side, per zone),
judged at once over several contents, pupils and distances (each relative to the same display unblanked)."""
import numpy as np, sys, time
from opt import *
from scipy.optimize import minimize

class Scenario:
    def __init__(self, weights, pupil=PUPIL, dist=D, pos=None):
        a = signals(weights)
        b = a.copy(); b[:, BLANKED] = 0
        self.S0 = cspec(emitter_plane(b)); Su = cspec(emitter_plane(a))
        eyes = EYES * dist / D
        lo, hi = pupil_interval(EMS[None, :], eyes[:, None], pupil, dist)
        self.W, *_ = cell_matrix_general(eyes, pupil, dist)
        self.ref = self.W @ np.abs(Su) ** 2
        self.ideal = np.concatenate([a[k, pos] for k in range(Z)])

def cell_matrix_general(eyes, pupil, dist):
    import opt
    lo, hi = pupil_interval(EMS[None, :], np.asarray(eyes)[:, None], pupil, dist)
    # reuse opt.cell_matrix's construction with these intervals
    ok = ((lo > -0.2) & (hi < 0.2)).ravel()
    lo, hi = lo.ravel()[ok], hi.ravel()[ok]
    erow = np.broadcast_to(np.arange(len(EMS))[None, :], (len(eyes), len(EMS))).ravel()[ok]
    ulo = (lo - SIN_FIRST) / SIN_STEP + 0.5 - BINS[0]; uhi = (hi - SIN_FIRST) / SIN_STEP + 0.5 - BINS[0]
    rows, cols, vals = [], [], []
    k0 = np.floor(ulo).astype(int); span = (np.ceil(uhi).astype(int) - k0).max()
    for j in range(span):
        k = k0 + j
        w = np.clip(np.minimum(uhi, k + 1) - np.maximum(ulo, k), 0, None)
        m = (w > 0) & (k >= 0) & (k < NB)
        rows.append(np.nonzero(m)[0]); cols.append(erow[m] * NB + k[m]); vals.append(w[m])
    W = sps.csr_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))), shape=(len(lo), len(EMS) * NB))
    return W, ok

if __name__ == '__main__':
    K = int(sys.argv[1]); iters = int(sys.argv[2])
    pos = np.concatenate([np.arange(HOLE - K, HOLE), np.arange(HOLE + 16, HOLE + 16 + K)])
    A = response(pos); AH = A.conj().T
    rng = np.random.default_rng(7)
    u = np.full(E, np.sqrt(0.5))
    scen = [('uniform 4mm', Scenario(u, pos=pos)), ('uniform 2mm', Scenario(u, 2e-3, pos=pos)),
            ('uniform 6mm', Scenario(u, 6e-3, pos=pos)), ('uniform 4mm@800', Scenario(u, dist=0.8, pos=pos)),
            ('random A', Scenario(np.sqrt(rng.uniform(0.2, 1, (E, 96))), pos=pos)),
            ('random B', Scenario(np.sqrt(rng.uniform(0.2, 1, (E, 96))), pos=pos))]
    # (a lone lit emitter is left out: its neighbours' columns are dark, so R there is 0/0)
    n = A.shape[1]; p = 8
    def f(x):
        gx = x[:n] + 1j * x[n:]
        Ltot = 0; G = np.zeros(n, complex)
        for _, s in scen:
            c = s.ideal * gx
            S = s.S0 + A @ c
            R = s.W @ np.abs(S) ** 2 / s.ref
            d = R - 1; ss = np.sum(d ** p); L = ss ** (1 / p)
            dR = ss ** (1 / p - 1) * d ** (p - 1)
            gc = AH @ ((s.W.T @ (dR / s.ref)) * S)
            G += s.ideal.conj() * gc; Ltot += L
        return Ltot, np.concatenate([2 * G.real, 2 * G.imag])
    t = time.time()
    r = minimize(f, np.zeros(2 * n), jac=True, method='L-BFGS-B', options={'maxiter': iters})
    gx = r.x[:n] + 1j * r.x[n:]
    np.save('/tmp/multi_gain_K%d.npy' % K, gx)
    print('K=%d robust gain search, %d iterations, %.0f s' % (K, r.nit, time.time() - t))
    for name, s in scen:
        R = s.W @ np.abs(s.S0 + A @ (s.ideal * gx)) ** 2 / s.ref
        R0 = s.W @ np.abs(s.S0) ** 2 / s.ref
        print('  %-18s raw %.3f..%.3f  compensated %.3f..%.3f' % (name, R0.min(), R0.max(), R.min(), R.max()))
    print('  gain |1+x| max %.2f' % np.abs(1 + gx).max())
