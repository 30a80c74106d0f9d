"""Carry blanking-gain tables found for hard segments over to the basis with `mark3`'s piece taper
(spec/layouts.md §4.2): per zone and per sample beside a run, the gain times the ratio of the evenly lit signal there
with hard segments to the same signal with the piece taper, so that for evenly lit content every run's neighbours
are sent exactly as before (the holes are alike: the ratio is the same beside every run). For other content it is
the nearest such table, not a search: `table.py` refines it (docs/seams/README.md §8).

    git show 88c6848:src/layout/mark3_blanking.rs > hard.rs        # the tables found for hard segments
    python3 from_rust.py hard.rs table_K64_edges.npy flat_K128.npy
    python3 carry.py 64 flat_K128.npy flat_p64_start.npy
"""
import sys
import numpy as np
import hololine as H
from lsq import HOLE

taper = int(sys.argv[1])
hard = H.uniform_signals(0.5)
H.PIECE_TAPER = taper
H.TAPERED = H._tapered_templates()
H._CAL = None
tapered = H.uniform_signals(0.5)
g = 1 + np.load(sys.argv[2]).reshape(H.Z, -1)
K = g.shape[1] // 2
pos = np.concatenate([np.arange(HOLE - K, HOLE), np.arange(HOLE + 16, HOLE + 16 + K)])
ratio = np.array([hard[k, pos] / tapered[k, pos] for k in range(H.Z)])
for h in H.HOLES[:5]:                        # the sixth run ends the hololine, past every chirp
    p = pos - HOLE + h
    ok = (p >= 0) & (p < H.N)
    assert all(np.allclose(hard[k, p[ok]] / tapered[k, p[ok]], ratio[k, ok]) for k in range(H.Z)), h
carried = g * ratio
np.save(sys.argv[3], (carried - 1).ravel())
print('K = %d: ratio |r| %.3f..%.3f; gains |g| up to %.2f (were %.2f)' % (K, np.abs(ratio).min(), np.abs(ratio).max(), np.abs(carried).max(), np.abs(g).max()))
