import sys, numpy as np
from opt import *
K = int(sys.argv[1]); kinds = sys.argv[2].split(','); iters = int(sys.argv[3]) if len(sys.argv) > 3 else 500
P = Problem(K)
report('raw', P, np.zeros(P.A.shape[1], complex))
for kind in kinds:
    param = {'taper': taper_real(P), 'tapersym': taper_real(P, True), 'gain': gain_complex(P), 'free': free_complex(P)}[kind]
    x, c, R = solve(P, param, iters=iters)
    report('%s K=%d' % (kind, K), P, c)
    np.save('/tmp/mm_%s_K%d.npy' % (kind, K), c)
