"""Write a gain table found by table.py as the Rust source of the `mark3` layout's blanking gains:

    python3 to_rust.py table_K32.npy > ../../src/layout/mark3_blanking.rs
"""
import sys
import numpy as np

gx = np.load(sys.argv[1])
Z = 3
K = len(gx) // (2 * Z)
g = 1 + gx.reshape(Z, 2 * K)
print('//! The `mark3` layout\'s blanking gains (spec/layouts.md §5.5), written by')
print('//! `docs/seams/to_rust.py` from the table `docs/seams/table.py` found: one')
print('//! complex gain per zone and per shown sample within %d samples of a blanked run,' % K)
print('//! chosen at once for uniform, random and smooth content, pupils of 2–6 mm')
print('//! and viewers at 450–800 mm. Not edited by hand.')
print()
print('/// Shown samples taken on each side of a blanked run.')
print('pub(super) const SAMPLES_EACH_SIDE: usize = %d;' % K)
print()
print('/// Per zone: `[re, im]` for the %d samples before a run, then the %d after it.' % (K, K))
print('#[rustfmt::skip]')
print('pub(super) const GAINS: [[[f64; 2]; %d]; %d] = [' % (2 * K, Z))
for k in range(Z):
    print('    [')
    for i in range(0, 2 * K, 2):
        print('        ' + ' '.join('[%s, %s],' % (repr(float(g[k, j].real)), repr(float(g[k, j].imag))) for j in range(i, min(i + 2, 2 * K))))
    print('    ],')
print('];')
