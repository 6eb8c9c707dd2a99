"""The design aid: what to change in a machine so that it runs smoother with gravity.

- `firing`: the distinct firing orders a machine's crank allows, ranked by δ
  (:func:`firing_orders`);
- `counterweights`: the counterweights per throw that minimise δ, or another objective
  (:func:`optimize_counterweights`, :class:`CounterweightOptimum`).
"""

from .counterweights import OBJECTIVES, CounterweightOptimum, optimize_counterweights
from .firing import firing_orders

__all__ = ["OBJECTIVES", "CounterweightOptimum", "firing_orders", "optimize_counterweights"]
