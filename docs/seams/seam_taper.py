import numpy as np
exec(open('seam_model.py').read().split("# pupil 4mm")[0])
full=np.ones(L)
def curve(amp, sg, n=17, span=0.008):
    out=[]
    for off in np.linspace(-span,span,n):
        s0=sg+off
        out.append(seen(amp,s0-0.0035,s0+0.0035)/seen(full,s0-0.0035,s0+0.0035))
    return np.array(out)
gap_at=1540
dg=(gap_at+8+0.5-L/2)*p; sg=-dg/np.sqrt(dg*dg+z*z)
best=None
for K in [8,12,16,20,24,32]:
    for A in np.arange(0.2,2.01,0.1):
        for shape in ['flat','lin']:
            amp=np.ones(L); amp[gap_at:gap_at+16]=0
            for k in range(K):
                h = A if shape=='flat' else A*(1-k/K)
                amp[gap_at-1-k]*=1+h; amp[gap_at+16+k]*=1+h
            cv=curve(amp,sg,9)
            sc=np.max(np.abs(cv-1))
            if best is None or sc<best[0]: best=(sc,K,A,shape,cv.min(),cv.max())
print('best', best)
