"""The bundled study files, shipped as the resource package ``mcbat.studies`` (read with
``importlib.resources``; format in ``README.md``). No code lives here."""
