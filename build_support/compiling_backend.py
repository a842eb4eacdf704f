"""setuptools' build, which also asks for mypy when the core is to be compiled by mypyc
(INVADERS_COMPILE=1, docs/compiled.md): then `pip install .` needs nothing else."""

import os

from setuptools import build_meta
from setuptools.build_meta import *  # noqa: F403  (every hook as setuptools has it)

# mypy (the version tests/test_types.py checks the core with), and what the core imports,
# for their types.
COMPILING = ["mypy==2.4.1", "pygame-ce>=2.5.6", "numpy>=1.24"]


def get_requires_for_build_wheel(config_settings=None):
    if os.environ.get("INVADERS_COMPILE") == "1":
        return COMPILING  # (setuptools' own way runs setup.py, which compiles with them)
    return build_meta.get_requires_for_build_wheel(config_settings)
