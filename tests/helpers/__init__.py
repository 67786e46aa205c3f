"""Helpers shared by the tests, imported as ``from helpers.<module> import ...``.

``tests/`` is on ``sys.path`` through ``pythonpath`` in ``[tool.pytest.ini_options]``.

- :mod:`helpers.ft_data`: F-T logs built from known point loads, and a feet file.
- :mod:`helpers.simfit_data`: recorded experiments for the simulator-fit tests.
- :mod:`helpers.gl`: skip a test where no offscreen OpenGL context can be created (videos).
"""
