"""float32 accuracy of diffsense.detection.pd against the mpmath reference.

Run from the repository root: PYTHONPATH=. python benchmarks/float32_accuracy.py
"""
import os; os.environ["DIFFSENSE_X64"]="0"
import numpy as np, jax.numpy as jnp
import diffsense.detection as det
import mpmath as mp
from tests.reference import mp_detection as ref
worst=0
for sw in [0,1,2,3,4]:
  for n in [1,10,100]:
    for pfa in [1e-3,1e-6,1e-10]:
      x=np.linspace(-5,25,7).astype(np.float32)
      got=np.asarray(det.pd(jnp.asarray(x,dtype=jnp.float32), jnp.float32(pfa), jnp.float32(n), sw))
      want=np.array([float(ref.pd_mp(mp.mpf(10)**(mp.mpf(float(s))/10), pfa, n, sw, dps=30)) for s in x])
      e=np.max(np.abs(got-want)); worst=max(worst,e)
      if e>1e-5: print(sw,n,pfa,e,x[np.argmax(np.abs(got-want))])
      if not np.all(np.isfinite(got)): print('nonfinite',sw,n,pfa)
print('float32 worst |dPd|', worst, got.dtype)
