"""Designs/s of ``mc.motion_sweep`` (δ with and without gravity) along one axis of each kind,
inline-4 preset: what the core shares between the designs of an axis decides its rate.

    RAYON_NUM_THREADS=1 python benches/python/bench_sweep_axes.py [AXIS ...]

- rpm: every design the machine's tables (the solves alone);
- pressure_scale, bore: one gas and one machine's J and U, the gas scaled;
- counterweight_mass, counterweight_radius: one machine's J, panels and gas, U reweighted;
- rod_length, crank_radius: every design its own gas and tables.

Best of five sweeps; "designs/cpu-s" divides by the process's CPU time (all threads), which
a host shared with other jobs disturbs less than the wall time.
"""

from __future__ import annotations

import sys
import time

import numpy as np

import multicrank as mc


def axes(machine: mc.Machine) -> dict[str, np.ndarray]:
    cylinder = machine.cylinders[0]
    return {
        "rpm": np.linspace(1500, 6000, 2048),
        "pressure_scale": np.linspace(0.8, 1.2, 2048),
        "bore": cylinder.bore * np.linspace(0.9, 1.1, 2048),
        "counterweight_mass": np.linspace(0.5, 2.0, 2048),
        "counterweight_radius": cylinder.crank_radius * np.linspace(0.6, 1.2, 2048),
        "rod_length": cylinder.rod_length * np.linspace(0.9, 1.1, 512),
        "crank_radius": cylinder.crank_radius * np.linspace(0.95, 1.05, 512),
    }


def main() -> None:
    machine = mc.presets.MACHINES["inline-4"]
    outputs = ["delta", "delta_without_gravity"]
    known = axes(machine)
    for axis in sys.argv[1:] or list(known):
        grid = mc.MachineGrid(machine, **{axis: known[axis]})
        mc.motion_sweep(machine, grid.frame(0, 8), outputs=outputs)
        wall = cpu = float("inf")
        for _ in range(5):
            start, start_cpu = time.perf_counter(), time.process_time()
            mc.motion_sweep(machine, grid, outputs=outputs)
            wall = min(wall, time.perf_counter() - start)
            cpu = min(cpu, time.process_time() - start_cpu)
        print(f"{axis:22s} {len(grid) / wall:9,.0f} designs/s  {len(grid) / cpu:9,.0f} designs/cpu-s", flush=True)


if __name__ == "__main__":
    main()
