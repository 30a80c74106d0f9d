"""The blanking-gain table built into the `mark3` layout: one complex gain per zone signal and per shown sample
within K of a hole (the same beside every hole: the chirps cross every hole at the same phase), chosen at once
for several contents, pupils and distances (each judged relative to the same display unblanked), with the
compensated signal kept inside the 8-bit range for uniform content at full brightness.

    python3 table.py K ITERATIONS [--start START.npy] [--nominal W] [--out NAME.npy] [--edges | --flat]

for the basis hololine.py models (PIECE_TAPER=64 for `mark3`'s, hololine.py says how);

writes NAME.npy (default table_K{K}.npy): the gains minus 1, zone-major, the K samples before a run then the K
after it. W weighs the nominal viewer (uniform content, 4 mm pupil, 600 mm) against each other scenario (1).
--edges adds silhouettes and dark-to-bright random content; --flat keeps uniform content only (every pupil and
distance): the flat-field table.

Held-out checks (other pupils, distances, contents, every hole, 8-bit codes): robust.py-style, in check_table.py.
"""
import numpy as np, sys, time
from opt import *
from multi import Scenario
from scipy.optimize import minimize

PEAK = 0.98          # |I|, |Q| bound for uniform content 1.0 (the quantizer's range is +-1)

class Edge(Scenario):
    """A silhouette: each column judged against its brightness without blanking, but never against less than a
    quarter of the median column (a dark column's ratio says nothing; its light beside a bright one does)."""
    def __init__(self, weights, pos):
        super().__init__(weights, pos=pos)
        self.den = np.maximum(self.ref, 0.25 * np.median(self.ref))

def edge(at, slope, bright=0.9, dark=0.05, flip=False):
    """Content bright on one side of emitter at + slope (v - 48), dark on the other: a lit object's edge, moving
    across views as a silhouette at another depth does."""
    e = np.arange(E)[:, None]; v = np.arange(96)[None, :]
    lit = (e < at + slope * (v - 48)) != flip
    return np.sqrt(np.where(lit, bright, dark))

def scenarios(pos, edges=False):
    rng = np.random.default_rng(7)
    u = np.full(E, np.sqrt(0.5))
    smooth = np.sqrt(0.5 + 0.4 * np.sin(np.arange(E)[:, None] / 7.0 + np.arange(96)[None, :] / 11.0))
    return [('uniform 4 mm 600 mm', Scenario(u, pos=pos)),
            ('uniform 2 mm', Scenario(u, 2e-3, pos=pos)),
            ('uniform 3 mm', Scenario(u, 3e-3, pos=pos)),
            ('uniform 6 mm', Scenario(u, 6e-3, pos=pos)),
            ('uniform 4 mm at 450 mm', Scenario(u, dist=0.45, pos=pos)),
            ('uniform 4 mm at 800 mm', Scenario(u, dist=0.8, pos=pos)),
            ('random A', Scenario(np.sqrt(rng.uniform(0.2, 1, (E, 96))), pos=pos)),
            ('random B', Scenario(np.sqrt(rng.uniform(0.2, 1, (E, 96))), pos=pos)),
            ('smooth', Scenario(smooth, pos=pos))] + ([
            ('edge at 100', Edge(edge(100, 0.0), pos)),
            ('edge at 110, moving', Edge(edge(110, 0.15, flip=True), pos)),
            ('edge at 118, dim', Edge(edge(118, -0.1, bright=0.5, dark=0.15), pos)),
            ('band 92-104', Edge(np.sqrt(np.where((np.arange(E)[:, None] >= 92) & (np.arange(E)[:, None] < 104) & (np.arange(96)[None, :] >= 0), 0.9, 0.1)), pos)),
            ('random 0-1', Edge(np.sqrt(np.random.default_rng(3).uniform(0, 1, (E, 96))), pos))] if edges else [])

if __name__ == '__main__':
    import argparse
    ap = argparse.ArgumentParser()
    ap.add_argument('K', type=int); ap.add_argument('iters', type=int)
    ap.add_argument('--start'); ap.add_argument('--nominal', type=float, default=1.0); ap.add_argument('--out')
    ap.add_argument('--flat', action='store_true', help='uniform content only (every pupil and distance)')
    ap.add_argument('--edges', action='store_true', help='also silhouettes, a band and dark-to-bright random content')
    args = ap.parse_args()
    K, iters = args.K, args.iters
    pos = np.concatenate([np.arange(HOLE - K, HOLE), np.arange(HOLE + 16, HOLE + 16 + K)])
    t = time.time()
    A = response(pos); AH = A.conj().T
    scen = scenarios(pos, args.edges)
    if args.flat: scen = scen[:6]
    for _, sc in scen:
        # R = 1 + (power - power unblanked) / den: den is the power unblanked but for Edge's dark columns
        sc.den = getattr(sc, 'den', sc.ref)
    full = np.concatenate([uniform_signals(1.0)[k, pos] for k in range(Z)])
    print('set up %.0f s' % (time.time() - t)); sys.stdout.flush()
    n = A.shape[1]; p = 8
    # Scenarios of the same content (pupils, distances) share their spectra: one product with A, and one with its
    # adjoint, per content and iteration.
    groups = []
    for i, (_, s) in enumerate(scen):
        for g in groups:
            if np.array_equal(g[0].ideal, s.ideal) and np.array_equal(g[0].S0, s.S0):
                g[1].append((i, s)); break
        else:
            groups.append((s, [(i, s)]))
    print('%d scenarios, %d contents' % (len(scen), len(groups))); sys.stdout.flush()
    def f(x):
        gx = x[:n] + 1j * x[n:]
        Ltot = 0; G = np.zeros(n, complex)
        for first, members in groups:
            c = first.ideal * gx
            S = first.S0 + A @ c
            back = 0
            for i, s in members:
                wt = args.nominal if i == 0 else 1.0
                R = 1 + (s.W @ np.abs(S) ** 2 - s.ref) / s.den
                d = R - 1; ss = np.sum(d ** p); L = wt * ss ** (1 / p)
                dR = wt * ss ** (1 / p - 1) * d ** (p - 1)
                back = back + s.W.T @ (dR / s.den)
                Ltot += L
            gc = AH @ (back * S)
            G += first.ideal.conj() * gc
        # keep I and Q of uniform content 1.0 inside +-PEAK: quadratic penalty beyond it
        y = full * (1 + gx)
        over_r = np.maximum(np.abs(y.real) - PEAK, 0) * np.sign(y.real)
        over_i = np.maximum(np.abs(y.imag) - PEAK, 0) * np.sign(y.imag)
        Ltot += 100 * np.sum(over_r ** 2 + over_i ** 2)
        gy = 200 * (over_r + 1j * over_i)          # dL/d(conj y), times 2
        G += full.conj() * gy / 2
        return Ltot, np.concatenate([2 * G.real, 2 * G.imag])
    x0 = np.zeros(2 * n)
    if args.start:
        g0 = np.load(args.start); x0 = np.concatenate([g0.real, g0.imag])
    t = time.time()
    out = args.out or 'table_K%d.npy' % K
    seen = [0]
    def checkpoint(x):
        # every 25 iterations the table so far, so that a search stopped early keeps its progress
        seen[0] += 1
        if seen[0] % 25 == 0:
            np.save(out, x[:n] + 1j * x[n:])
            print('  %d iterations, %.0f s' % (seen[0], time.time() - t)); sys.stdout.flush()
    r = minimize(f, x0, jac=True, method='L-BFGS-B', options={'maxiter': iters}, callback=checkpoint)
    gx = r.x[:n] + 1j * r.x[n:]
    np.save(out, gx)
    print('K=%d table, nominal weight %g, %d iterations, %.0f s, objective %.4f' % (K, args.nominal, r.nit, time.time() - t, r.fun))
    for name, s in scen:
        R = 1 + (s.W @ np.abs(s.S0 + A @ (s.ideal * gx)) ** 2 - s.ref) / s.den
        R0 = 1 + (s.W @ np.abs(s.S0) ** 2 - s.ref) / s.den
        print('  %-24s raw %.3f..%.3f  compensated %.3f..%.3f' % (name, R0.min(), R0.max(), R.min(), R.max()))
    y = full * (1 + gx)
    print('  gain |1+x| max %.2f; uniform 1.0: peak |I|,|Q| %.3f' % (np.abs(1 + gx).max(), max(np.abs(y.real).max(), np.abs(y.imag).max())))
