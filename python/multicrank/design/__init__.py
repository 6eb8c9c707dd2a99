"""The design aid: what to change in a machine so that it runs smoother with gravity.

- `firing`: the distinct firing orders a machine's crank allows, ranked by δ
  (:func:`firing_orders`).
"""

from .firing import firing_orders

__all__ = ["firing_orders"]
