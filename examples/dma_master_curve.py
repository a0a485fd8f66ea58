"""DMA sweeps at several temperatures -> master curve, WLF law, Prony spectrum, cards.

Synthetic data generated here (not a measured material): a generalised Maxwell solid
with seven Prony terms at T_ref = 20 °C and the WLF law C1 = 9, C2 = 110 °C, swept from
0.1 to 100 Hz at 0, 10, ..., 60 °C with 1 % noise, written to a CSV file in the usual
long layout and read back. Runs in a few seconds.

    python examples/dma_master_curve.py
"""

import tempfile
from pathlib import Path

import numpy as np

import vhfit
from vhfit import tts
from vhfit.export import export
from vhfit.spectrum import prony_spectrum

# --- the synthetic material and its sweeps -------------------------------------------
E_INF = 2.4                                          # MPa, long-term modulus
G = np.array([300.0, 150.0, 80.0, 40.0, 20.0, 8.0, 3.0])   # MPa
TAU = 10.0 ** np.arange(-5.0, 2.0)                   # s, at T_ref
TRUE_LAW = tts.WLF(C1=9.0, C2=110.0, T_ref=20.0)
rng = np.random.default_rng(1)

f = np.logspace(-1, 2, 10)                           # the DMA window, Hz
rows = []
for T in np.arange(0.0, 61.0, 10.0):
    w = 2 * np.pi * f[:, None] * TRUE_LAW.aT(T) * TAU   # at T the reference moduli at f a_T
    e1 = E_INF + (G * w**2 / (1 + w**2)).sum(1)
    e2 = (G * w / (1 + w**2)).sum(1)
    noise = 1 + 0.01 * rng.standard_normal((2, f.size))
    rows += [(fk, a, b, T) for fk, a, b in zip(f, e1 * noise[0], e2 * noise[1])]

folder = Path(tempfile.mkdtemp(prefix="vhfit-dma-"))
csv = folder / "dma_sweeps.csv"
csv.write_text("frequency_Hz,storage_MPa,loss_MPa,temperature_C\n"
               + "".join(f"{a:.6g},{b:.6g},{c:.6g},{T:g}\n" for a, b, c, T in rows))

# --- master curve and shift law ------------------------------------------------------
sweeps = vhfit.read_csv(csv)                         # one FrequencySweep per temperature
mc = tts.master_curve(sweeps, T_ref=20.0, law="wlf")
print(f"{len(sweeps)} sweeps -> master curve at {mc.T_ref:g} C over "
      f"{np.log10(mc.frequency.max() / mc.frequency.min()):.1f} decades")
print(" T (C)   log10 a_T built   true")
for T, L in zip(mc.temperatures, mc.log_aT):
    print(f"{T:6.1f}   {L:+9.3f}        {float(TRUE_LAW.log_aT(T)) + 0.0:+.3f}")
print(f"WLF fitted: C1 = {mc.law.C1:.3f}, C2 = {mc.law.C2:.1f} (true 9, 110)")

# --- Prony spectrum: one tau per decade, pruned, refined ---------------------------
spec = prony_spectrum(mc, tolerance=0.05)
print(spec.summary().splitlines()[0])
print("error against N (first rows):", ", ".join(
    f"N={int(n)}: {e:.2%}" for n, e in spec.table[-8:][::-1]))
best = prony_spectrum(mc, n_prony=spec.n_prony, refine=True)
print(f"refined at N = {best.n_prony}: RMS relative error {best.error:.2%}")

# --- a stress-strain test at 40 C is the reference model in reduced time ------------
curve = vhfit.Curve(strain=[0.0, -0.1, -0.2], stress=[0.0, -1.0, -2.0], strain_rate=-1.0)
at_ref = tts.shift_curve(curve, float(mc.law.aT(40.0)))
print(f"a -1/s test at 40 C acts at T_ref as a rate of {at_ref.strain_rate:.3g} 1/s")

# --- the card: Prony terms at T_ref plus the WLF shift ------------------------------
model = vhfit.ViscoHyperelastic("neo_hooke", n_prony=best.n_prony)
params = {"C10": best.E_inf / 6.0, **best.params()}   # E_inf = 6 C10 (incompressible)
card = export(model, params, to="abaqus", shift=mc.law)
print("Abaqus card ends with:", *card.splitlines()[-2:], sep="\n  ")

try:
    from vhfit import plot

    plot.plot_sweeps(mc, folder / "sweeps.png")
    plot.plot_master_curve(mc, best, folder / "master.png")
    plot.plot_shift_factors(mc, folder / "shift_factors.png")
    plot.plot_spectrum_residuals(mc, best, folder / "residuals.png")
    print(f"figures in {folder}")
except plot.PlotUnavailable:
    print("(no matplotlib: figures skipped)")
