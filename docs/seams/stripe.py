"""The ghost stripe (docs/seams/README.md §8): a block of emitters lit in every view, the rest dark; over eyes across
the block's viewing zone (from every one the whole block is in view) at 450, 600 and 800 mm, the brightest dark
column (4 or more emitters from every lit one) over the lit columns' median, calibrated as `holo view` shows it; and
the same light over what a fully lit emitter sends into a pupil in the middle of the fan (absolute).

    PIECE_TAPER=64 python3 stripe.py [--codes]

for the basis hololine.py models; --codes rounds the signals to 8-bit codes first.
"""
import sys
import numpy as np
import hololine as H


def zone(lit_lo, lit_hi, dist, count):
    """Eyes at `dist` from which emitters lit_lo … lit_hi − 1 are all in view (views 0 and 95 reach past them)."""
    tan = [np.tan(np.arcsin(H.sin_theta(H.offset_samples(2, 1023.5 - 16)))), np.tan(np.arcsin(H.sin_theta(H.offset_samples(0, 15.5))))]
    reach = lambda e, t: H.emitter_x(e) + (dist - H.ZE) * t
    left = max(reach(lit_lo, tan[0]), reach(lit_hi - 1, tan[0]))
    right = min(reach(lit_lo, tan[1]), reach(lit_hi - 1, tan[1]))
    return np.linspace(left, right, count)


def stripe(lit_lo, lit_hi, dist, codes=False, level=0.5, count=39):
    w = np.zeros((H.E, 96))
    w[lit_lo:lit_hi, :] = np.sqrt(level)
    a = H.signals(w)
    spec = H.spectra(H.emitter_plane(H.quantize(a) if codes else a))
    cal = H.calibration()
    typical = H.between(cal, -0.0035, 0.0035)
    dark = np.ones(H.E, bool)
    dark[max(lit_lo - 4, 0):lit_hi + 4] = False
    eyes = zone(lit_lo, lit_hi, dist, count)
    cols, lo, hi = H.seen_many(spec, eyes, dist=dist)
    worst = (0.0, None, None, None)
    for k, x in enumerate(eyes):
        scene = np.median(cols[k, lit_lo:lit_hi])
        c = np.where(dark, cols[k], 0)
        e = int(np.argmax(c))
        if c[e] / scene > worst[0]:
            worst = (c[e] / scene, x, e, H.between(spec[e], lo[k, e], hi[k, e]) / typical / level)
    return worst


if __name__ == '__main__':
    codes = '--codes' in sys.argv
    print('basis: segment taper %d, piece taper %d (%s)%s' % (H.SEGMENT_TAPER, H.PIECE_TAPER, H.PIECE_ENDS, ', 8-bit codes' if codes else ''))
    for lo, hi in [(150, 300), (20, 170), (100, 236)]:
        for dist in [0.45, 0.6, 0.8]:
            r, x, e, ab = stripe(lo, hi, dist, codes)
            print('  lit %d-%d at %.0f mm: stripe %.3f %% (eye %+.1f mm, emitter %d); absolute %.1e' % (lo, hi, dist * 1e3, 100 * r, x * 1e3, e, ab))
        sys.stdout.flush()
