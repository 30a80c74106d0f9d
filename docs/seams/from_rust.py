"""The `mark3` layout's blanking-gain tables back from their Rust source, as `table.py` writes them (the gains minus
1, zone-major, the K samples before a run then the K after it): the inverse of `to_rust.py`, to check or warm-start
from the built-in tables without searching again.

    python3 from_rust.py ../../src/layout/mark3_blanking.rs table_K64_edges.npy flat.npy
"""
import re
import sys
import numpy as np


def tables(source):
    out = {}
    for name, body in re.findall(r'const (\w+): \[\[\[f64; 2\]; \d+\]; \d+\] = \[(.*?)\n\];', source, re.S):
        zones = re.findall(r'\[\n(.*?)\n    \]', body, re.S)
        g = [[complex(float(a), float(b)) for a, b in re.findall(r'\[([-0-9.e]+), ([-0-9.e]+)\]', z)] for z in zones]
        out[name] = np.array(g)
    return out


if __name__ == '__main__':
    t = tables(open(sys.argv[1]).read())
    np.save(sys.argv[2], (t['GAINS'] - 1).ravel())
    np.save(sys.argv[3], (t['FLAT_FIELD_GAINS'] - 1).ravel())
    for name, g in t.items():
        print(name, g.shape, 'max |g| %.2f' % np.abs(g).max())
