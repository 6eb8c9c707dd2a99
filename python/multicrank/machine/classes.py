"""The classes of machine and the coefficient of speed fluctuation each allows: a machine file's
``class`` key and the built-in machines (:mod:`multicrank.presets`) read them here."""

from __future__ import annotations

__all__ = ["SPEED_FLUCTUATION"]

#: The usual coefficient of speed fluctuation δ = (ω_max − ω_min)/ω_mean of each class of
#: machine, (lowest, highest). Compressors (and pumps) 1/20–1/50, vehicle engines 1/100–1/300
#: and AC generator sets ≤ 1/300 are the classic handbook values (the same as the report's
#: threshold note). Ship propulsion: a direct-driven propeller is a smooth, heavily damped
#: load, like a pump's; we take the pump and compressor limit, δ ≤ 1/20, as its bound
#: (reasoning, not a handbook figure). A lower bound of 0: the class asks no more than the
#: upper one (a smoother machine is as good).
SPEED_FLUCTUATION: dict[str, tuple[float, float]] = {
    "compressor": (1 / 50, 1 / 20),
    "vehicle engine": (1 / 300, 1 / 100),
    "generator set": (0.0, 1 / 300),
    "ship propulsion": (0.0, 1 / 20),
}
