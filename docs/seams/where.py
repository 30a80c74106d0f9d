"""Where (relative to the hole) the dark and bright columns are: R(e, s) = seen / seen-unblanked,
indexed by the emitter offset from the emitter whose chirp crosses the hole in direction s."""
import numpy as np
from hololine import *
from taper import taper_gain
EYES=np.arange(-0.080,0.08001,0.0001)
def hole_sin(e, j):
    xh=(4096*j+4088-N/2)*P; d=xh-emitter_x(e); return -d/np.sqrt(d*d+ZE*ZE)
def Rmap(b, ref_cols=None):
    sp=spectra(emitter_plane(b)); cols,lo,hi=seen_many(sp,EYES); return cols,lo,hi
if __name__=='__main__':
  a=uniform_signals(0.5)
  c0,lo,hi=Rmap(a)
  s=(lo+hi)/2
  ok=(lo>-0.2)&(hi<0.2)
  cases={'raw':np.ones(N),'taper K5 A2.8':taper_gain(5,2.8),'taper K16 A2.5':taper_gain(16,2.5),'taper K32 A1.5':taper_gain(32,1.5)}
  es=np.arange(E)
  for name,g in cases.items():
      b=a*g; b[:,BLANKED]=0
      c,_,_=Rmap(b)
      R=np.where(ok,c/c0,np.nan)
      print(name,'R min %.3f max %.3f'%(np.nanmin(R),np.nanmax(R)))
      # for hole j=2 (emitters near 64*2=128..): offset from the dark emitter
      for j in [1,2,3]:
          # fractional dark emitter for each eye: solve hole_sin(e,j)=s for each e approx: use emitter where |hole_sin-s| minimal
          hs=hole_sin(es,j)[None,:]
          # the dark emitter per eye: index where hs - s changes sign
          diff=hs-s  # increases with e? 
          out=[]
          for dE in range(-6,7):
              vals=[]
              for i in range(len(EYES)):
                  k=np.argmin(np.abs(diff[i]))
                  if 0<=k+dE<E and ok[i,k+dE]: vals.append(R[i,k+dE])
              if vals: out.append('%+d:%.2f-%.2f'%(dE,min(vals),max(vals)))
          print('  hole',j,' '.join(out))
