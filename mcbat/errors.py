"""User-facing errors: one line that names the source, the field and the offending value."""


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
    """

    def __init__(self, field, message, source=None):
        self.field = field
        self.message = message
        self.source = source
        super().__init__(self._render())

    def _render(self):
        where = f"{self.source}: " if self.source else ""
        field = f"{self.field}: " if self.field else ""
        return f"{where}{field}{self.message}"

    def within(self, prefix=None, source=None):
        """A copy located inside ``prefix`` (a parent field) and/or ``source`` (a file)."""
        field = self.field
        if prefix:
            field = f"{prefix}.{field}" if field else prefix
        return InputError(field, self.message, source or self.source)
