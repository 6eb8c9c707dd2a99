"""
A start-up against a propeller
==============================

A single-cylinder four-stroke engine is run up from 300 rpm against a propeller, a load
that grows with the square of the speed. ``mc.simulate`` integrates the equation of
motion

.. math:: J(\\varphi)\\,\\ddot\\varphi + \\tfrac12 J'(\\varphi)\\,\\dot\\varphi^2
          = M_\\mathrm{gas} - U'(\\varphi) - M_\\mathrm{load}(\\dot\\varphi)

in time until the speed settles, and checks its own accuracy with the energy balance.
The run ends in the engine's periodic steady state, which ``mc.steady_state`` gives
directly.
"""

# %%
# The engine
# ----------
# A 90 mm stroke, 85 mm bore cylinder with a 150 mm rod, its crank web and
# counterweight, and a 0.12 kg·m² flywheel. The gas pressure is the library's synthetic
# single-zone engine cycle over the cylinder's own volume (``Cylinder.engine_diagram``:
# 700 J released per cycle, compression ratio about 10).
import math
import os

import matplotlib.pyplot as plt
import numpy as np

import multicrank as mc

# Short settings for the documentation's continuous-integration build.
FAST = os.environ.get("MULTICRANK_DOCS_FAST", "") not in ("", "0")

cylinder = mc.Cylinder(
    crank_radius=0.045,
    rod_length=0.15,
    piston_mass=0.45,
    rod_mass=0.35,
    rod_cg=0.1,
    rod_inertia=0.0007,
    crank_mass=1.2,
    crank_cg_radius=0.02,
    counterweight_mass=1.0,
    counterweight_radius=0.04,
    bore=0.085,
)
cylinder = cylinder.replace(
    pressure=cylinder.engine_diagram(
        intake_pressure=0.95e5, heat_release=700.0, clearance_volume=5.5e-5
    )
)
machine = mc.Machine(
    [cylinder], shaft_inertia=0.12, strokes=4, name="single-cylinder engine"
)
swept = cylinder.swept_volume()  # m³
print(f"λ = {cylinder.crank_ratio:.2f}, swept volume {swept * 1e6:.0f} cm³")

# %%
# The propeller
# -------------
# A square-law load, M = M_n (ω/ω_n)², sized to absorb the engine's mean torque at
# 1500 rpm. The mean gas torque is order 0 of ``mc.torque_orders``.
mean_torque = mc.torque_orders(machine, 1500, max_order=1).loc[0.0, "gas_cos"]
propeller = mc.PowerLawLoad(torque=mean_torque, rpm=1500, exponent=2)
print(f"mean gas torque {mean_torque:.1f} N·m: the propeller takes it at 1500 rpm")

# %%
# The run
# -------
# From 300 rpm at the firing dead centre, sampled every half millisecond. The
# tolerance is looser than the default (1e-10): the tabulated pressure has kinks at its
# valve events, and the adaptive steps that follow them are what a run costs.
duration, tolerance = (2.5, 1e-7) if FAST else (4.0, 1e-8)
times = np.linspace(0.0, duration, int(duration * 2000) + 1)
run = mc.simulate(
    machine,
    times,
    rpm0=300,
    load=propeller,
    rtol=tolerance,
    atol=tolerance,
)
print(f"{len(run)} samples, {run.rpm_history[0]:.0f} → {run.rpm_history[-1]:.0f} rpm")
print(f"energy check: drift {run.energy_drift:.1e} of the largest kinetic energy")

# %%
# The steady state it approaches, solved directly (in closed form for a square-law
# load):
steady = mc.steady_state(machine, load=propeller)
print(f"steady state: {steady.rpm:.1f} rpm mean, δ = {steady.delta:.3f}")

# The last working cycle (4π) of the run: its time-mean speed and δ.
start = run.phi[-1] - machine.cycle
t_start = np.interp(start, run.phi, run.time)
last_mean = machine.cycle / (run.time[-1] - t_start)
window = run.omega[run.phi >= start]
last_delta = (window.max() - window.min()) / last_mean
last_rpm = last_mean * 30 / math.pi
print(f"the run's last cycle: {last_rpm:.1f} rpm mean, δ = {last_delta:.3f}")

# %%
# Speed and torques over time
# ---------------------------
# The speed climbs and its fluctuation — large for a single cylinder with a light
# flywheel — rides on top. The lower panel shows the torques over the first and the last
# tenth of a second: the gas torque's firing peaks against the propeller.
figure = plt.figure(figsize=(8, 7), layout="constrained")
grid = figure.add_gridspec(2, 2, height_ratios=[1.2, 1])
speed = figure.add_subplot(grid[0, :])
speed.plot(run.time, run.rpm_history, linewidth=0.8, label="simulated")
speed.axhline(
    steady.rpm,
    color="black",
    linestyle="--",
    linewidth=1,
    label=f"steady state, {steady.rpm:.0f} rpm mean",
)
speed.set_xlabel("time t [s]")
speed.set_ylabel("speed n [rpm]")
speed.set_title(
    f"Start-up of a single-cylinder engine from 300 rpm, δ at the end {last_delta:.3f}"
)
speed.legend(loc="lower right")
for column, (low, high) in enumerate(((0.0, 0.1), (duration - 0.1, duration))):
    ax = figure.add_subplot(
        grid[1, column], sharey=None if column == 0 else figure.axes[1]
    )
    shown = (run.time >= low) & (run.time <= high)
    for name, label in (
        ("gas_torque", "gas"),
        ("inertia_torque", "inertia"),
        ("load_torque", "propeller"),
    ):
        ax.plot(run.time[shown], getattr(run, name)[shown], label=label, linewidth=0.9)
    ax.set_xlabel("time t [s]")
    ax.set_title(f"torques from {low:.1f} to {high:.1f} s")
figure.axes[1].set_ylabel("torque [N·m]")
figure.axes[1].legend(loc="upper right")
plt.show()

# %%
# The speed settles within a few seconds — the propeller's torque grows with speed, so
# the run approaches its steady state by a fixed factor per cycle — and the last working
# cycle matches the steady state's mean speed and δ above. The gravity torque is left
# out of the plot: on this light, fast engine it is tiny beside the gas torque,
print(
    f"largest |gravity torque| {abs(run.gravity_torque).max():.2f} N·m, "
    f"|gas torque| {abs(run.gas_torque).max():.0f} N·m"
)

# %%
# and ``steady.delta_without_gravity`` shows how little it changes δ:
print(
    f"δ = {steady.delta:.5f} with gravity, {steady.delta_without_gravity:.5f} without"
)
