"""Generators of the documentation site's pages (run by the mkdocs hook ``docs/_gen/hooks.py``
and by the tests): the case-file and body-file references, read from the validators."""
