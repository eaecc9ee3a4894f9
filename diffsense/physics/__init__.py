"""Physical relations, pure formulas shared by every sensor: constants, antennas, targets,
clutter, noise, radiance (blackbody), sea_noise, waveforms, tracking and propagation
(:mod:`.propagation`).

Each function is a pure JAX function of arrays (jit/vmap/grad-able) with its formula, units,
domain and source in its docstring; none knows which sensor calls it.
"""
