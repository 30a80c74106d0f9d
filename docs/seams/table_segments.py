"""Blanking gains plus a per-view factor on the elements a hole cuts: the plain remedy (raise the weight of every
element whose segment loses samples to the blanking) as more freedom for table.py's search. A hole cuts the second
half of one 32-sample segment of each of the 16 chirps per zone that cross it, so 48 of the 96 views have a factor
that matters; weights are scaled before the zone sum, then the gains apply as in table.py.

    python3 table_segments.py K ITERATIONS [--start START.npy] [--nominal W] [--out NAME.npy] [--complex]

START may be a gain table from table.py (complex) or a result of this script. NAME.npy (default
table_segments_K{K}.npy) holds the real parameter vector: Re and Im of the gains minus 1, then the factors minus 1.
Not used in any layout (README §6 says why); check_segments.py checks a result in the full pipeline.
"""
import sys
import numpy as np, time, argparse
from table import *
from scipy.optimize import minimize

def seg_matrix(weights, pos):
    """T: (Z*len(pos), 96) complex: the change of the zone signals at pos per unit change of view v's factor
    on the segments hole HOLE cuts (those ending at HOLE + 16: the hole is their second half)."""
    w = np.asarray(weights, float)
    if w.ndim == 1: w = np.repeat(w[:, None], 96, axis=1)
    T = np.zeros((Z * len(pos), 96), complex)
    s0 = HOLE - 16
    for k in range(Z):
        for e in range(E):
            n0 = 64 * e + 1024 * k
            if (s0 - n0) % 32 or not 0 <= (s0 - n0) // 32 < 32: continue
            i = (s0 - n0) // 32; v = 95 - (32 * k + i)
            for j, n in enumerate(pos):
                if s0 <= n < s0 + 32:
                    T[k * len(pos) + j, v] += w[e, v] * TEMPLATE[k][n - n0] / NORM
    return T

if __name__ == '__main__':
    ap = argparse.ArgumentParser()
    ap.add_argument('K', type=int); ap.add_argument('iters', type=int)
    ap.add_argument('--start'); ap.add_argument('--out'); ap.add_argument('--complex', action='store_true')
    ap.add_argument('--nominal', type=float, default=1.0)
    args = ap.parse_args()
    K = args.K
    pos = np.concatenate([np.arange(HOLE - K, HOLE), np.arange(HOLE + 16, HOLE + 16 + K)])
    t = time.time()
    A = response(pos); AH = A.conj().T
    scen = scenarios(pos, True)
    rng = np.random.default_rng(7)
    # the weights each scenario was built from, for T (same order and seeds as table.scenarios)
    u = np.full(E, np.sqrt(0.5))
    smooth = np.sqrt(0.5 + 0.4 * np.sin(np.arange(E)[:, None] / 7.0 + np.arange(96)[None, :] / 11.0))
    ws = [u] * 6 + [np.sqrt(rng.uniform(0.2, 1, (E, 96))), np.sqrt(rng.uniform(0.2, 1, (E, 96))), smooth,
          edge(100, 0.0), edge(110, 0.15, flip=True), edge(118, -0.1, bright=0.5, dark=0.15),
          np.sqrt(np.where((np.arange(E)[:, None] >= 92) & (np.arange(E)[:, None] < 104) & (np.arange(96)[None, :] >= 0), 0.9, 0.1)),
          np.sqrt(np.random.default_rng(3).uniform(0, 1, (E, 96)))]
    for (_, sc), w in zip(scen, ws):
        sc.den = getattr(sc, 'den', sc.ref)
        sc.T = seg_matrix(w, pos)
    full = np.concatenate([uniform_signals(1.0)[k, pos] for k in range(Z)])
    Tfull = seg_matrix(np.full(E, 1.0), pos)
    print('set up %.0f s' % (time.time() - t)); sys.stdout.flush()
    n = A.shape[1]; p = 8; nq = 96 * (2 if args.complex else 1)
    def unpack(x):
        gx = x[:n] + 1j * x[n:2 * n]
        q = x[2 * n:2 * n + 96] + (1j * x[2 * n + 96:] if args.complex else 0)
        return gx, q
    def f(x):
        gx, q = unpack(x)
        Ltot = 0; G = np.zeros(n, complex); Q = np.zeros(96, complex)
        for i, (_, s) in enumerate(scen):
            wt = args.nominal if i == 0 else 1.0
            base = s.ideal + s.T @ q
            c = (1 + gx) * base - s.ideal
            S = s.S0 + A @ c
            R = 1 + (s.W @ np.abs(S) ** 2 - s.ref) / s.den
            d = R - 1; ss = np.sum(d ** p); L = wt * ss ** (1 / p)
            dR = wt * ss ** (1 / p - 1) * d ** (p - 1)
            gc = AH @ ((s.W.T @ (dR / s.den)) * S)
            G += base.conj() * gc; Q += s.T.conj().T @ ((1 + gx).conj() * gc); Ltot += L
        y = (1 + gx) * (full + Tfull @ q)
        over_r = np.maximum(np.abs(y.real) - PEAK, 0) * np.sign(y.real)
        over_i = np.maximum(np.abs(y.imag) - PEAK, 0) * np.sign(y.imag)
        Ltot += 100 * np.sum(over_r ** 2 + over_i ** 2)
        gy = 100 * (over_r + 1j * over_i)
        G += (full + Tfull @ q).conj() * gy; Q += Tfull.conj().T @ ((1 + gx).conj() * gy)
        gq = [2 * Q.real] + ([2 * Q.imag] if args.complex else [])
        return Ltot, np.concatenate([2 * G.real, 2 * G.imag] + gq)
    x0 = np.zeros(2 * n + nq)
    if args.start:
        g0 = np.load(args.start)
        if g0.dtype == complex: x0[:2 * n] = np.concatenate([g0.real, g0.imag])
        else: x0[:len(g0)] = g0
    t = time.time()
    r = minimize(f, x0, jac=True, method='L-BFGS-B', options={'maxiter': args.iters})
    np.save(args.out or 'table_segments_K%d.npy' % K, r.x)
    gx, q = unpack(r.x)
    print('K=%d gains + segment factors, %d iterations, %.0f s, objective %.4f' % (K, r.nit, time.time() - t, r.fun))
    for name, s in scen:
        c = (1 + gx) * (s.ideal + s.T @ q) - s.ideal
        R = 1 + (s.W @ np.abs(s.S0 + A @ c) ** 2 - s.ref) / s.den
        R0 = 1 + (s.W @ np.abs(s.S0) ** 2 - s.ref) / s.den
        print('  %-24s raw %.3f..%.3f  compensated %.3f..%.3f' % (name, R0.min(), R0.max(), R.min(), R.max()))
    y = (1 + gx) * (full + Tfull @ q)
    print('  gain |1+x| max %.2f; factors %s; uniform 1.0: peak %.3f' % (np.abs(1 + gx).max(), np.round(1 + q[np.abs(q) > 0], 2), max(np.abs(y.real).max(), np.abs(y.imag).max())))
