import numpy as np, sys
from opt import *
K = int(sys.argv[1]); Kw = int(sys.argv[2]) if len(sys.argv) > 2 else 0
iters = int(sys.argv[3]) if len(sys.argv) > 3 else 800
P = Problem(K)
for name, param in [('complex gain', gain_complex(P)), ('free complex', free_complex(P))]:
    x0 = None
    if Kw:
        cw = np.load('/tmp/opt_%s_K%d.npy' % (name.replace(' ', '_'), Kw)).reshape(Z, 2 * Kw)
        c0 = np.zeros((Z, 2 * K), complex); c0[:, K - Kw:K + Kw] = cw
        c0 = c0.ravel()
        if name == 'complex gain':
            g = c0 / P.ideal
            x0 = np.concatenate([g.real, g.imag])
        else:
            x0 = np.concatenate([c0.real, c0.imag])
    x, c, R = solve(P, param, x0=x0, iters=iters)
    report(name + ' K=%d' % K, P, c)
    np.save('/tmp/opt_%s_K%d.npy' % (name.replace(' ', '_'), K), c)
