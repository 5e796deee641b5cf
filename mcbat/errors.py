"""User-facing errors: one line that names the source, the field and the offending value.

Library code names Python parameters (``out``, ``samples``) or study keys (``ball.mass``)
in ``field``. Other parameters a message mentions are data too, in ``mentions``: the message
holds a ``{name}`` placeholder for each, written in call syntax by ``str(error)``
(``overwrite=True``, ``scheduler=ADDRESS``) and as its flag by the command line
(``mcbat.cli``: ``--overwrite``, ``--scheduler ADDRESS``).
"""

__all__ = ["EnvironmentFailure", "InputError", "Metavar", "call_syntax"]


class InputError(ValueError):
    """Bad user input. The CLI prints ``str(error)`` on one line and exits with code 2.

    Parameters
    ----------
    field : str
        Dotted path of the offending field, e.g. ``"ball.mass"`` or ``"case[3].mu"``.
    message : str
        What is wrong, including the offending value.
    source : str, optional
        File name (or ``"<stdin>"``) the input came from.
    mentions : dict, optional
        Other parameters the message refers to, each with the value it would be given
        (``{"overwrite": True}``, ``{"scheduler": Metavar("ADDRESS")}``); the message
        marks where each goes with ``{name}``. ``message`` is the text in Python's call
        syntax; ``render_message`` spells the mentions another way (as flags).

    Attributes
    ----------
    field, source, mentions
        As given.
    template : str
        The message as given, with its ``{name}`` placeholders.
    message : str
        The message with each mention in call syntax (``overwrite=True``).
    """

    def __init__(self, field: str | None, message: str, source: str | None = None, *,
                 mentions: dict[str, object] | None = None) -> None:
        self.field = field
        self.template = message
        self.mentions = dict(mentions or {})
        self.message = self.render_message(call_syntax)
        self.source = source
        super().__init__(self._render())

    def render_message(self, spell) -> str:
        """The message with each mention written by ``spell(name, value)``.

        Only the placeholders of the names in ``mentions`` are replaced, so braces in the
        rest of the message (a user's value, a dict) are left as they are.
        """
        text = self.template
        for name, value in self.mentions.items():
            text = text.replace("{" + name + "}", spell(name, value))
        return text

    def _render(self):
        where = f"{self.source}: " if self.source else ""
        field = f"{self.field}: " if self.field else ""
        return _one_line(f"{where}{field}{self.message}")

    def within(self, prefix: str | None = None,
               source: str | None = None) -> "InputError":
        """A copy located inside ``prefix`` (a parent field) and/or ``source`` (a file)."""
        field = self.field
        if prefix:
            field = f"{prefix}.{field}" if field else prefix
        return InputError(field, self.template, source or self.source,
                          mentions=self.mentions)


class Metavar(str):
    """A placeholder for a value in a message (``ADDRESS``, ``N``): written as it is, not
    quoted like a string value."""

    __slots__ = ()

    def __repr__(self):
        return str(self)


def call_syntax(name, value) -> str:
    """A parameter as a Python call would give it: ``overwrite=True``, ``engine='dask'``,
    ``scheduler=ADDRESS`` (a ``Metavar``)."""
    return f"{name}={value!r}"


class EnvironmentFailure(RuntimeError):
    """Something outside mcbat failed mid-run (the Dask scheduler went away). The CLI
    prints ``str(error)`` on one line and exits with code 4; complete chunk files are
    kept, so rerunning the same command once the environment is back resumes the run.
    """

    def __init__(self, message):
        super().__init__(_one_line(message))


def _one_line(text: str) -> str:
    """``text`` with every non-printable character (newlines, NUL, line separators)
    escaped: an error is one line, whatever the user's keys and values contain."""
    if text.isprintable():
        return text
    return "".join(c if c.isprintable() else repr(c)[1:-1] for c in text)
