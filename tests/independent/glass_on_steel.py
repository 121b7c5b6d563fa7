#!/usr/bin/env python3
# Run: python3 tests/independent/glass_on_steel.py (needs mpmath). The values it
# prints are asserted in tests/cli_terms.rs; this script does not call dembound.
# Independent check of the glass-on-steel answers (not using dembound).
# Hertz: F = k d^(3/2), k = (4/3) E* sqrt(R*), 1/E* = (1-nu_m^2)/E_m + (1-nu_b^2)/E_b
# (eqs 5-8 with the general Poisson mixing), R* = R_m R_b/(R_m + R_b), m* = m (fixed boundary).
from mpmath import mp, mpf, sqrt, pi, quad, findroot, inf
mp.dps = 30
R, E, nu, rho = mpf('1e-3'), mpf('63e9'), mpf('0.22'), mpf(2500)
nub, g, H, T = mpf('0.3'), mpf('9.81'), mpf('0.1'), mpf('0.005')
m = 4 * pi * rho * R**3 / 3
v = sqrt(2 * g * H)

def estar(Eb):
    return 1 / ((1 - nu**2) / E + (0 if Eb == inf else (1 - nub**2) / Eb))

def rstar(Rb):
    return R if Rb == inf else R * Rb / (R + Rb)

# Gravity-free closed form: T_c = C (m^2 / (E*^2 R* v))^(1/5), C constant, so
# only ratios matter.
# (a) flat wall vs rigid: (E*_inf/E*)^(2/5) = 1 + T
Eb_a = (1 - nub**2) * E / ((1 - nu**2) * ((1 + T)**mpf(2.5) - 1))
# (b) steel sphere vs flat steel: (R/R*)^(1/5) = 1 + T -> R*/R = (1+T)^-5
rb = (1 + T)**-5
Rb_b = R * rb / (1 - rb)
print("gravity-free closed form: (a) E_b =", mp.nstr(Eb_a, 12), "Pa  zeta =", mp.nstr(Eb_a / E, 12))
print("gravity-free closed form: (b) R_b =", mp.nstr(Rb_b, 12), "m   r =", mp.nstr(Rb_b / R, 12))

# With gravity during the contact: m d'' = m g - k d^(3/2) (d the overlap, d' = v at onset).
# Energy: d'^2 = v^2 + 2 g d - (4/5)(k/m) d^(5/2); the motion is symmetric about d_max,
# T_c = 2 int_0^dmax dd / sqrt(...), evaluated by tanh-sinh quadrature.
def contact_time(Eb, Rb):
    k = mpf(4) / 3 * estar(Eb) * sqrt(rstar(Rb))
    f = lambda d: v**2 + 2 * g * d - mpf(4) / 5 * k / m * d**mpf(2.5)
    d0 = (5 * m * v**2 / (4 * k))**mpf(0.4)
    dmax = findroot(f, d0)
    # d = dmax (1 - s^2) removes the 1/sqrt singularity at dmax.
    fp = 2 * g - 2 * k / m * dmax**mpf(1.5)  # f'(dmax) < 0
    lim = 2 * sqrt(dmax / -fp)  # the integrand's limit at s = 0
    def integrand(s):
        fs = f(dmax * (1 - s**2))
        return lim if fs <= 0 else 2 * dmax * s / sqrt(fs)
    return 2 * quad(integrand, [0, 1])

t_rigid = contact_time(inf, inf)
Eb_g = findroot(lambda lEb: contact_time(mp.e**lEb, inf) / t_rigid - 1 - T, mp.log(Eb_a))
Eb_g = mp.e**Eb_g
t_flat = contact_time(mpf('200e9'), inf)
Rb_g = mp.e**findroot(lambda lRb: contact_time(mpf('200e9'), mp.e**lRb) / t_flat - 1 - T, mp.log(Rb_b))
print("with gravity (quadrature): (a) E_b =", mp.nstr(Eb_g, 12), "Pa  zeta =", mp.nstr(Eb_g / E, 12))
print("with gravity (quadrature): (b) R_b =", mp.nstr(Rb_g, 12), "m   r =", mp.nstr(Rb_g / R, 12))
print("gravity shifts: (a)", mp.nstr(Eb_g / Eb_a - 1, 3), " (b)", mp.nstr(Rb_g / Rb_b - 1, 3))
k = mpf(4)/3*estar(inf)*sqrt(R); print("gamma = 2 g h_max/v^2 =", mp.nstr(2*g*(5*m*v**2/(4*k))**mpf(0.4)/v**2, 3))
print("rigid T_c =", mp.nstr(t_rigid, 10), "s")
