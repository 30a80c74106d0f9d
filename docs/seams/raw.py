import numpy as np, time
from hololine import *
t=time.time()
print('p',P,'ze',ZE,'G',G,'M',M,'WIN',WIN,'FFTLEN',FFTLEN,'PLEN',PLEN)
a=uniform_signals(0.5)
print('signals', time.time()-t, 'max |a|', np.abs(a).max(), 'max |I|,|Q|', np.abs(a.real).max(), np.abs(a.imag).max())
eyes=[-0.04,0.0,0.04]
for quant in [False, True]:
    for blank in [False, True]:
        b=a.copy()
        if blank: b[:,BLANKED]=0
        if quant: b=quantize(b)
        sp=spectra(emitter_plane(b))
        cols=seen(sp, eyes)
        r=darkest(cols)
        print('quant',quant,'blank',blank, 'min per eye', np.nanmin(r,axis=1).round(3), 'at', np.nanargmin(r,axis=1), 'max', np.nanmax(r,axis=1).round(3), 'mean col', cols[:,6:-6].mean(1).round(3))
print(time.time()-t)
