"""Physical constants (SI).

Exact SI / CODATA 2018 values. The textbook (Brooker) rounds k = 1.38e-23 J/K and
c = 3e8 m/s; tests that reproduce its worked examples state when that rounding matters.
The nominal sound speeds are round reference values, named as such (use the sound-speed models
of :mod:`diffsense.physics.propagation.acoustic` for a given medium).
"""

SPEED_OF_LIGHT_M_S = 299_792_458.0
BOLTZMANN_J_K = 1.380649e-23
PLANCK_J_S = 6.62607015e-34
ELEMENTARY_CHARGE_C = 1.602176634e-19
STEFAN_BOLTZMANN_W_M2_K4 = 5.670374419e-8
REFERENCE_TEMPERATURE_K = 290.0  # IEEE standard noise temperature T0
NOMINAL_SEA_SOUND_SPEED_M_S = 1500.0  # round value of sonar texts (book §12.8 uses 1522 m/s at 5 °C)
NOMINAL_AIR_SOUND_SPEED_M_S = 340.0  # the book's value for air (§8.16.2, §13.20)
