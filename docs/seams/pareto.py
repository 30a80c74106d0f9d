"""Pareto: the darkest column (min R over all eyes and emitters) for a cap on the brightest."""
import numpy as np, sys
from opt import *

def solve_cap(P, param, cap, x0=None, iters=600, p=8):
    nx, to_c, back = param
    def f(x):
        c = to_c(x)
        R, S = P.R(c)
        d = np.maximum(1 - R, 0) + 1e-12
        s = np.sum(d ** p)
        L = s ** (1 / p)
        dR = -(s ** (1 / p - 1)) * d ** (p - 1)
        if cap is not None:
            h = np.maximum(R - cap, 0)
            L += 200 * np.sum(h ** 2)
            dR += 400 * h
        return L, back(P.grad_c(S, dR))
    from scipy.optimize import minimize
    x0 = np.zeros(nx) if x0 is None else x0
    r = minimize(f, x0, jac=True, method='L-BFGS-B', options={'maxiter': iters})
    c = to_c(r.x); R, _ = P.R(c)
    return r.x, c, R

if __name__ == '__main__':
    K = int(sys.argv[1]); kinds = sys.argv[2].split(','); ITERS = int(sys.argv[3])
    P = Problem(K)
    for kind in kinds:
        param = {'taper': taper_real(P), 'gain': gain_complex(P), 'free': free_complex(P)}[kind]
        x = None
        for cap in [1.5, 1.25, 1.1, 1.05, None]:
            # warm start from the symmetric minimax solution for the tight caps
            x, c, R = solve_cap(P, param, cap, x0=x if cap is not None else None, iters=ITERS)
            amp = np.abs(c.reshape(Z, -1) + P.ideal.reshape(Z, -1)).max()
            print('K=%d %-6s cap %-5s min %.3f max %.3f peak |a+c| %.2f' % (K, kind, cap, R.min(), R.max(), amp))
            sys.stdout.flush()
            np.save('/tmp/pareto_%s_K%d_%s.npy' % (kind, K, cap), c)
