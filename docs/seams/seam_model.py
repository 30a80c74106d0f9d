import numpy as np
lam=633e-9; p=3.7202e-6; z=0.026883; L=3072
u=np.arange(L); d=(u+0.5-L/2)*p
r=np.sqrt(d*d+z*z)
phase=-2*np.pi/lam*(d*d/(r+z))
a=np.exp(1j*phase)
def seen(amp, eye_sin_lo, eye_sin_hi, M=4):
    # upsample by M (band-limited), propagate z to focus with angular spectrum, window one pitch (64 samples) at centre
    N=L*M*2
    f=np.zeros(N,complex)
    up=np.fft.ifft(np.fft.fft(amp*a), n=L)  # identity
    # sinc-interp: zero-pad spectrum
    A=np.fft.fft(amp*a); A2=np.zeros(L*M,complex); A2[:L//2]=A[:L//2]; A2[-L//2:]=A[-L//2:]
    fine=np.fft.ifft(A2)*M
    f[:L*M]=fine
    fx=np.fft.fftfreq(N, p/M)
    kz=np.sqrt(np.maximum(0,(1/lam)**2-fx**2))
    F=np.fft.fft(f)*np.exp(2j*np.pi*kz*z)
    g=np.fft.ifft(F)
    centre=L*M//2
    w=g[centre-32*M:centre+32*M]
    S=np.fft.fftshift(np.fft.fft(w, n=len(w)*8))
    fs=np.fft.fftshift(np.fft.fftfreq(len(w)*8, p/M))
    sin=fs*lam
    sel=(sin>=eye_sin_lo)&(sin<eye_sin_hi)
    return np.sum(np.abs(S[sel])**2)
# pupil 4mm at 573 mm: sin interval width ~ 0.007 centred at s0
full=np.ones(L)
for gap_at in [1500, 1520, 1540, 1560]:
    amp=full.copy(); amp[gap_at:gap_at+16]=0
    # direction of sample gap: sin = -d/r at gap centre
    dg=(gap_at+8+0.5-L/2)*p; sg=-dg/np.sqrt(dg*dg+z*z)
    res=[]
    for off in np.linspace(-0.006,0.006,7):
        s0=sg+off
        res.append(seen(amp,s0-0.0035,s0+0.0035)/seen(full,s0-0.0035,s0+0.0035))
    print(gap_at, ' '.join('%.3f'%x for x in res))

def profile(gap_at, gains):
    # gains: dict segment index -> gain (segments of 32 samples)
    amp=np.ones(L)
    for s,g in gains.items():
        amp[s*32:(s+1)*32]*=g
    amp[gap_at:gap_at+16]=0
    return amp
def curve(amp, sg):
    out=[]
    for off in np.linspace(-0.008,0.008,17):
        s0=sg+off
        out.append(seen(amp,s0-0.0035,s0+0.0035)/seen(full,s0-0.0035,s0+0.0035))
    return np.array(out)
import itertools
for gap_at in [1536+0, 1536+8, 1536+16]:
    dg=(gap_at+8+0.5-L/2)*p; sg=-dg/np.sqrt(dg*dg+z*z)
    seg=gap_at//32
    best=None
    cut=[seg] if (gap_at+16-1)//32==seg else [seg, seg+1]
    # search: gain for cut segments c, for neighbours n1 (one each side)
    for c in np.arange(1.0,2.6,0.1):
        for n in np.arange(1.0,1.8,0.05):
            gains={s:c for s in cut}
            gains[cut[0]-1]=n; gains[cut[-1]+1]=n
            cv=curve(profile(gap_at,gains),sg)
            score=np.max(np.abs(cv-1))
            if best is None or score<best[0]: best=(score,c,n,cv.min(),cv.max())
    print(gap_at, 'cut',cut,'best max dev %.3f c=%.2f n=%.2f min %.3f max %.3f'%best)
