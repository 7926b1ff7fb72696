"""The one error type for inputs that have no answer.

The CLI turns it into a single line on stderr and exit code 2; the API raises it
(a ``ValueError`` subclass) instead of returning NaN.
"""

from __future__ import annotations


class InvalidParameter(ValueError):
    """A parameter outside the range where the method has a real solution.

    ``str(err)`` is one line: ``<name> = <value> is outside the valid range <range>``,
    or ``<name> = <value> is not valid; expected <what>`` when ``valid`` names a kind of
    value ("a whole number in [1, 500]", "true or false") rather than a range.
    """

    def __init__(self, name: str, value, valid: str, why: str = ""):
        self.name = name
        self.value = value
        self.valid = valid
        self.why = why
        shown = f"{value:g}" if isinstance(value, float) else repr(value) if isinstance(value, str) else str(value)
        if valid.startswith(("a ", "an ", "true or false")):
            msg = f"{name} = {shown} is not valid; expected {valid}"
        elif " | " in valid and not valid.startswith(("(", "[", "<", ">")):
            msg = f"{name} = {shown} is not valid; expected one of {valid}"
        else:
            msg = f"{name} = {shown} is outside the valid range {valid}"
        if why:
            msg += f" ({why})"
        super().__init__(msg)


class NotApplicable(InvalidParameter):
    """The method exists but was derived for other conditions (e.g. a vertical back or
    level backfill). A comparison table shows it as "n/a" instead of stopping."""
