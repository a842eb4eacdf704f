"""setuptools' build, which also asks for mypy when the core is to be compiled by mypyc
(core_build.py says when: by default, wherever the machine can), so that `pip install .`
needs nothing else; an editable install is built as Python."""

import os

from core_build import compiling
from setuptools import build_meta
from setuptools.build_meta import *  # noqa: F403  (every hook as setuptools has it)

# mypy (the version tests/test_types.py checks the core with), and what the core imports,
# for their types.
COMPILING = ["mypy==2.4.1", "pygame-ce>=2.5.6", "numpy>=1.24"]


def get_requires_for_build_wheel(config_settings=None):
    if compiling():
        return COMPILING  # (setuptools' own way runs setup.py, which compiles with them)
    return build_meta.get_requires_for_build_wheel(config_settings)


def get_requires_for_build_editable(config_settings=None):
    compiling(editable=True)  # (INVADERS_COMPILE=1 refused, in words)
    return build_meta.get_requires_for_build_editable(config_settings)


def prepare_metadata_for_build_editable(metadata_directory, config_settings=None):
    _as_python()
    return build_meta.prepare_metadata_for_build_editable(metadata_directory, config_settings)


def build_editable(wheel_directory, config_settings=None, metadata_directory=None):
    _as_python()
    return build_meta.build_editable(wheel_directory, config_settings, metadata_directory)


def _as_python():
    """An editable build: setup.py, which runs in this process, told to leave the core
    Python."""
    compiling(editable=True)
    os.environ["INVADERS_COMPILE"] = "0"
