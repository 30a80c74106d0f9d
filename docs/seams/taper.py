import numpy as np
from hololine import *
def taper_gain(K=5, A=2.8, lin=False):
    dist=np.full(N, 10**9)
    blk=np.where(BLANKED)[0]
    # distance to nearest blanked sample
    for h in HOLES:
        for side,edge in [(-1,h),(1,h+15)]:
            for k in range(1,K+1):
                n=edge+side*k
                if 0<=n<N and not BLANKED[n]: dist[n]=min(dist[n],k)
    t=(dist-1)/K
    g=np.where(dist<=K, 1+A*(1-t) if lin else 1+A*0.5*(1+np.cos(np.pi*t)), 1.0)
    return g
if __name__=='__main__':
    a=uniform_signals(0.5)
    for K,A in [(5,2.8),(8,1.8),(16,1.5),(32,1.5),(16,2.5)]:
        g=taper_gain(K,A)
        b=a*g; b[:,BLANKED]=0
        clipped=np.sum(np.abs(b.real)>255.5/127-128/127)+np.sum(b.real< -128.5/127)+np.sum(np.abs(b.imag)>127.5/127)
        peak=np.abs(np.concatenate([b.real.ravel(),b.imag.ravel()])).max()
        for quant in [False,True]:
            bb=quantize(b) if quant else b
            sp=spectra(emitter_plane(bb))
            cols=seen(sp,[-0.04,0,0.04]); r=darkest(cols)
            print(K,A,'quant',quant,'peak |I|,|Q| %.2f'%peak,'min',np.nanmin(r,1).round(3),'max',np.nanmax(r,1).round(2), 'argmax', np.nanargmax(r,1))
