"""Write the gain tables found by table.py (the flat-field one carried over to the piece taper by carry.py, then
searched again) as the Rust source of the `mark3` layout's blanking gains:

    python3 to_rust.py table_K64_edges.npy flat_p64.npy 0.05 > ../../src/layout/mark3_blanking.rs

(the general table, the flat-field table and the largest spread of radiances that counts as evenly lit).
"""
import sys
import numpy as np

Z = 3

def table(path):
    gx = np.load(path)
    K = len(gx) // (2 * Z)
    return K, 1 + gx.reshape(Z, 2 * K)

def emit(name, g):
    K = g.shape[1] // 2
    print('#[rustfmt::skip]')
    print('pub(super) const %s: [[[f64; 2]; %d]; %d] = [' % (name, 2 * K, Z))
    for k in range(Z):
        print('    [')
        for i in range(0, 2 * K, 2):
            print('        ' + ' '.join('[%s, %s],' % (repr(float(g[k, j].real)), repr(float(g[k, j].imag))) for j in range(i, min(i + 2, 2 * K))))
        print('    ],')
    print('];')

K, g = table(sys.argv[1])
KF, f = table(sys.argv[2])
spread = float(sys.argv[3])
print('//! The `mark3` layout\'s blanking gains (spec/layouts.md §5.5), written by')
print('//! `docs/seams/to_rust.py` from the tables `docs/seams/table.py` found: one')
print('//! complex gain per zone and per shown sample near a blanked run. The general')
print('//! table (%d samples each side) was chosen at once for uniform, random, smooth' % K)
print('//! and edged content, pupils of 2–6 mm and viewers at 450–800 mm; the flat-field')
print('//! table (%d samples each side) for evenly lit content alone, over the same' % KF)
print('//! pupils and viewers, carried over from hard segments to the basis\'s piece')
print('//! taper (`docs/seams/carry.py`) and searched again from there')
print('//! (docs/seams/README.md §8). Not edited by hand.')
print()
print('/// Shown samples the general table takes on each side of a blanked run.')
print('pub(super) const SAMPLES_EACH_SIDE: usize = %d;' % K)
print()
print('/// Per zone: `[re, im]` for the %d samples before a run, then the %d after it.' % (K, K))
emit('GAINS', g)
print()
print('/// The largest spread of radiances, `(max − min) / max`, of the elements near')
print('/// a run that counts as evenly lit.')
print('pub(super) const FLAT_FIELD_MAX_SPREAD: f64 = %r;' % spread)
print()
print('/// Shown samples the flat-field table takes on each side of a blanked run.')
print('pub(super) const FLAT_FIELD_SAMPLES_EACH_SIDE: usize = %d;' % KF)
print()
print('/// Per zone: `[re, im]` for the %d samples before a run, then the %d after it.' % (KF, KF))
emit('FLAT_FIELD_GAINS', f)
