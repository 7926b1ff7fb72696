"""What a study is: a named set of commands (compare, validate, calibrate), each a case
record with defaults, the flags that set its keys, and a function that runs it.

``cli.py`` builds ``wallsim <verb> <study>`` from these records, so a new study adds
no code there; a notebook uses the same records through ``studies.get(name)``.

One rule for where a setting comes from, for every study (lowest first):
the case's defaults < ``--config FILE.toml`` < flags given on the command line <
``--set KEY=VALUE``. A flag that maps to a case key (``Option.key``) only counts when
the user typed it, so a config file is never overridden by a flag's default.
"""

from __future__ import annotations

import json
from dataclasses import dataclass, field
from pathlib import Path
from types import SimpleNamespace
from typing import Any, Callable

from analytic.errors import InvalidParameter
from analytic.schema import as_before

from .config import resolve_case, set_value
from .registry import NAMES


@dataclass(frozen=True)
class Option:
    """One command-line flag.

    flag:     as typed, e.g. ``--particles``; a name without dashes is a positional
              argument (optional: a case key, e.g. ``wall_file``)
    help:     one line with the unit and the default in brackets/parentheses
    key:      the dotted case key it sets; None for a run option (output, recording, ...)
    parse:    text -> value, raising ``InvalidParameter`` (or argparse's type error)
    to_case:  value -> the case field's value (a unit change, a named preset)
    default:  run options only: the value when the flag is absent (case keys default
              to the case)
    choices:  the allowed words, if any
    switch:   a flag without a value (store_true)
    optional: the value may be left out (``--rrd`` or ``--rrd FILE``: given alone the
              option holds ``True``)
    """

    flag: str
    help: str
    key: str | None = None
    parse: Callable[[str], Any] | None = None
    to_case: Callable[[Any], Any] | None = None
    default: Any = None
    choices: tuple[str, ...] | None = None
    switch: bool = False
    optional: bool = False
    metavar: str | None = None

    @property
    def dest(self) -> str:
        return self.flag.lstrip("-").replace("-", "_")


@dataclass(frozen=True)
class Command:
    """``wallsim <verb> <study>``: a case, its flags, and what runs it.

    default_case: the case with this command's defaults (a frozen dataclass)
    run:          (case, options) -> (result dict, one line for stderr or None); the
                  options namespace holds every run option plus ``out``, ``quiet``
    text:         result -> what a person reads (str or a rich renderable)
    seed_key:     the case key ``--seed`` sets (None: the case draws no random numbers)
    busy_note:    say on stderr when other jobs hold the cores (3D runs)
    figures:      result -> the figures the command judges against the paper, each a
                  ``studies.seeds.figure`` record (name, value, reference, window); a
                  command with figures and a seed takes ``--seeds`` (mean +- sd over
                  seeds, ``studies/seeds.py``)
    scale_note:   (case, result) -> one line for a run coarser than the paper's (what
                  it gave against the paper-scale validation), or None
    footprint:    case -> (the key that sets the size, its value, the memory the run
                  needs [bytes]): checked against this machine before anything runs
    """

    verb: str
    help: str
    description: str
    default_case: Callable[[], Any]
    run: Callable[[Any, SimpleNamespace], tuple[dict, str | None]]
    text: Callable[[dict], Any]
    options: tuple[Option, ...] = ()
    seed_key: str | None = "seed"
    seed_default: int = 1
    busy_note: bool = False
    figures: Callable[[dict], list[dict]] | None = None
    scale_note: Callable[[Any, dict], str | None] | None = None
    footprint: Callable[[Any], tuple[str, Any, float]] | None = None

    def resolve(self, *, config: str | None = None, flags: dict[str, Any] | None = None,
                sets: list[str] | None = None, resume: str | None = None, study: str | None = None,
                flag_names: dict[str, str] | None = None):
        """The case to run: defaults < config file < flags (key -> value) < ``--set``;
        or, with ``resume`` (a run folder of ``study``), exactly the case that run
        started with."""
        if resume is not None:
            if config or flags or sets:
                raise InvalidParameter("--resume", resume, "a run folder alone (no --config, --set or case flags)",
                                       "a resumed run keeps the settings it started with")
            config = _resume_config(resume, study)
        # a config.toml written before a field was added lacks it: it meant what runs had then
        base = as_before(self.default_case()) if resume is not None else self.default_case()
        return resolve_case(base, config=config, flags=flags or {}, sets=sets or [],
                            flag_names=flag_names)

    def envelope(self, case, sources: dict[str, str] | None = None, opts: SimpleNamespace | None = None):
        """The run envelope of this command on ``case`` with run options ``opts``
        (studies/runner.py)."""
        from .runner import command_envelope
        note = (lambda result: self.scale_note(case, result)) if self.scale_note else None
        return command_envelope(sources, note, vtk=bool(getattr(opts, "vtk", False)))

    def check_fits(self, case) -> None:
        """Refuse, in one line naming the size key and the estimate, a case whose memory
        estimate exceeds what this machine has (before anything is allocated)."""
        if self.footprint is None:
            return
        from .runner import machine_memory
        key, value, need = self.footprint(case)
        have = machine_memory()
        if have is not None and need > have:
            raise InvalidParameter(key, value, "a size this machine can hold",
                                   f"needs ~{need / 1e9:.3g} GB; this machine has {have / 1e9:.3g} GB")

    def run_options(self, **given) -> SimpleNamespace:
        """Every run option at its default, with ``given`` on top (unknown names refused)."""
        opts = {o.dest: o.default for o in self.options if o.key is None}
        opts |= {"out": "runs", "quiet": True}
        unknown = sorted(set(given) - set(opts))
        if unknown:
            raise InvalidParameter(unknown[0], given[unknown[0]], ", ".join(sorted(opts)), "not an option of "
                                   f"{self.verb}")
        return SimpleNamespace(**(opts | given))


def _resume_config(resume: str, study: str | None) -> str:
    """The config.toml of the run folder ``resume``, which must be a run of ``study``."""
    folder = Path(resume)
    config = folder / "config.toml"
    if not resume or not config.is_file():
        raise InvalidParameter("--resume", resume, "a run folder with a config.toml")
    other = folder.resolve().parent.name
    if study is not None and other != study and other in NAMES:
        raise InvalidParameter("--resume", resume, f"a run folder of {study} (runs/{study}/...)",
                               f"it is a run of {other}")
    return str(config)


@dataclass(frozen=True)
class Study:
    """A paper case (or a calibration test) with its commands and its reference data.

    reference_file: the paper's numbers with their source and tolerances (package data)
    """

    name: str
    title: str
    commands: tuple[Command, ...]
    reference_file: Path | None = None
    extra: dict = field(default_factory=dict)

    def command(self, verb: str | None = None) -> Command:
        """The command for ``verb`` (default: the first one, the study's main run)."""
        if verb is None:
            return self.commands[0]
        for c in self.commands:
            if c.verb == verb:
                return c
        raise InvalidParameter("verb", verb, " | ".join(c.verb for c in self.commands))

    @property
    def Case(self) -> type:
        """The case record of the main command."""
        return type(self.command().default_case())

    def case(self, verb: str | None = None, **overrides):
        """The main (or ``verb``'s) case with ``overrides`` by key, e.g.
        ``case(mode="RT", particles=3000)``: bare names resolve as ``--set`` does."""
        case = self.command(verb).default_case()
        for key, value in overrides.items():
            case = set_value(case, key, value)
        return case

    def run(self, case=None, verb: str | None = None, **options) -> dict:
        """Run the main command (or ``verb``) on ``case`` (default: the defaults) and
        return its result dict; ``options`` are the command's run options (``out``,
        ``quiet``, ``rrd``, ...). The run folder is written as by the CLI."""
        cmd = self.command(verb)
        if options.get("resume"):
            started = cmd.resolve(resume=str(options["resume"]), study=self.name)
            if case is not None and case != started:
                raise InvalidParameter("resume", str(options["resume"]), "the case that run started with",
                                       "a resumed run keeps its settings; pass case=None")
            case = started
        case = case if case is not None else cmd.default_case()
        cmd.check_fits(case)
        opts = cmd.run_options(**options)
        with cmd.envelope(case, opts=opts):
            result, _ = cmd.run(case, opts)
        return result

    def reference(self) -> dict:
        """The paper's numbers this study is checked against."""
        if self.reference_file is None:
            return {}
        return json.loads(Path(self.reference_file).read_text())
