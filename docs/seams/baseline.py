import numpy as np
from hololine import *
from scan import *
a=uniform_signals(0.5)
for q in [False,True]:
    cols,r=evaluate(a,quant=q)
    es=np.arange(E)
    lo,hi=pupil_interval(es[None,:],EYES[:,None])
    s=(lo+hi)/2
    bad=np.where((r<0.97)|(r>1.03))
    print('quant',q,'n bad',len(bad[0]))
    hist=np.histogram(s[bad],bins=np.linspace(-0.21,0.21,22))
    print(hist[0]); 
    i=np.nanargmin(r); print('min at eye',EYES[i//E],'e',i%E,'sin',s.flat[i], r.flat[i]); i=np.nanargmax(r); print('max at',EYES[i//E],i%E,s.flat[i],r.flat[i])
    print('cols range (valid)', np.nanmin(np.where(np.isnan(r),np.nan,cols)), np.nanmax(np.where(np.isnan(r),np.nan,cols)))
