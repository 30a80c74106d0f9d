import numpy as np, sys
from hololine import *
EYES=np.arange(-0.080,0.08001,0.00025)
def evaluate(b, eyes=EYES, quant=True, ideal_cols=None):
    bb=quantize(b) if quant else b
    sp=spectra(emitter_plane(bb))
    cols,lo,hi=seen_many(sp,eyes)
    r=ratio_stats(cols,lo,hi)
    return cols, r
if __name__=='__main__':
    a=uniform_signals(0.5)
    cols0,r0=evaluate(a, quant=False)
    print('no blanking, float: ratio min %.3f max %.3f'%(np.nanmin(r0),np.nanmax(r0)))
    c0q,r0q=evaluate(a)
    print('no blanking, 8-bit: ratio min %.3f max %.3f'%(np.nanmin(r0q),np.nanmax(r0q)))
    b=a.copy(); b[:,BLANKED]=0
    cols,r=evaluate(b, quant=False)
    rel=cols/cols0
    print('blanked float: ratio min %.3f max %.3f; vs unblanked same eye min %.3f max %.3f'%(np.nanmin(r),np.nanmax(r),np.nanmin(np.where(np.isnan(r),np.nan,rel)),np.nanmax(np.where(np.isnan(r),np.nan,rel))))
    cq,rq=evaluate(b)
    print('blanked 8-bit: ratio min %.3f max %.3f'%(np.nanmin(rq),np.nanmax(rq)))
    mins=np.nanmin(rq,1); maxs=np.nanmax(rq,1)
    for x,mn,mx in zip(EYES[::20],mins[::20],maxs[::20]): print('eye %+.1f mm: min %.3f max %.3f'%(x*1e3,mn,mx))
    np.savez('/tmp/raw_scan.npz', eyes=EYES, mins=mins, maxs=maxs)
