"""Power-level search for blanking compensation: corrections on the shown samples within K of
each hole (the same at every hole: uniform content gives every hole the same surroundings),
judged by what every eye sees of every emitter near the hole (pupil power / unblanked pupil power)."""
import numpy as np, sys, time
import scipy.sparse as sps
from scipy.optimize import minimize
from hololine import *
from lsq import HOLE, EMS, field_zone, apply

SIN_BINS = SIN_FIRST + SIN_STEP * np.arange(FFTLEN)
BINS = np.where(np.abs(SIN_BINS) < 0.215)[0]
NB = len(BINS)
# eyes that see hole 1 (x = -15 mm) through all its windows at every direction of the fan
EYES = np.arange(-0.145, 0.12001, 0.0002)

def cspec(g):
    idx = FIRST[EMS][:, None] + np.arange(WIN)[None, :]
    F = np.fft.fftshift(np.fft.fft(g[idx], n=FFTLEN, axis=1), axes=1)
    return F[:, BINS].ravel()

def cell_matrix(eyes=EYES, pupil=PUPIL):
    lo, hi = pupil_interval(EMS[None, :], np.asarray(eyes)[:, None], pupil)
    ok = ((lo > -0.2) & (hi < 0.2)).ravel()
    lo, hi = lo.ravel()[ok], hi.ravel()[ok]
    erow = np.broadcast_to(np.arange(len(EMS))[None, :], (len(eyes), len(EMS))).ravel()[ok]
    # bin u covers [u, u+1) in units where sin = SIN_FIRST + (u - 0.5 + BINS0...) : use global bin index then shift
    ulo = (lo - SIN_FIRST) / SIN_STEP + 0.5 - BINS[0]
    uhi = (hi - SIN_FIRST) / SIN_STEP + 0.5 - BINS[0]
    rows, cols, vals = [], [], []
    k0 = np.floor(ulo).astype(int); k1 = np.ceil(uhi).astype(int)
    span = (k1 - k0).max()
    for j in range(span):
        k = k0 + j
        w = np.clip(np.minimum(uhi, k + 1) - np.maximum(ulo, k), 0, None)
        m = (w > 0) & (k >= 0) & (k < NB)
        rows.append(np.nonzero(m)[0]); cols.append(erow[m] * NB + k[m]); vals.append(w[m])
    W = sps.csr_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))), shape=(len(lo), len(EMS) * NB))
    return W, ok, lo, hi

def response(pos):
    cols = []
    for k in range(Z):
        for n in pos:
            v = np.zeros(N, complex); v[n] = 1.0
            cols.append(cspec(propagate(field_zone(k, v))))
    return np.array(cols).T

class Problem:
    def __init__(self, K, eyes=EYES, inner=0):
        self.a = uniform_signals(0.5)
        b = self.a.copy(); b[:, BLANKED] = 0
        self.b = b
        self.pos = np.concatenate([np.arange(HOLE - K, HOLE), np.arange(HOLE + 16, HOLE + 16 + K)])
        self.S0 = cspec(emitter_plane(b))
        Su = cspec(emitter_plane(self.a))
        self.W, self.ok, self.lo, self.hi = cell_matrix(eyes)
        self.ref = self.W @ np.abs(Su) ** 2
        t = time.time()
        self.A = response(self.pos)
        self.ideal = np.concatenate([self.a[k, self.pos] for k in range(Z)])
        print('problem K=%d: %d cells, A %s, %.1f s' % (K, len(self.ref), self.A.shape, time.time() - t)); sys.stdout.flush()

    def R(self, c):
        S = self.S0 + self.A @ c
        return self.W @ (np.abs(S) ** 2) / self.ref, S

    def grad_c(self, S, dR):
        """dL/dc* (complex) given dL/dR."""
        g = self.W.T @ (dR / self.ref)
        return self.A.conj().T @ (g * S)

# parametrisations: x (real vector) -> c (complex, Z*len(pos)), and the chain rule back
def free_complex(P):
    n = P.A.shape[1]
    to_c = lambda x: x[:n] + 1j * x[n:]
    back = lambda gc: np.concatenate([2 * gc.real, 2 * gc.imag])
    return 2 * n, to_c, back

def taper_real(P, symmetric=False):
    """Per-sample real gain g = 1 + x on the ideal signal (all zones the same): a taper."""
    K = len(P.pos) // 2
    ide = P.ideal.reshape(Z, 2 * K)
    def expand(x):
        return np.concatenate([x[::-1], x]) if symmetric else x
    def to_c(x):
        return (ide * expand(x)[None, :]).ravel()
    def back(gc):
        g = 2 * (ide.conj() * gc.reshape(Z, 2 * K)).real.sum(0)
        return g[:K][::-1] + g[K:] if symmetric else g
    return (K if symmetric else 2 * K), to_c, back

def gain_complex(P):
    """Per-sample complex gain on the ideal signal, per zone."""
    n = P.A.shape[1]
    ide = P.ideal
    to_c = lambda x: ide * (x[:n] + 1j * x[n:])
    back = lambda gc: np.concatenate([2 * (ide.conj() * gc).real, 2 * (ide.conj() * gc).imag])
    return 2 * n, to_c, back

def solve(P, param, floor=None, cap=None, p=8, x0=None, iters=400, l2=0.0):
    """Minimise a smooth version of max|R-1| (floor/cap None), or, given a cap,
    push the minimum up: sum relu(floor-R)^2 + w sum relu(R-cap)^2."""
    nx, to_c, back = param
    def f(x):
        c = to_c(x)
        R, S = P.R(c)
        if floor is None:
            d = R - 1
            s = np.sum(d ** p)
            L = s ** (1 / p)
            dR = (s ** (1 / p - 1)) * d ** (p - 1)
        else:
            lo = np.maximum(floor - R, 0); hi = np.maximum(R - cap, 0)
            L = np.sum(lo ** 2) + 10 * np.sum(hi ** 2)
            dR = -2 * lo + 20 * hi
        L += l2 * np.sum(np.abs(c) ** 2)
        gc = P.grad_c(S, dR) + l2 * c
        return L, back(gc)
    x0 = np.zeros(nx) if x0 is None else x0
    r = minimize(f, x0, jac=True, method='L-BFGS-B', options={'maxiter': iters})
    c = to_c(r.x)
    R, _ = P.R(c)
    return r.x, c, R

def report(name, P, c):
    R, _ = P.R(c)
    amp = np.abs(c.reshape(Z, -1) + P.ideal.reshape(Z, -1))
    print('%-28s R min %.3f max %.3f | peak |a+c| %.2f (ideal max %.2f) | rms c %.3f'
          % (name, R.min(), R.max(), amp.max(), np.abs(P.ideal).max(), np.sqrt(np.mean(np.abs(c) ** 2))))
    sys.stdout.flush()
    return R.min(), R.max()

if __name__ == '__main__':
    K = int(sys.argv[1]) if len(sys.argv) > 1 else 16
    P = Problem(K)
    report('raw', P, np.zeros(P.A.shape[1], complex))
    for name, param in [('taper sym', taper_real(P, True)), ('taper', taper_real(P)),
                        ('complex gain', gain_complex(P)), ('free complex', free_complex(P))]:
        x, c, R = solve(P, param)
        report(name + ' K=%d' % K, P, c)
        np.save('/tmp/opt_%s_K%d.npy' % (name.replace(' ', '_'), K), c)
