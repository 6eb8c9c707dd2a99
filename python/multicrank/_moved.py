"""The module paths of multicrank 0.1, before the package was split into rooms (gravity/,
machine/, pressure/, motion/, sweeps/, cli/, report/), kept as aliases of where each module
lives now: pickles made with 0.1 name their classes by those paths (``multicrank.engines.Engine``,
``multicrank.loads.PowerLawLoad``, …), and code may import them. Nothing is loaded until such a
path is imported."""

from __future__ import annotations

import importlib
import importlib.abc
import importlib.machinery
import sys
import warnings
from types import ModuleType

#: old module path -> the module that holds its contents now
MOVED = {
    "multicrank.mechanism": "multicrank.gravity.mechanism",
    "multicrank.evaluation": "multicrank.gravity.evaluation",
    "multicrank.harmonics": "multicrank.gravity.harmonics",
    "multicrank.extrema": "multicrank.gravity.extrema",
    "multicrank.engines": "multicrank.gravity.engines",
    "multicrank.layouts": "multicrank.gravity.layouts",
    "multicrank.grids": "multicrank.gravity.grids",
    "multicrank.machine_files": "multicrank.machine.files",
    "multicrank.loads": "multicrank.motion.loads",
    "multicrank.transient": "multicrank.motion.transient",
    "multicrank.orders": "multicrank.motion.orders",
    "multicrank.designs": "multicrank.sweeps.designs",
    "multicrank.store": "multicrank.sweeps.store",
    # 0.2: two modules were named firing; the machine's (the phases a layout's cylinders get)
    # is phases now, and design.firing (mc.firing_orders) keeps the name.
    "multicrank.machine.firing": "multicrank.machine.phases",
}
#: The moved paths of 0.2 (not 0.1's, which old pickles name): importing one warns, and it goes in 0.3.
RENAMED_IN_0_2 = frozenset({"multicrank.machine.firing"})


class _MovedModules(importlib.abc.MetaPathFinder, importlib.abc.Loader):
    """Finds an old path and answers with the module that lives at the new one (one object
    under two names, so classes pickled under either load as the same class)."""

    def find_spec(
        self, fullname: str, path: object = None, target: object = None
    ) -> importlib.machinery.ModuleSpec | None:
        if fullname in MOVED:
            return importlib.machinery.ModuleSpec(fullname, self)
        return None

    def create_module(self, spec: importlib.machinery.ModuleSpec) -> ModuleType:
        if spec.name in RENAMED_IN_0_2:
            warnings.warn(
                f"the module {spec.name} is deprecated since multicrank 0.2: use {MOVED[spec.name]} "
                "(the old name goes in 0.3)",
                DeprecationWarning,
                stacklevel=2,
            )
        module = importlib.import_module(MOVED[spec.name])
        # The import machinery sets the created module's __spec__ to this (old) spec; keep the
        # module's own, or its relative imports would resolve from the old path's package.
        spec.loader_state = module.__spec__
        return module

    def exec_module(self, module: ModuleType) -> None:
        # The module at the new path is already executed: only give it its own spec back.
        alias = module.__spec__
        if alias is not None:
            module.__spec__ = alias.loader_state


def install() -> None:
    """Put the finder on sys.meta_path once (after the regular finders: a real module of that
    name, were one ever added, wins)."""
    if not any(isinstance(finder, _MovedModules) for finder in sys.meta_path):
        sys.meta_path.append(_MovedModules())
