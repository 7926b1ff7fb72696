"""Case configuration: frozen dataclasses, overridden by a TOML file and ``--set key=value``.

A case is a (possibly nested) frozen dataclass. Overrides are applied with
``dataclasses.replace`` so the result is a new, fully resolved case that is written
into the run folder. Unknown keys and values of the wrong type raise
``InvalidParameter`` naming the key and what it accepts.
"""

from __future__ import annotations

import dataclasses
import tomllib
from pathlib import Path

from analytic.errors import InvalidParameter
from analytic.schema import Spec, check_value, field_type, item_type, spec_of, split_optional, valid_text


#: names used before the study layer's vocabulary (docs/architecture.md, glossary): a
#: config file, --set key, cached specimen or older report that uses one still reads
RENAMED_KEYS = {
    "disp_over_H": "wall_disp_over_H", "dis_over_H": "wall_disp_over_H",
    "dis_over_H_max": "wall_disp_over_H_max", "dis_over_H_active": "wall_disp_over_H_active",
    "dis_over_H_end": "wall_disp_over_H_end", "dis_over_H_steady": "wall_disp_over_H_steady",
    "dis_over_H_steady_95": "wall_disp_over_H_steady_95", "disp_over_H_steady": "wall_disp_over_H_steady",
    "centroid": "resultant_height_over_H", "centroid_at_rest": "resultant_height_over_H_at_rest",
    "centroid_active": "resultant_height_over_H_active", "normal_kN": "thrust_kN",
    "wall_load_kN": "thrust_at_rest_kN", "at_rest_wall_load_kN": "thrust_at_rest_kN_per_0.5m",
    "at_rest_load_kN_per_0.5m": "thrust_at_rest_kN_per_0.5m", "z_over_H": "depth_over_H",
}


def current_name(key: str) -> str:
    """``key`` (dotted or bare) with an old field name replaced by today's."""
    *head, last = key.split(".")
    return ".".join([*head, RENAMED_KEYS.get(last, last)])


def with_current_names(obj):
    """A JSON-like record with every old key renamed (older reports and caches)."""
    if isinstance(obj, dict):
        return {RENAMED_KEYS.get(k, k): with_current_names(v) for k, v in obj.items()}
    if isinstance(obj, list):
        return [with_current_names(v) for v in obj]
    return obj


def _field_specs(cls) -> dict[str, Spec | None]:
    return {f.name: spec_of(f) for f in dataclasses.fields(cls)}


def _coerce(key: str, raw, typ, spec: Spec | None = None):
    """A TOML value or the text of a flag or ``--set`` as the field's type, checked
    against its declaration (analytic/schema.py); errors name ``key`` and the value as typed."""
    base, optional = split_optional(typ)
    if optional and (raw is None or isinstance(raw, str) and raw.strip().lower() in ("none", "null", "")):
        return None
    inner = item_type(base)
    try:
        if inner is not None:
            items = _list_items(key, raw, typ, spec)
            value = tuple(_parsed(key, item, inner, typ, spec) for item in items)
        else:
            value = _parsed(key, raw, base, typ, spec)
        return check_value(key, value, typ, spec)
    except InvalidParameter as err:
        if err.name == key and isinstance(raw, str) and err.value != raw:
            raise InvalidParameter(key, raw, err.valid, err.why) from None    # the value as typed
        raise


def _list_items(key: str, raw, typ, spec) -> list:
    """The items of a list value: 'a,b' (or '(a, b)') from text, a TOML array as it is,
    a single TOML value as a list of one; an empty item ('36,,28') is refused."""
    if isinstance(raw, str):
        text = raw.strip()
        if text[:1] in "([" and text[-1:] in ")]":
            text = text[1:-1]
        if spec is not None and spec.may_be_empty and text.strip().lower() in ("", "none"):
            return []
        items = [p.strip() for p in text.split(",")]
        if not text.strip() or any(not p for p in items):
            raise InvalidParameter(key, raw, valid_text(typ, spec), "an empty item")
        return items
    if isinstance(raw, (list, tuple)):
        return list(raw)
    return [raw]


def _parsed(key: str, raw, typ, whole_typ, spec):
    """One value from text ('3000', '1e9', 'true', 'RT'); a TOML value stays as it is
    (``check_value`` then checks it)."""
    if not isinstance(raw, str):
        return raw
    text = raw.strip()
    if typ is bool:
        low = text.lower()
        if low in ("1", "true", "yes", "on"):
            return True
        if low in ("0", "false", "no", "off"):
            return False
        raise InvalidParameter(key, raw, "true or false")
    if typ in (int, float):
        try:
            return int(text)
        except ValueError:
            pass
        try:
            return float(text)
        except ValueError:
            raise InvalidParameter(key, raw, valid_text(whole_typ, spec), "not a number") from None
    return text


def flat_keys(case, prefix: str = "") -> list[str]:
    """All settable keys of a (nested) case, dotted for nested dataclasses."""
    keys = []
    for f in dataclasses.fields(case):
        v = getattr(case, f.name)
        if dataclasses.is_dataclass(v):
            keys += flat_keys(v, prefix + f.name + ".")
        else:
            keys.append(prefix + f.name)
    return keys


def _resolve(case, dotted: str, raw=None):
    """Find the (sub)case and field for a key; bare names also match nested fields."""
    parts = dotted.split(".")
    node = case
    for p in parts[:-1]:
        if not hasattr(node, p) or not dataclasses.is_dataclass(getattr(node, p)):
            return None
        node = getattr(node, p)
    name = parts[-1]
    if any(f.name == name for f in dataclasses.fields(node)) and not dataclasses.is_dataclass(getattr(node, name)):
        return parts[:-1], name
    if len(parts) == 1:  # unique bare name inside a nested record
        hits = [k for k in flat_keys(case) if k.split(".")[-1] == name]
        if len(hits) == 1:
            return hits[0].split(".")[:-1], name
        if len(hits) > 1:
            raise InvalidParameter(dotted, raw, " or ".join(hits), "the name is in two records: give its record")
    return None


def set_value(case, key: str, raw):
    """Return a copy of ``case`` with ``key`` set to ``raw`` (coerced to the field type)."""
    return apply_overrides(case, [(key, raw)])


def apply_overrides(case, items) -> object:
    """``case`` with every (key, raw value[, name shown in errors]) of ``items`` applied
    at once, later items
    winning: each record is rebuilt once with all its changes, so a check that spans
    fields (d_min <= d_max, H <= box height, enough particles for the grains) sees the
    final values whatever the order of the keys in a file or on the command line."""
    changes: dict[tuple, dict] = {}
    for key, raw, *shown in items:
        key = current_name(key)
        hit = _resolve(case, key, raw)
        if hit is None:
            raise InvalidParameter(key, raw, "a key of this case", "unknown key; `wallsim keys <study>` lists them")
        path, name = hit
        node = case
        for part in path:
            node = getattr(node, part)
        label = shown[0] if shown else key          # a flag's error names the flag
        value = _coerce(label, raw, field_type(type(node), name), _field_specs(type(node))[name])
        changes.setdefault(tuple(path), {})[name] = (label, value)
    return _rebuilt(case, (), changes)


def _rebuilt(node, path: tuple, changes: dict):
    """``node`` with its nested records rebuilt first, then its own changed fields; a
    failing check is reported under the key the user typed for that field."""
    kw = {}
    for f in dataclasses.fields(node):
        value = getattr(node, f.name)
        if dataclasses.is_dataclass(value):
            sub = _rebuilt(value, path + (f.name,), changes)
            if sub is not value:
                kw[f.name] = sub
    own = changes.get(path, {})
    kw |= {name: value for name, (_, value) in own.items()}
    if not kw:
        return node
    try:
        return dataclasses.replace(node, **kw)
    except InvalidParameter as err:
        if err.name in own and own[err.name][0] != err.name:
            raise InvalidParameter(own[err.name][0], err.value, err.valid, err.why) from None
        raise


def _set_items(sets: list[str] | None) -> list[tuple[str, str]]:
    items = []
    for item in sets or []:
        if "=" not in item:
            raise InvalidParameter("--set", item, "key=value")
        key, raw = item.split("=", 1)
        items.append((key.strip(), raw.strip()))
    return items


def case_value(case, key: str):
    """The value of ``key`` (dotted or a unique bare name, as ``--set`` takes it) in ``case``;
    ``InvalidParameter`` for a key the case does not have."""
    key = current_name(key)
    hit = _resolve(case, key)
    if hit is None:
        raise InvalidParameter(key, None, "a key of this case", "unknown key; `wallsim keys <study>` lists them")
    node = case
    for part in hit[0]:
        node = getattr(node, part)
    return getattr(node, hit[1])


def apply_sets(case, sets: list[str] | None):
    """Apply ``--set key=value`` strings (all at once, the last of a key winning)."""
    return apply_overrides(case, _set_items(sets))


def read_toml(path: str | Path) -> dict:
    """A --config file as a dict, or one line naming the file and what is wrong."""
    try:
        return tomllib.loads(Path(path).read_text())
    except (FileNotFoundError, IsADirectoryError, NotADirectoryError):
        raise InvalidParameter("--config", str(path), "an existing TOML file") from None
    except (PermissionError, UnicodeDecodeError) as err:
        raise InvalidParameter("--config", str(path), "a readable TOML text file", type(err).__name__) from None
    except tomllib.TOMLDecodeError as err:
        raise InvalidParameter("--config", str(path), "valid TOML", str(err).splitlines()[0]) from None


def toml_items(data: dict, prefix: str = "") -> list[tuple[str, object]]:
    """(dotted key, value) of every leaf of a TOML table (tables are nested records)."""
    out = []
    for k, v in data.items():
        out += toml_items(v, prefix + k + ".") if isinstance(v, dict) else [(prefix + k, v)]
    return out


def revalidated(case):
    """The case rebuilt from the innermost record out, so every record's checks run on
    the values it ends up with (``--set`` of one field checks that record only)."""
    changes = {f.name: revalidated(getattr(case, f.name)) for f in dataclasses.fields(case)
               if dataclasses.is_dataclass(getattr(case, f.name))}
    return dataclasses.replace(case, **changes)


def resolve_case(case, *, config: str | Path | None = None, flags: dict | None = None,
                 sets: list[str] | None = None, flag_names: dict | None = None):
    """The case a command runs, one precedence for every study (lowest first): the
    defaults in ``case`` < the ``config`` TOML file < ``flags`` (dotted key -> value, only
    the flags the user typed; ``flag_names``: key -> the flag an error names) < ``sets``
    (``--set key=value``)."""
    items = toml_items(read_toml(config)) if config else []
    names = flag_names or {}
    items += [(k, v, names[k]) if k in names else (k, v) for k, v in (flags or {}).items()]
    items += _set_items(sets)
    return revalidated(apply_overrides(case, items))


@dataclasses.dataclass(frozen=True)
class KeyInfo:
    """One settable key as ``wallsim keys`` prints it (from the field's declaration)."""

    key: str
    default: object
    unit: str
    valid: str
    meaning: str


def describe_keys(case, prefix: str = "") -> list[KeyInfo]:
    """Every settable key of a case, dotted for nested records, with its default, unit,
    what it accepts and its meaning (``analytic.schema.param``)."""
    rows = []
    cls = type(case)
    for f in dataclasses.fields(case):
        value = getattr(case, f.name)
        if dataclasses.is_dataclass(value):
            rows += describe_keys(value, prefix + f.name + ".")
            continue
        spec = spec_of(f)
        typ = field_type(cls, f.name)
        rows.append(KeyInfo(prefix + f.name, value, spec.unit if spec else "?", valid_text(typ, spec),
                            spec.meaning if spec else ""))
    return rows


def setting_sources(config: str | Path | None, flags: dict | None, sets: list[str] | None,
                    flag_names: dict | None = None) -> dict[str, str]:
    """Where each non-default setting came from, in precedence order (a later source
    overwrites an earlier one): ``{"seed": "--set", "specimen.particles": "flag --particles"}``."""
    out = {}
    if config:
        out |= {current_name(k): f"--config {config}" for k, _ in toml_items(read_toml(config))}
    out |= {k: f"flag {(flag_names or {}).get(k, '')}".rstrip() for k in (flags or {})}
    out |= {current_name(item.split("=", 1)[0].strip()): "--set" for item in sets or [] if "=" in item}
    return out


def sources_comment(sources: dict[str, str]) -> str:
    """TOML comment lines for config.toml: where the settings came from (comments:
    --config ignores them)."""
    lines = ["", "# where the settings came from (the others are the case's defaults):"]
    lines += [f"#   {k}: {v}" for k, v in sorted(sources.items())] or ["#   all defaults"]
    return "\n".join(lines) + "\n"
