"""Whether the install compiles the package's core with mypyc (docs/compiled.md), and the
build of it that falls back to Python.

INVADERS_COMPILE=1 compiles it, or the install fails saying why (CI's compiled run).
INVADERS_COMPILE=0 leaves it Python. Unset, the install compiles it where the machine can (a
C compiler on the PATH and Python's headers); where it cannot, or the compile fails all the
same, the package is installed as Python, which gives the same answers, more slowly. An
editable install is always Python: compiled modules would stand in front of the sources
being edited.
"""

from __future__ import annotations

import os
import shlex
import shutil
import sys
import sysconfig
from pathlib import Path

from setuptools.command.build_ext import build_ext
from setuptools.errors import BaseError, CCompilerError

SAID = {"1": "compile the core", "0": "leave it Python", "": "compile it where the machine can"}


def chosen() -> str:
    """INVADERS_COMPILE as given: "1", "0" or "" (unset); any other value refused in one
    line."""
    value = os.environ.get("INVADERS_COMPILE", "")
    if value not in SAID:
        raise SystemExit(f"INVADERS_COMPILE={value!r}: 1 ({SAID['1']}), 0 ({SAID['0']}) "
                         f"or unset ({SAID['']})")
    return value


def can_compile() -> bool:
    """A C compiler on the PATH (CC, else the one this Python was built with) and Python's
    headers: what building a C extension needs."""
    compiler = os.environ.get("CC") or sysconfig.get_config_var("CC")
    if not compiler or not shlex.split(compiler):
        return False
    headers = Path(sysconfig.get_path("include")) / "Python.h"
    return shutil.which(shlex.split(compiler)[0]) is not None and headers.is_file()


def compiling(editable: bool = False) -> bool:
    """Whether this build compiles the core (an editable one never: INVADERS_COMPILE=1
    with one is refused in one line)."""
    value = chosen()
    if editable:
        if value == "1":
            raise SystemExit("INVADERS_COMPILE=1: an editable install (-e) stays Python "
                             "(compiled modules would stand in front of the sources edited); "
                             "compile with `pip install .`")
        return False
    return value == "1" or (value == "" and can_compile())


def said_python(why: str) -> None:
    """One line on the build's output: the core is installed as Python, and why."""
    print(f"invaders: the core is installed as Python: {why}", file=sys.stderr)


class FallbackBuild(build_ext):
    """setuptools' build of the extensions; if it fails, none is left built (a module's
    extension without the library it calls would not import) and the package stays
    Python, said in one line. For a build that compiles only because the machine seemed
    able to (INVADERS_COMPILE unset)."""

    def run(self) -> None:
        try:
            super().run()
        except (CCompilerError, BaseError, OSError) as failure:
            for extension in self.extensions:
                Path(self.get_ext_fullpath(extension.name)).unlink(missing_ok=True)
            said_python(f"compiling it failed ({failure})")
