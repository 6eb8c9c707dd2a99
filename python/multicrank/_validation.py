"""Coercion and validation shared by the fast API and the numpy reference (the design
parameters' broadcasting, built on them, is `_broadcasting`'s).

Everything that reaches the Rust kernels leaves here as a contiguous float64 array, and every kind
of bad input leaves here as a :class:`MechanismError` that names the parameter, in its message and
as data (its ``parameter``: :func:`refused`, the package's one way to make one). It holds the one
rule for a speed asked of a machine (:func:`running_omega`) and its one conversion
(:func:`omega_from_rpm`). It depends on nothing of the package but the extension, so every other
module can use it without an import circle.
"""

from __future__ import annotations

import difflib
import math
import operator
import os
import sys
import warnings
from collections.abc import Iterator
from contextlib import contextmanager
from typing import Any, TypeVar

import numpy as np

from ._native import SPEED_LIMITS as _CORE_SPEED_LIMITS
from ._native import MechanismError

__all__ = [
    "INDEX_MAX",
    "MAGNITUDE_LIMIT",
    "RPM_LIMITS",
    "SPEED_LIMITS",
    "allocatable_bytes",
    "as_count",
    "as_flag",
    "as_instance",
    "as_label",
    "as_nonnegative",
    "as_omega",
    "as_omega_array",
    "as_option",
    "as_real_array",
    "as_returned",
    "as_rpm",
    "as_rpm_range",
    "as_scalar",
    "as_strokes",
    "as_threshold",
    "as_work_size",
    "check_fields",
    "check_magnitude",
    "check_size",
    "contiguous",
    "has_gas",
    "omega_from_rpm",
    "one_of",
    "part_of",
    "refused",
    "renamed",
    "reworded",
    "rpm_from_omega",
    "running_omega",
    "running_rpm",
    "warn_renamed",
]

_NUMERIC_KINDS = "iuf"

#: The largest count the native layer takes (its integers are 64-bit): anything above is
#: refused here, by name, rather than overflowing in the conversion.
INDEX_MAX = 2**63 - 1
#: The largest count the native layer takes (its counts are u64/usize); what is larger than
#: memory allows is refused by check_size, by name, before any work.
COUNT_MAX = 2**64 - 1


def refused(parameter: str, message: str) -> MechanismError:
    """The package's one way to make a :class:`MechanismError`: ``message`` (which starts with
    the parameter's name, or the context it is re-raised with) and ``parameter``, the name as
    data (the exception's ``parameter``), so that a caller tells which value was wrong without
    reading the message. ``raise refused("rpm", f"rpm = {rpm} is out of range; ...")``."""
    error = MechanismError(message)
    error.parameter = parameter
    return error


def reworded(error: MechanismError, message: str) -> MechanismError:
    """``error`` re-raised with its context (``message``: "design 3 (rpm = 0): …", "--shaft
    FILE: …"): a :class:`MechanismError` about the same parameter as ``error``."""
    again = MechanismError(message)
    again.parameter = error.parameter
    return again


@contextmanager
def part_of(parameter: str) -> Iterator[None]:
    """The refusals inside, of a part of ``parameter`` (``banks[2]``, a grid's axis, an element
    of an openTorsion model), as refusals of ``parameter``: their message as it is, their
    ``parameter`` this one."""
    try:
        yield
    except MechanismError as error:
        if error.parameter == parameter:
            raise
        raise refused(parameter, str(error)) from None


def as_real_array(value: Any, name: str) -> np.ndarray:
    """`value` as a float64 ndarray; strings, complex, bool, object and None are rejected."""
    try:
        array = np.asarray(value)
    except Exception as exc:  # ragged nested lists and the like
        raise refused(name, f"{name} must be a real number or an array of real numbers: {exc}") from None
    if array.dtype.kind not in _NUMERIC_KINDS:
        raise refused(
            name,
            f"{name} must be a real number or an array of real numbers, got dtype {array.dtype}"
            f" ({type(value).__name__})",
        )
    return array.astype(np.float64, copy=False)


def as_array(values: Any, what: str) -> np.ndarray:
    """np.asarray, with numpy's errors for ragged or odd input turned into ours."""
    try:
        return np.asarray(values)
    except (ValueError, TypeError) as exc:
        raise refused(what, f"{what} must be a scalar or a 1-D sequence: {exc}") from None


#: The largest magnitude of a machine's physical quantities in SI units — lengths [m], masses
#: [kg], inertias [kg·m²], g [m/s²], pressures [Pa], torques [N·m] — 10²⁴ times anything built,
#: and far enough below a double's overflow (1.8·10³⁰⁸) that the products the motion forms of
#: them (m r² ω², p·A·r, and the squares of energies and torques) stay finite. Larger values
#: are refused by name; a bore of 10¹⁶⁰ m made the piston area overflow.
MAGNITUDE_LIMIT = 1e30


def check_magnitude(value: float, name: str, unit: str) -> float:
    """``value`` unless it is finite and larger in magnitude than :data:`MAGNITUDE_LIMIT`:
    then a :class:`MechanismError` naming ``name`` and the allowed range (NaN and inf are
    left to the caller's own check, which words them)."""
    if math.isfinite(value) and abs(value) > MAGNITUDE_LIMIT:
        raise refused(
            name,
            f"{name} = {value:g} is out of range; allowed: |{name}| <= {MAGNITUDE_LIMIT:g} [{unit}] (beyond it, "
            "products of the machine's quantities overflow)",
        )
    return value


def as_returned(
    value: Any, name: str, quantity: str, unit: str, shape: tuple[int, ...], *, broadcast: bool = False
) -> np.ndarray:
    """What a user's callable ``name`` returned (a ``quantity`` in ``unit``: "pressure", "Pa"),
    checked: real numbers — not complex (whose imaginary part would be dropped), bool, text
    or objects —, finite and at most :data:`MAGNITUDE_LIMIT` in magnitude, and of ``shape``,
    the shape of the arguments it was called with (``broadcast``: or a shape that broadcasts
    to it). A float64 array of ``shape``."""
    wanted = f"a real {quantity} [{unit}]"
    try:
        array = np.asarray(value)
    except Exception as exc:  # ragged nested lists and the like
        raise refused(name, f"{name} must return {wanted} per point: {exc}") from None
    if array.dtype.kind not in _NUMERIC_KINDS:
        raise refused(name, f"{name} must return {wanted} per point, got dtype {array.dtype} ({type(value).__name__})")
    if array.shape != shape:
        try:
            fits = broadcast and np.broadcast_shapes(array.shape, shape) == shape
        except ValueError:
            fits = False
        if not fits:
            allowed = "an array that broadcasts to it" if broadcast else "an array of that shape, one per point"
            raise refused(
                name,
                f"{name} returned shape {array.shape} when called with shape {shape}; it must return {wanted} "
                f"as {allowed} (a vectorised callable)",
            )
        array = np.broadcast_to(array, shape)
    values = array.astype(np.float64)
    bad = np.flatnonzero(~np.isfinite(values))
    if bad.size:
        raise refused(name, f"{name} returned a non-finite {quantity} ({values.flat[bad[0]]}) [{unit}]")
    huge = np.flatnonzero(np.abs(values) > MAGNITUDE_LIMIT)
    if huge.size:
        raise refused(
            name,
            f"{name} returned a {quantity} of {values.flat[huge[0]]:g} [{unit}], out of range; allowed: "
            f"|{quantity}| <= {MAGNITUDE_LIMIT:g} [{unit}]",
        )
    return values


def allocatable_bytes() -> int:
    """The most bytes one result may take: the machine's physical memory (``sys.maxsize``
    where the platform does not say). A request beyond it could only fail or swap for hours."""
    try:
        pages, page_size = os.sysconf("SC_PHYS_PAGES"), os.sysconf("SC_PAGE_SIZE")
    except (AttributeError, ValueError, OSError):
        return sys.maxsize
    return pages * page_size if pages > 0 and page_size > 0 else sys.maxsize


def check_size(parameter: str, value: Any, count: int, *, item_bytes: int = 8) -> int:
    """``count`` (items of ``item_bytes`` each, asked for through ``parameter`` = ``value``),
    or a :class:`MechanismError` naming them when that much memory cannot be had — raised
    before anything is allocated or computed. Python integers: the product never overflows."""
    size = count * item_bytes
    if size > allocatable_bytes():
        raise refused(
            parameter,
            f"{parameter} = {value} asks for {count} values ({size} bytes), more than can be "
            f"allocated (this machine has {allocatable_bytes()} bytes of memory)",
        )
    return count


def contiguous(array: np.ndarray) -> np.ndarray:
    """A C-contiguous, aligned float64 array, as the native kernels take it (no copy if it already is).

    np.ascontiguousarray alone would pass a misaligned buffer (np.frombuffer at an odd
    offset) through, which the extension then refuses.
    """
    return np.require(array, dtype=np.float64, requirements=["C_CONTIGUOUS", "ALIGNED"])


def as_work_size(value: Any, name: str) -> int:
    """A parallel threshold: a work size ≥ 0 (huge values, clamped to 2⁶³ − 1, mean serial)."""
    if isinstance(value, (bool, np.bool_)):
        raise refused(name, f"{name} must be an integer >= 0, got {value!r}")
    try:
        count = operator.index(value)
    except TypeError:
        raise refused(name, f"{name} must be an integer >= 0, got {value!r}") from None
    if count < 0:
        raise refused(name, f"{name} = {count} is out of range; allowed: an integer >= 0")
    return min(count, INDEX_MAX)


def as_threshold(value: Any) -> int | None:
    """The ``parallel_threshold`` of one call, or None for the global default."""
    return None if value is None else as_work_size(value, "parallel_threshold")


def as_scalar(value: Any, name: str) -> float:
    """One real number (its range is checked where it is used)."""
    if type(value) is float:  # the common case, as the general route gives it (~1 µs less a call)
        return value
    array = as_real_array(value, name)
    if array.ndim != 0:
        raise refused(name, f"{name} must be a single real number, got shape {array.shape}")
    return float(array)


def as_nonnegative(value: Any, name: str) -> float:
    """One finite real number >= 0 (a standard deviation, a tolerance)."""
    scalar = as_scalar(value, name)
    if not (math.isfinite(scalar) and scalar >= 0):
        raise refused(name, f"{name} = {scalar} is out of range; allowed: a finite real >= 0")
    return scalar


def as_count(value: Any, name: str, *, minimum: int, maximum: int = COUNT_MAX) -> int:
    """An integer in [minimum, maximum] (bools and floats such as 2.0 are rejected).

    ``maximum`` defaults to the native layer's unsigned 64-bit limit: a larger Python int would
    otherwise escape as an OverflowError from the conversion.
    """
    allowed = f"an integer >= {minimum}" if maximum == COUNT_MAX else f"an integer {minimum} <= {name} <= {maximum}"
    if isinstance(value, (bool, np.bool_)):
        raise refused(name, f"{name} must be {allowed}, got {value!r}")
    try:
        count = operator.index(value)
    except TypeError:
        raise refused(name, f"{name} must be {allowed}, got {value!r}") from None
    if count < minimum:
        raise refused(name, f"{name} = {count} is out of range; allowed: {allowed}")
    if count > maximum:
        limit = "" if maximum != COUNT_MAX else f" (at most {maximum})"
        raise refused(name, f"{name} = {count} is out of range; allowed: {allowed}{limit}")
    return count


def as_flag(value: Any, name: str) -> bool:
    """True or False (numpy's bools too); anything else, truthy or not, is refused."""
    if not isinstance(value, (bool, np.bool_)):
        raise refused(name, f"{name} must be True or False, got {value!r}")
    return bool(value)


def as_label(value: Any, name: str) -> str:
    """A text label (a name shown in tables and reprs)."""
    if not isinstance(value, str):
        raise refused(name, f"{name} must be a string, got {type(value).__name__} {value!r}")
    return value


def as_option(value: Any, name: str, allowed: tuple[str, ...]) -> str:
    """One of the option strings in `allowed`."""
    if not isinstance(value, str) or value not in allowed:
        choices = ", ".join(repr(a) for a in allowed)
        raise refused(name, f"{name} = {value!r} is not allowed; allowed: {choices}")
    return value


def as_strokes(value: Any) -> int:
    """The number of strokes of the working cycle: 2 or 4."""
    strokes = as_count(value, "strokes", minimum=1)
    if strokes not in (2, 4):
        raise refused("strokes", f"strokes = {strokes} is not allowed; allowed: 2 or 4")
    return strokes


#: A float, or an array of them (the speed conversions keep the type they are given).
Speed = TypeVar("Speed", float, np.ndarray)


def omega_from_rpm(rpm: Speed) -> Speed:
    """ω = π n/30 [rad/s] of a speed n [1/min] (a number or an array): the package's one
    conversion of a user's speed to the core's unit."""
    return rpm * math.pi / 30.0  # one revolution (2π rad) per minute (60 s)


def rpm_from_omega(omega: Speed) -> Speed:
    """n = 30 ω/π [1/min] of a speed ω [rad/s] (a number or an array): every ``rpm…`` a
    result shows is derived from its ω by this function."""
    return omega * 30.0 / math.pi


#: The speeds ω [rad/s] a machine may run at: the core's one rule for a speed (its
#: ``SPEED_LIMITS``, which every entry of the core checks), (π/30)·10⁻⁶ to (π/30)·10⁸. Far
#: outside them ω² and the cycle's time scales over- or underflow a double on the way to δ;
#: no machine comes near either end.
SPEED_LIMITS: tuple[float, float] = (float(_CORE_SPEED_LIMITS[0]), float(_CORE_SPEED_LIMITS[1]))

#: :data:`SPEED_LIMITS` in the user's unit [1/min] (10⁻⁶ to 10⁸), for messages.
RPM_LIMITS: tuple[float, float] = (rpm_from_omega(SPEED_LIMITS[0]), rpm_from_omega(SPEED_LIMITS[1]))


def _within_limits(omega: float) -> bool:
    return math.isfinite(omega) and SPEED_LIMITS[0] <= omega <= SPEED_LIMITS[1]


def as_omega(value: Any, name: str = "rpm") -> float:
    """ω [rad/s] of a user's speed ``value`` [1/min] named ``name``: one finite number whose
    ω lies within :data:`SPEED_LIMITS` (the core's rule), converted here, once; the message
    of a bad one names ``name`` and the range in 1/min."""
    speed = as_scalar(value, name)
    omega = omega_from_rpm(speed)
    if not _within_limits(omega):
        low, high = RPM_LIMITS
        raise refused(name, f"{name} = {speed} is out of range; allowed: {low:g} <= {name} <= {high:g} [1/min]")
    return omega


def as_omega_array(values: np.ndarray, name: str = "rpm") -> np.ndarray:
    """ω [rad/s] of an array of a user's speeds [1/min] named ``name``, every value checked as
    :func:`as_omega` checks one (the first bad one named in its message)."""
    omega = omega_from_rpm(np.asarray(values, dtype=np.float64))
    bad = np.flatnonzero(~((omega >= SPEED_LIMITS[0]) & (omega <= SPEED_LIMITS[1])))  # NaN fails both
    if bad.size:
        as_omega(float(np.asarray(values).flat[bad[0]]), name)  # raises, naming the range in 1/min
    return omega


def as_rpm(value: Any, name: str = "rpm") -> float:
    """A speed n [1/min] as the user gave it (not converted), checked by :func:`as_omega`
    (the core's rule): for a speed that is shown or handed on in 1/min, a table's ``rpm``
    column."""
    speed = as_scalar(value, name)
    as_omega(speed, name)
    return speed


def _asked(machine: Any, rpm: Any, name: str) -> Any:
    """The one rule for a speed asked of a machine: ``rpm`` [1/min], or where it is None the
    machine's own ``rpm``; refused by ``name`` where it has none."""
    if rpm is not None:
        return rpm
    if machine.rpm is None:
        raise refused(name, f"{name} is required: machine {machine.name!r} has no running speed (rpm) of its own")
    return machine.rpm


def running_omega(machine: Any, rpm: Any, name: str = "rpm") -> float:
    """ω [rad/s] of the speed asked of a machine (a :class:`~multicrank.Machine`): ``rpm``
    [1/min], or where it is None the machine's own ``rpm``, refused by ``name`` where it has
    none; checked by the core's rule and converted once (:func:`as_omega`)."""
    return as_omega(_asked(machine, rpm, name), name)


def running_rpm(machine: Any, rpm: Any, name: str = "rpm") -> float:
    """:func:`running_omega`'s speed as given, in 1/min (checked, not converted): for a speed
    that is shown or handed on in 1/min, a table's ``rpm`` column."""
    return as_rpm(_asked(machine, rpm, name), name)


def as_rpm_range(value: Any) -> tuple[float, float]:
    """A machine's ``rpm_range``: (low, high) [1/min] with 0 < low < high, within :data:`SPEED_LIMITS`."""
    bounds = as_real_array(value, "rpm_range")
    if bounds.shape != (2,):
        raise refused("rpm_range", f"rpm_range must be two speeds (low, high) [1/min], got shape {bounds.shape}")
    low, high = (float(b) for b in bounds)
    if not (low < high and _within_limits(omega_from_rpm(low)) and _within_limits(omega_from_rpm(high))):
        raise refused(
            "rpm_range",
            f"rpm_range = ({low:g}, {high:g}) is out of range; allowed: {RPM_LIMITS[0]:g} <= low < high "
            f"<= {RPM_LIMITS[1]:g} [1/min]",
        )
    return low, high


def check_fields(given: Any, known: tuple[str, ...], what: str, *, elsewhere: tuple[str, ...] = ()) -> None:
    """Refuse keywords of ``replace`` that are no field of ``what`` ("cylinder", "machine"):
    a :class:`MechanismError` naming them (and the nearest field, where one is close) and
    listing the fields there are. ``elsewhere``: the fields of a machine's cylinders, which
    a machine's ``replace`` changes through ``cylinders``."""
    unknown = sorted(set(given) - set(known))
    if not unknown:
        return
    close = difflib.get_close_matches(unknown[0], known, n=1)
    hint = f" (did you mean {close[0]!r}?)" if close else ""
    if set(unknown) <= set(elsewhere):
        hint = (
            f" ({', '.join(unknown)}: a field of each cylinder; change it through cylinders="
            f"[c.replace({unknown[0]}=...) for c in machine.cylinders])"
        )
    raise refused(unknown[0], f"unknown {what} field(s) {', '.join(unknown)}{hint}; known: {', '.join(known)}")


def one_of(first: tuple[str, Any], second: tuple[str, Any]) -> tuple[str, Any]:
    """The one of two (name, value) keywords that was given (not None), for a quantity that
    may be given either way (a speed in rad/s or in 1/min); neither or both is refused."""
    given = [(name, value) for name, value in (first, second) if value is not None]
    if len(given) != 1:
        told = "both" if given else "neither"
        # Both: the second, the other way to give it, is the one too many; neither: the first.
        raise refused(second[0] if given else first[0], f"give exactly one of {first[0]} and {second[0]}, got {told}")
    return given[0]


Kind = TypeVar("Kind")


def as_instance(value: Any, kind: type[Kind], name: str) -> Kind:
    """An instance of one of the package's public classes (``as_instance(machine, Machine,
    "machine")``): anything else has none of its methods, and is refused by name. The class
    is the caller's to give, so that this module imports none of them."""
    if not isinstance(value, kind):
        raise refused(name, f"{name} must be a multicrank.{kind.__name__}, got {type(value).__name__}")
    return value


def has_gas(cylinder: Any) -> bool:
    """Whether a cylinder takes a gas torque: a bore and a pressure on at least one end."""
    return bool(cylinder.bore > 0 and (cylinder.pressure is not None or cylinder.pressure_crank_end is not None))


def warn_renamed(old: str, new: str, *, stacklevel: int = 3) -> None:
    """Say that ``old`` (a keyword or attribute of 0.1) is now called ``new``: a
    DeprecationWarning pointing at the caller's line. The old name goes in 0.3."""
    warnings.warn(
        f"{old} is deprecated since multicrank 0.2: use {new} (the old name goes in 0.3)",
        DeprecationWarning,
        stacklevel=stacklevel,
    )


class renamed:
    """An old attribute name kept working: ``J = renamed("reduced_inertia")`` reads and writes
    ``self.reduced_inertia`` with a DeprecationWarning (:func:`warn_renamed`; a frozen class refuses writes)."""

    def __init__(self, new: str) -> None:
        self.new = self.old = new

    def __set_name__(self, owner: type, name: str) -> None:
        self.old = f"{owner.__name__}.{name}"

    def __get__(self, instance: Any, owner: type | None = None) -> Any:
        if instance is None:
            return self
        warn_renamed(self.old, f"{self.old.split('.')[0]}.{self.new}")
        return getattr(instance, self.new)

    def __set__(self, instance: Any, value: Any) -> None:
        warn_renamed(self.old, f"{self.old.split('.')[0]}.{self.new}")
        setattr(instance, self.new, value)
