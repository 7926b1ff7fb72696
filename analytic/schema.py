"""Case fields declared once: type, unit, valid range and a one-line meaning.

Every case record (a frozen dataclass of a study, a DEM engine or a theory) declares
its fields with ``param``; ``check_fields`` in the record's ``__post_init__`` checks
them all, so a flag, ``--set``, a ``--config`` file and the Python API meet one
validator, and ``wallsim keys`` prints the same declaration::

    @dataclass(frozen=True)
    class Recipe:
        particles: int = param(30_000, unit="-", lo=50, hi=2_000_000,
                               meaning="spheres including clump members (paper ~30,000)")

        def __post_init__(self):
            check_fields(self)
            ...  # checks that span fields (d_min <= d_max)

The type comes from the annotation: ``int`` is a whole number (3000.5 is refused, not
cut to 3000), ``float`` a finite number, ``tuple[float, ...]`` a non-empty list whose
every item is in the range, ``Literal[...]`` one of its words, ``X | None`` also None.
"""

from __future__ import annotations

import dataclasses
import math
import numbers
import types
import typing
from dataclasses import MISSING, dataclass

from .errors import InvalidParameter


class _FromTheStart:
    def __repr__(self) -> str:
        return "FROM_THE_START"


#: ``Spec.absent_means`` of a field its record has had from the start
FROM_THE_START = _FromTheStart()


@dataclass(frozen=True)
class Spec:
    """What a field is: meaning (one line), unit ("-" for a ratio or a count, "" for a
    word) and the range of a number or of each item of a list.

    absent_means: for a field added after runs were made without it, the value those
    runs had in effect: content keys leave the field out while it holds this value (so
    the run folders and caches of earlier runs keep their names), and a saved case that
    lacks the field (an earlier run's config.toml) reads as this value, not the default.
    """

    meaning: str
    unit: str = "-"
    lo: float | None = None
    hi: float | None = None
    lo_open: bool = False
    hi_open: bool = False
    may_be_empty: bool = False
    absent_means: object = FROM_THE_START

    def bounds_text(self) -> str:
        """'(0, 80) deg', '>= 50', or '' when unbounded."""
        u = f" {self.unit}" if self.unit not in ("", "-") else ""
        lo, hi = _bound(self.lo), _bound(self.hi)
        if lo is None and hi is None:
            return ""
        if hi is None:
            return f"{'>' if self.lo_open else '>='} {lo}{u}"
        if lo is None:
            return f"{'<' if self.hi_open else '<='} {hi}{u}"
        return f"{'(' if self.lo_open else '['}{lo}, {hi}{')' if self.hi_open else ']'}{u}"

    def contains(self, x: float) -> bool:
        if self.lo is not None and (x < self.lo or (self.lo_open and x == self.lo)):
            return False
        return not (self.hi is not None and (x > self.hi or (self.hi_open and x == self.hi)))


def _bound(x) -> str | None:
    """A bound as text: whole numbers in full (4294967295, not 4.29497e+09)."""
    if x is None:
        return None
    if float(x).is_integer() and abs(x) < 1e16:
        return str(int(x))
    return f"{x:g}"


def param(default=MISSING, *, meaning: str, unit: str = "-", lo: float | None = None, hi: float | None = None,
          lo_open: bool = False, hi_open: bool = False, may_be_empty: bool = False, factory=MISSING,
          absent_means=FROM_THE_START):
    """A declared case field (``dataclasses.field`` with its ``Spec`` as metadata);
    ``may_be_empty``: a list field that may hold nothing (``none`` on the command line);
    ``absent_means``: see ``Spec``."""
    spec = Spec(meaning, unit, lo, hi, lo_open, hi_open, may_be_empty, absent_means)
    return dataclasses.field(default=default, default_factory=factory, metadata={"spec": spec})


def spec_of(field: dataclasses.Field) -> Spec | None:
    return field.metadata.get("spec")


def added_later(field: dataclasses.Field) -> bool:
    """Whether the field declares what a record made before it existed had in effect."""
    spec = spec_of(field)
    return spec is not None and spec.absent_means is not FROM_THE_START


def left_out_of_keys(record, field: dataclasses.Field) -> bool:
    """Whether a content key of ``record`` leaves ``field`` out: a field added later,
    holding what the records made before it had in effect."""
    return added_later(field) and getattr(record, field.name) == spec_of(field).absent_means


def as_before(record):
    """``record`` with each field added later at what records made before it had in
    effect (nested records too): the base a saved case without those fields is read on."""
    changes = {}
    for f in dataclasses.fields(record):
        value = getattr(record, f.name)
        if added_later(f):
            changes[f.name] = spec_of(f).absent_means
        elif dataclasses.is_dataclass(value) and not isinstance(value, type):
            changes[f.name] = as_before(value)
    return dataclasses.replace(record, **changes) if changes else record


def _hints(cls) -> dict:
    cached = cls.__dict__.get("_wallsim_hints")
    if cached is None:
        cached = typing.get_type_hints(cls)
        setattr(cls, "_wallsim_hints", cached)
    return cached


def field_type(cls, name: str):
    """The resolved annotation of field ``name`` of record class ``cls``."""
    return _hints(cls)[name]


def _is_union(typ) -> bool:
    return typing.get_origin(typ) in (typing.Union, types.UnionType)


def split_optional(typ) -> tuple[object, bool]:
    """(the type without None, whether None is allowed)."""
    if _is_union(typ):
        args = [a for a in typing.get_args(typ) if a is not type(None)]
        return args[0], len(args) < len(typing.get_args(typ))
    return typ, False


def item_type(typ):
    """The item type of a list-valued field (``tuple[float, ...]``, bare ``tuple``: float),
    or None when the field holds one value."""
    if typ in (tuple, list):
        return float
    if typing.get_origin(typ) in (tuple, list):
        args = [a for a in typing.get_args(typ) if a is not Ellipsis]
        return args[0] if args else float
    return None


def valid_text(typ, spec: Spec | None) -> str:
    """What a field accepts, as an error message and ``wallsim keys`` say it:
    'a whole number in [1, 500]', 'a comma-separated list of numbers in (0, 80) deg'."""
    base, optional = split_optional(typ)
    bounds = spec.bounds_text() if spec else ""
    inner = item_type(base)
    if inner is not None:
        text = "a comma-separated list of " + _kind(inner, plural=True) + (f" in {bounds}" if bounds and
                                                                           bounds[0] in "([" else
                                                                           f" {bounds}" if bounds else "")
    elif typing.get_origin(base) is typing.Literal:
        text = " | ".join(map(str, typing.get_args(base)))
    else:
        text = _kind(base) + (f" in {bounds}" if bounds and bounds[0] in "([" else f" {bounds}" if bounds else "")
    return text + (" or none" if optional or (spec is not None and spec.may_be_empty and inner is not None)
                   else "")


def _kind(typ, plural: bool = False) -> str:
    if typ is bool:
        return "true or false"
    if typ is int:
        return "whole numbers" if plural else "a whole number"
    if typ is float:
        return "numbers" if plural else "a number"
    if typing.get_origin(typ) is typing.Literal:
        return " | ".join(map(str, typing.get_args(typ)))
    return "words" if plural else "a word"


def _whole(value) -> int | None:
    """``value`` as an int when it is a whole number (3000, 3000.0, 1e9), else None."""
    if isinstance(value, bool):
        return None
    if isinstance(value, numbers.Integral):
        return int(value)
    if isinstance(value, numbers.Real) and math.isfinite(value) and float(value).is_integer():
        return int(value)
    return None


def check_value(name: str, value, typ, spec: Spec | None):
    """``value`` checked against the field's type and range (ints stay ints, numbers
    become floats, lists tuples); InvalidParameter naming the field and what it accepts."""
    base, optional = split_optional(typ)
    if value is None:
        if optional:
            return None
        raise InvalidParameter(name, value, valid_text(typ, spec))
    inner = item_type(base)
    if inner is not None:
        if isinstance(value, (str, bytes)) or not isinstance(value, (tuple, list)):
            raise InvalidParameter(name, value, valid_text(typ, spec))
        if len(value) == 0:
            if spec is not None and spec.may_be_empty:
                return ()
            raise InvalidParameter(name, "", valid_text(typ, spec), "the list is empty")
        return tuple(_check_one(name, v, inner, spec, typ) for v in value)
    return _check_one(name, value, base, spec, typ)


def _check_one(name, value, base, spec, typ):
    if base is bool:
        if isinstance(value, bool):
            return value
        raise InvalidParameter(name, value, "true or false")
    if typing.get_origin(base) is typing.Literal:
        if value not in typing.get_args(base):
            raise InvalidParameter(name, value, " | ".join(map(str, typing.get_args(base))))
        return value
    if base is int:
        whole = _whole(value)
        if whole is None or (spec is not None and not spec.contains(whole)):
            raise InvalidParameter(name, value, valid_text(typ, spec))
        return whole
    if base is float:
        if isinstance(value, bool) or not isinstance(value, numbers.Real) or not math.isfinite(value):
            raise InvalidParameter(name, value, valid_text(typ, spec))
        x = float(value)
        if spec is not None and not spec.contains(x):
            raise InvalidParameter(name, value, valid_text(typ, spec))
        return x
    if base is str and not isinstance(value, str):
        raise InvalidParameter(name, value, "a word")
    return value


def check_fields(record) -> None:
    """Check every declared field of ``record`` (call first in ``__post_init__``); a
    value of another type that means the same (3000.0 for an int, a list for a tuple)
    is stored as the declared type."""
    cls = type(record)
    for f in dataclasses.fields(record):
        spec = spec_of(f)
        if spec is None:
            continue
        value = getattr(record, f.name)
        checked = check_value(f.name, value, field_type(cls, f.name), spec)
        if checked is not value:
            object.__setattr__(record, f.name, checked)


def undeclared_fields(cls) -> list[str]:
    """Fields of record class ``cls`` (and its nested records) without a ``param``
    declaration (a test keeps this empty for every study's case)."""
    out = []
    for f in dataclasses.fields(cls):
        typ = field_type(cls, f.name)
        if dataclasses.is_dataclass(typ):
            out += [f"{f.name}.{k}" for k in undeclared_fields(typ)]
        elif spec_of(f) is None:
            out.append(f.name)
    return out


#: what numpy's generators accept as a seed (SeedSequence takes any non-negative integer;
#: 32 bits keep it short enough to type and to put in a folder name)
MAX_SEED = 2**32 - 1


def seed_param(default: int = 1, meaning: str = "random seed: the same seed gives the same bits "
                                                "(README, same seed, same bits)"):
    """The ``seed`` field of a case that draws random numbers."""
    return param(default, lo=0, hi=MAX_SEED, meaning=meaning)
