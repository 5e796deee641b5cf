"""The bundled reference tables, shipped as the resource package ``mcbat.data`` (read with
``importlib.resources``; provenance in ``README.md``). No code lives here."""
