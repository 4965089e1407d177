"""Helpers of the test suite, not tests: ``tests/conftest.py`` puts ``tests/`` on ``sys.path``
so that test files import them as ``support.<module>``.

- ``paths``: the repository, ``tests/data`` and the shared models (with a skip marker);
- ``hostile``: a case that could crash or run away, in a child process with limits;
- ``startup``: a fresh interpreter running the command line (no limits);
- ``objfiles``: a Mesh written as a minimal OBJ file, and a small OBJ text;
- ``scripts``: the repository's ``scripts/`` (not installed), imported for their tests;
- ``reference_lines``, ``reference_raster``, ``svg_raster``: slow pure-NumPy references;
- ``render_corpus`` and ``fuzz_obj``: also scripts (``python tests/support/render_corpus.py``,
  ``python tests/support/fuzz_obj.py --help``).
"""
