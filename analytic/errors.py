"""The one error type for inputs that have no answer.

The CLI turns it into a single line on stderr and exit code 2; the API raises it
(a ``ValueError`` subclass) instead of returning NaN.
"""

from __future__ import annotations


class InvalidParameter(ValueError):
    """A parameter outside the range where the method has a real solution.

    ``str(err)`` is one line: ``<name> = <value> is outside the valid range <range>``.
    """

    def __init__(self, name: str, value, valid: str, why: str = ""):
        self.name = name
        self.value = value
        self.valid = valid
        self.why = why
        shown = f"{value:g}" if isinstance(value, float) else repr(value) if isinstance(value, str) else str(value)
        msg = f"{name} = {shown} is outside the valid range {valid}"
        if why:
            msg += f" ({why})"
        super().__init__(msg)


class NotApplicable(InvalidParameter):
    """The method exists but was derived for other conditions (e.g. a vertical back or
    level backfill). A comparison table shows it as "n/a" instead of stopping."""
